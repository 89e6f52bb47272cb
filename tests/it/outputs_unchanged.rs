//! `footslam learn` writes byte for byte what it wrote before the FootSLAM speed work
//! (issue 37): every output file of three runs, against digests in `tests/golden/`.
//!
//! * the bundled office walk with every default (20,000 particles, seed 0), on 2 threads;
//! * the bundled tower walk (three floors, WiFi scans in the filter) with 1,500 particles,
//!   on 1 thread and on 2, which must agree with each other and with the digests;
//! * a simulated office walk with magnetometer readings (the field maps, MagSLAM), 1,500
//!   particles, on 2 threads.
//!
//! **What is compared.** Every file a run writes, by size and FNV-1a 64-bit digest, except
//! the lines of `summary.json` that measure the run rather than its answer (run times,
//! throughput, peak memory, the thread count), as `track`'s golden test compares them
//! ([`fnv1a`] and [`comparable`] are its).
//!
//! **How the digests were made.** With `FOOTSLAM_BLESS=1 cargo test --release --workspace
//! --test it learn_is_unchanged` on commit 44d822c (main before the arena maps of issue 37),
//! x86-64 Linux. Regenerate them only for a change meant to alter the answer, and say so in
//! the commit; a speed change must leave them alone. Since: the tower's heatmaps (2026-11-29:
//! cells nobody surveyed drawn paler by the interpolated map's prediction). A failure names the file that changed
//! and keeps the run's folder under `target/outputs_unchanged/` for a look.

use crate::cli_cases::footslam;
use crate::track_outputs_unchanged::{comparable, fnv1a};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `size digest` of every file of `dir`, by name.
fn digests(dir: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(dir).expect("output folder") {
        let path = entry.expect("entry").path();
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        let bytes = comparable(&name, std::fs::read(&path).expect("output file"));
        out.insert(name, format!("{} {:016x}", bytes.len(), fnv1a(&bytes)));
    }
    out
}

/// A fresh folder for run `name` under `target/outputs_unchanged/`.
fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target").join("outputs_unchanged").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// Runs `footslam ARGS` in `dir`.
fn run(dir: &Path, args: &[&str]) {
    footslam().current_dir(dir).args(args).assert().success();
}

/// Compares the digests of folder `out` with `tests/golden/<golden>.txt` (or writes them
/// there with `FOOTSLAM_BLESS` set), naming every file that differs.
fn check(out: &Path, golden: &str) {
    let got = digests(out);
    let file = root()
        .join("tests")
        .join("golden")
        .join(format!("{golden}.txt"));
    if std::env::var_os("FOOTSLAM_BLESS").is_some() {
        let text: String = got.iter().map(|(n, d)| format!("{n} {d}\n")).collect();
        std::fs::write(&file, text).expect("write golden");
        return;
    }
    let text = std::fs::read_to_string(&file)
        .unwrap_or_else(|e| panic!("{}: {e} (see this file's docs)", file.display()));
    let want: BTreeMap<String, String> = text
        .lines()
        .filter_map(|l| l.split_once(' '))
        .map(|(n, d)| (n.to_owned(), d.to_owned()))
        .collect();
    let mut wrong = Vec::new();
    for (name, digest) in &want {
        match got.get(name) {
            None => wrong.push(format!("{name}: no longer written")),
            Some(d) if d != digest => {
                wrong.push(format!("{name}: size and digest {d}, golden {digest}"))
            }
            Some(_) => {}
        }
    }
    for name in got.keys().filter(|n| !want.contains_key(*n)) {
        wrong.push(format!("{name}: written now, not in the golden list"));
    }
    assert!(
        wrong.is_empty(),
        "{golden}: outputs changed (run kept in {}):\n  {}",
        out.display(),
        wrong.join("\n  ")
    );
}

#[test]
fn the_default_learn_is_unchanged() {
    let dir = scratch("office");
    let out = dir.join("out");
    let out = out.to_str().expect("path");
    run(&root(), &["learn", "-q", "--threads", "2", "--out", out]);
    check(Path::new(out), "learn_office");
}

#[test]
fn the_tower_learn_is_unchanged_on_one_and_two_threads() {
    let dir = scratch("tower");
    for threads in ["1", "2"] {
        let out = dir.join(format!("threads-{threads}"));
        let out = out.to_str().expect("path");
        let args = [
            "learn",
            "-q",
            "--steps",
            "datasets/tower",
            "--particles",
            "1500",
            "--threads",
            threads,
            "--out",
            out,
        ];
        run(&root(), &args);
    }
    assert_eq!(
        digests(&dir.join("threads-1")),
        digests(&dir.join("threads-2")),
        "the tower walk learned on 1 and on 2 threads differs"
    );
    check(&dir.join("threads-2"), "learn_tower");
}

#[test]
fn the_magnetic_learn_is_unchanged() {
    let dir = scratch("magnetic");
    run(
        &dir,
        &["simulate", "--magnetometer", "--seed", "3", "--out", "sim"],
    );
    run(
        &dir,
        &[
            "learn",
            "-q",
            "--steps",
            "sim",
            "--particles",
            "1500",
            "--threads",
            "2",
            "--out",
            "out",
        ],
    );
    check(&dir.join("out"), "learn_magnetic");
}
