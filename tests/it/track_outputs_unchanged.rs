//! `footslam track` writes the same files as before on the bundled data: every output of a
//! few fixed-seed runs (the tower walk from an unknown start on one and on two threads, the
//! tower from a known start without the path tree, and the office walk, which never settles
//! and so is clustered at every step) is compared byte for byte with the digest committed in
//! `tests/golden/track_outputs.txt`.
//!
//! Speed work on the tracker (propagation, wall index, clustering, buffers, pictures) must
//! not change a single output byte; this test holds it. Only the lines of `summary.json`
//! that measure the run rather than the walk (run times, throughput, peak memory, thread
//! count) are left out of its digest.
//!
//! The golden file was made by running this test with `FOOTSLAM_BLESS=1` on the code before
//! the speed work (commit 753b6f1, x86-64 Linux). A failure names the case and the file that
//! changed: either restore the old behaviour, or — for an intended change of results — rerun
//! with `FOOTSLAM_BLESS=1` and say why in the commit.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

const GOLDEN: &str = "tests/golden/track_outputs.txt";

/// Lines of `summary.json` that measure the run, not the walk.
const VOLATILE: [&str; 5] = [
    "\"runtime_s\":",
    "\"filter_runtime_s\":",
    "\"particle_steps_per_s\":",
    "\"peak_memory_bytes\":",
    "\"threads\":",
];

/// The runs: a case name (the golden's key) and `track`'s arguments, from the repository
/// root.
const CASES: [(&str, &[&str]); 4] = [
    ("tower", &["--seed", "0", "--threads", "1"]),
    ("tower", &["--seed", "0", "--threads", "2"]),
    (
        "tower-start-online",
        &[
            "--seed",
            "3",
            "--start",
            "38.24,5.28,-1.40,2",
            "--online",
            "--threads",
            "2",
        ],
    ),
    (
        "office",
        &[
            "--seed",
            "0",
            "--plan",
            "datasets/office/floor.geojson",
            "--steps",
            "datasets/office/steps.csv",
            "--threads",
            "2",
        ],
    ),
];

/// FNV-1a, 64 bits: a digest that needs no dependency.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The bytes of an output as compared: `summary.json` without its volatile lines.
pub fn comparable(name: &str, bytes: Vec<u8>) -> Vec<u8> {
    if name != "summary.json" {
        return bytes;
    }
    let text = String::from_utf8(bytes).expect("summary.json is UTF-8");
    text.lines()
        .filter(|l| !VOLATILE.iter().any(|v| l.trim_start().starts_with(v)))
        .flat_map(|l| l.bytes().chain(std::iter::once(b'\n')))
        .collect()
}

/// `case file length digest` lines of every file `track ARGS` writes, sorted by name.
fn digests(case: &str, args: &[&str], out: &Path) -> Vec<String> {
    Command::cargo_bin("footslam")
        .expect("binary")
        .current_dir(root())
        .arg("track")
        .arg("-q")
        .args(args)
        .arg("--out")
        .arg(out)
        .assert()
        .success();
    let mut names: Vec<String> = std::fs::read_dir(out)
        .expect("output folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(out.join(&name)).expect("output");
            let bytes = comparable(&name, bytes);
            format!("{case} {name} {} {:016x}", bytes.len(), fnv1a(&bytes))
        })
        .collect()
}

#[test]
fn track_outputs_are_byte_identical_to_the_golden_digests() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut lines: Vec<String> = Vec::new();
    for (k, (case, args)) in CASES.iter().enumerate() {
        let got = digests(case, args, &dir.path().join(format!("{k}")));
        // A second run of a case (another thread count) must agree with the first.
        if let Some(first) = CASES.iter().position(|(c, _)| c == case)
            && first < k
        {
            let earlier: Vec<&String> = lines
                .iter()
                .filter(|l| l.starts_with(&format!("{case} ")))
                .collect();
            assert_eq!(
                earlier,
                got.iter().collect::<Vec<_>>(),
                "{case}: `track {}` writes other files than `track {}`",
                args.join(" "),
                CASES[first].1.join(" ")
            );
            continue;
        }
        lines.extend(got);
    }
    let golden_path = root().join(GOLDEN);
    if std::env::var_os("FOOTSLAM_BLESS").is_some() {
        std::fs::write(&golden_path, lines.join("\n") + "\n").expect("write golden");
        return;
    }
    let golden = std::fs::read_to_string(&golden_path).expect("tests/golden/track_outputs.txt");
    let golden: Vec<&str> = golden.lines().collect();
    let key = |l: &str| l.split(' ').take(2).collect::<Vec<_>>().join(" ");
    let mut wrong = Vec::new();
    for g in &golden {
        match lines.iter().find(|l| key(l) == key(g)) {
            None => wrong.push(format!("{} is no longer written", key(g))),
            Some(l) if l != g => wrong.push(format!("{} changed ({l}, was {g})", key(g))),
            Some(_) => {}
        }
    }
    for l in &lines {
        if !golden.iter().any(|g| key(g) == key(l)) {
            wrong.push(format!("{} is new (not in {GOLDEN})", key(l)));
        }
    }
    assert!(
        wrong.is_empty(),
        "track outputs differ:\n{}",
        wrong.join("\n")
    );
}
