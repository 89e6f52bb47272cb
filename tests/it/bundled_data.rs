//! The bundled sample data regenerates as `datasets/README.md` says: each documented
//! `footslam simulate` command, run into a scratch folder, writes every committed file of
//! `datasets/office/` and `datasets/tower/` (pictures included) byte for byte.
//!
//! Byte for byte, not to a tolerance: the simulator draws from a seeded portable generator
//! and prints to fixed precision, and the pictures are rasterised and encoded without
//! threads or clocks, so two runs agree exactly (checked on x86-64 Linux). A platform whose
//! maths library rounds a sine differently in the last bit could in principle flip a printed
//! digit; the failure message then names the file, and the fix is to compare that file
//! numerically rather than to loosen the others.
//!
//! A failure here means the simulator or a renderer changed what it writes: either restore
//! the old behaviour, or regenerate the bundled data with the documented commands (and check
//! the tests and figures that read it), or change the documented command so that it
//! reproduces the data again.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `footslam ARGS --out OUT` from the repository root (as the docs do) and compares
/// every file of the committed `dataset` folder but its README with the output's.
fn regenerates(dataset: &str, args: &[&str], documented_in: &[&str]) {
    let command = format!("footslam {}", args.join(" "));
    for doc in documented_in {
        let text = std::fs::read_to_string(root().join(doc)).expect("doc");
        assert!(
            text.contains(&command),
            "{doc} no longer documents `{command} --out ...`: keep the test and the doc in step"
        );
    }

    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join(dataset);
    Command::cargo_bin("footslam")
        .expect("binary")
        .current_dir(root())
        .args(args)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();

    let committed = root().join("datasets").join(dataset);
    let mut compared = 0;
    for entry in std::fs::read_dir(&committed).expect("dataset folder") {
        let path = entry.expect("entry").path();
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        if name == "README.md" {
            continue;
        }
        let written = out.join(&name);
        assert!(
            written.is_file(),
            "{dataset}/{name} is committed but the command no longer writes it"
        );
        assert!(
            read(&path) == read(&written),
            "{dataset}/{name} differs from what `{command}` writes now"
        );
        compared += 1;
    }
    for entry in std::fs::read_dir(&out).expect("output folder") {
        let name = entry.expect("entry").file_name();
        assert!(
            committed.join(&name).is_file(),
            "the command writes {name:?}, which datasets/{dataset} does not hold"
        );
    }
    assert!(compared >= 6, "{dataset}: only {compared} files compared");
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_office_walk_regenerates_bit_identical() {
    regenerates(
        "office",
        &["simulate", "--seed", "1", "--origin", "48.1491,11.5681"],
        &["datasets/README.md"],
    );
}

#[test]
fn the_tower_walk_regenerates_bit_identical() {
    regenerates(
        "tower",
        &[
            "simulate",
            "--building",
            "tower",
            "--seed",
            "1",
            "--origin",
            "52.2100,0.0910",
            "--config",
            "datasets/configs/tower-sim.toml",
        ],
        &["datasets/README.md", "datasets/tower/README.md"],
    );
}

/// The copies of the bundled pictures that the README shows are the bundled pictures.
#[test]
fn the_readme_pictures_are_the_bundled_ones() {
    for (doc, bundled) in [
        ("docs/office-truth.png", "datasets/office/truth.png"),
        ("docs/tower-truth.png", "datasets/tower/truth.png"),
    ] {
        assert!(
            read(&root().join(doc)) == read(&root().join(bundled)),
            "{doc} differs from {bundled}: copy it again"
        );
    }
}
