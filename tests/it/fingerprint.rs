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
    // The walk's scans placed on the map (with `config`), scored against its truth.
    let place = |out: &Path, config: Option<&Path>| {
        let mut fingerprint = footslam();
        fingerprint.arg("fingerprint").arg("--radiomap");
        fingerprint.arg(survey.join("radiomap.geojson"));
        fingerprint.arg("--wifi").arg(tower("wifi.csv"));
        if let Some(config) = config {
            fingerprint.arg("--config").arg(config);
        }
        fingerprint.arg("--out").arg(out).assert().success();
        let eval = footslam()
            .args(["eval", "--json", "--truth"])
            .arg(tower("truth.csv"))
            .arg("--track")
            .arg(out.join("track.csv"))
            .assert()
            .success();
        let v: serde_json::Value = serde_json::from_slice(&eval.get_output().stdout).expect("json");
        v
    };
    let fp = dir.path().join("fp");
    let v = place(&fp, None);
    for name in ["track.csv", "summary.json", "config.json"] {
        assert!(fp.join(name).is_file(), "{name}");
    }
    // Placed on the map's own walk: 3 m cells, median within a cell, every scan on its floor.
    assert!(v["track"]["p50"].as_f64().expect("p50") < 3.0, "{v}");
    assert!(v["floor_accuracy"].as_f64().expect("floors") > 0.9, "{v}");
    // The default (`auto`) picks by the survey's coverage — this walk surveys under 60 % of
    // the tower's cells: the path-loss model per access point — and reports its fit.
    let summary = |dir: &Path| -> serde_json::Value {
        let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary");
        serde_json::from_str(&text).expect("json")
    };
    let report = summary(&fp);
    assert_eq!(report["method"], "pathloss", "{report}");
    let fit = &report["pathloss"];
    assert!(fit["access_points"].as_u64().expect("APs") > 0, "{fit}");
    let n = fit["median_exponent"].as_f64().expect("n");
    assert!((1.5..=5.0).contains(&n), "{fit}");

    // The interpolated map stays selectable, and places the walk as well.
    let config = dir.path().join("gp.toml");
    std::fs::write(&config, "method = \"interpolated\"\n").expect("write");
    let gp = dir.path().join("gp");
    let v = place(&gp, Some(&config));
    assert!(v["track"]["p50"].as_f64().expect("p50") < 3.0, "{v}");
    let fit = &summary(&gp)["interpolation"];
    assert!(fit["length_scale"].as_f64().expect("ℓ") > 0.0, "{fit}");
    assert!(fit["pairs"].as_u64().expect("pairs") > 0, "{fit}");

    // The weighted k-nearest method stays selectable, and places the walk as well.
    let config = dir.path().join("ndist.toml");
    std::fs::write(&config, "method = \"ndist\"\n").expect("write");
    let nd = dir.path().join("nd");
    let v = place(&nd, Some(&config));
    assert!(v["track"]["p50"].as_f64().expect("p50") < 3.0, "{v}");
    let summary = std::fs::read_to_string(nd.join("summary.json")).expect("summary");
    assert!(summary.contains("\"interpolation\": null"), "{summary}");

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
