//! `footslam track --walks` and `fingerprint --walks`: a batch of walks on one plan and
//! radio map, prepared once, gives each walk what the command alone gives it.

use super::track::simulate_tower;
use assert_cmd::Command;
use predicates::prelude::*;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The simulated walk's true start, `X,Y,HEADING,LEVEL`.
fn true_start(walk: &Path) -> String {
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&walk.join("summary.json"))).expect("summary.json");
    let s = &summary["start"];
    format!("{},{},{},{}", s["x"], s["y"], s["heading"], s["level"])
}

/// Three simulated tower walks in `dir`, the first surveyed into a radio map, and a manifest
/// `walks.csv` of the other two (the first named `second` and started where it was, the
/// other named by its row and started unknown): the plan, the radio map and the two walks'
/// folders.
fn batch_inputs(dir: &Path) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let simulate = |seed| simulate_tower(dir, seed, "2");
    let (a, b, c) = (simulate("21"), simulate("22"), simulate("23"));
    let plan = a.join("floor.geojson");
    let survey = dir.join("survey");
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(&plan)
        .arg("--steps")
        .arg(a.join("steps.csv"))
        .arg("--wifi")
        .arg(a.join("wifi.csv"))
        .arg("--out")
        .arg(&survey)
        .assert()
        .success();
    // Paths relative to the manifest.
    std::fs::write(
        dir.join("walks.csv"),
        format!(
            "steps,wifi,start,name\n\
             tower-22/steps.csv,tower-22/wifi.csv,\"{}\",second\n\
             tower-23/steps.csv,tower-23/wifi.csv,,\n",
            true_start(&b)
        ),
    )
    .expect("manifest");
    (plan, survey.join("radiomap.geojson"), b, c)
}

/// `footslam track --walks manifest` on `plan` with `radiomap`, seed 3, into `out`.
fn track_batch(
    plan: &Path,
    radiomap: &Path,
    manifest: &Path,
    out: &Path,
) -> assert_cmd::assert::Assert {
    footslam()
        .arg("track")
        .arg("--plan")
        .arg(plan)
        .arg("--radiomap")
        .arg(radiomap)
        .arg("--walks")
        .arg(manifest)
        .args(["--seed", "3", "--out"])
        .arg(out)
        .assert()
}

#[test]
fn a_batch_tracks_each_walk_as_track_alone_does() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (plan, radiomap, b, c) = batch_inputs(dir.path());
    let out = dir.path().join("batch");
    track_batch(&plan, &radiomap, &dir.path().join("walks.csv"), &out)
        .success()
        .stdout(predicate::str::contains("2 walks tracked"));
    // The first walk's start is its own: the second starts unknown, as alone.
    for (walk, name, start) in [(&b, "second", Some(true_start(&b))), (&c, "walk-2", None)] {
        let alone = dir.path().join(format!("alone-{name}"));
        footslam()
            .arg("track")
            .args(start.map(|s| format!("--start={s}")))
            .arg("--plan")
            .arg(&plan)
            .arg("--radiomap")
            .arg(&radiomap)
            .arg("--steps")
            .arg(walk.join("steps.csv"))
            .arg("--wifi")
            .arg(walk.join("wifi.csv"))
            .args(["--seed", "3", "--out"])
            .arg(&alone)
            .assert()
            .success();
        for file in [
            "track.csv",
            "track_filtered.csv",
            "track.geojson",
            "config.json",
        ] {
            assert_eq!(
                read(&out.join(name).join(file)),
                read(&alone.join(file)),
                "{name}/{file}"
            );
        }
        assert!(out.join(name).join("track.png").is_file());
    }
    let table = String::from_utf8(read(&out.join("walks.csv"))).expect("utf-8");
    assert_eq!(table.lines().count(), 3, "{table}");
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&out.join("summary.json"))).expect("json");
    let names: Vec<&str> = summary["walks"]
        .as_array()
        .expect("walks")
        .iter()
        .map(|w| w["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["second", "walk-2"]);

    // A radio map needs every walk's log; names are plain and unique.
    for (manifest, problem) in [
        ("steps\ntower-22/steps.csv\n", "`wifi`"),
        (
            "steps,wifi,name\ntower-22/steps.csv,tower-22/wifi.csv,x\ntower-23/steps.csv,tower-23/wifi.csv,x\n",
            "names must be unique",
        ),
        (
            "steps,wifi,name\ntower-22/steps.csv,tower-22/wifi.csv,../up\n",
            "a plain folder name",
        ),
    ] {
        std::fs::write(dir.path().join("bad.csv"), manifest).expect("manifest");
        let bad = dir.path().join("bad");
        track_batch(&plan, &radiomap, &dir.path().join("bad.csv"), &bad)
            .failure()
            .stderr(predicate::str::contains(problem).and(predicate::str::contains("bad.csv")));
        assert!(!bad.exists(), "no partial output");
    }
}

#[test]
fn a_batch_places_each_walks_scans_as_fingerprint_alone_does() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (_, radiomap, b, c) = batch_inputs(dir.path());
    let out = dir.path().join("batch");
    footslam()
        .arg("fingerprint")
        .arg("--radiomap")
        .arg(&radiomap)
        .arg("--walks")
        .arg(dir.path().join("walks.csv"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "of 2 walks by the radio map alone",
        ));
    for (walk, name) in [(&b, "second"), (&c, "walk-2")] {
        let alone = dir.path().join(format!("alone-{name}"));
        footslam()
            .arg("fingerprint")
            .arg("--radiomap")
            .arg(&radiomap)
            .arg("--wifi")
            .arg(walk.join("wifi.csv"))
            .arg("--out")
            .arg(&alone)
            .assert()
            .success();
        for file in ["track.csv", "config.json"] {
            assert_eq!(
                read(&out.join(name).join(file)),
                read(&alone.join(file)),
                "{name}/{file}"
            );
        }
    }
    let table = String::from_utf8(read(&out.join("walks.csv"))).expect("utf-8");
    assert!(
        table.lines().nth(1).expect("row").contains("second"),
        "{table}"
    );
    assert_eq!(table.lines().count(), 3, "{table}");
    // A log, or a manifest of them; not both.
    footslam()
        .arg("fingerprint")
        .arg("--radiomap")
        .arg(&radiomap)
        .arg("--out")
        .arg(dir.path().join("none"))
        .assert()
        .failure()
        .stderr(predicate::str::contains("--wifi"));
}
