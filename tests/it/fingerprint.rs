//! `footslam fingerprint`: the radio map used alone, on the bundled simulated tower walk
//! (surveyed by `footslam survey` from an unknown start, then each of its scans placed).

use assert_cmd::Command;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn tower(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("datasets/tower")
        .join(name)
}

#[test]
fn places_scans_near_the_truth_and_refuses_another_building() {
    let dir = tempfile::tempdir().expect("tempdir");
    let survey = dir.path().join("survey");
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(tower("floor.geojson"))
        .arg("--steps")
        .arg(tower("steps.csv"))
        .arg("--wifi")
        .arg(tower("wifi.csv"))
        .arg("--out")
        .arg(&survey)
        .assert()
        .success();
    let fp = dir.path().join("fp");
    footslam()
        .arg("fingerprint")
        .arg("--radiomap")
        .arg(survey.join("radiomap.geojson"))
        .arg("--wifi")
        .arg(tower("wifi.csv"))
        .arg("--out")
        .arg(&fp)
        .assert()
        .success();
    for name in ["track.csv", "summary.json", "config.json"] {
        assert!(fp.join(name).is_file(), "{name}");
    }
    let out = footslam()
        .args(["eval", "--json", "--truth"])
        .arg(tower("truth.csv"))
        .arg("--track")
        .arg(fp.join("track.csv"))
        .assert()
        .success();
    let v: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).expect("json");
    // Placed on the map's own walk: 3 m cells, median within a cell, every scan on its floor.
    assert!(v["track"]["p50"].as_f64().expect("p50") < 3.0, "{v}");
    assert!(v["floor_accuracy"].as_f64().expect("floors") > 0.9, "{v}");

    // A log of another building (no access point in common) is an error naming both files.
    let other = dir.path().join("other.csv");
    std::fs::write(&other, "t,bssid,rssi\n1,zz:zz:zz:zz:zz:01,-60\n").expect("write");
    footslam()
        .arg("fingerprint")
        .arg("--radiomap")
        .arg(survey.join("radiomap.geojson"))
        .arg("--wifi")
        .arg(&other)
        .arg("--out")
        .arg(dir.path().join("fp2"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("other.csv"))
        .stderr(predicates::str::contains("different buildings"));
    assert!(!dir.path().join("fp2").exists());
}
