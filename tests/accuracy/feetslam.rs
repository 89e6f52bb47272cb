//! FeetSLAM iterations over a batch of walks with known starts (`learn --walks`): each walk
//! is learned again with the merged map of the others as its prior; the result does not
//! depend on the thread count, and walks without a shared frame are not iterated.

use assert_cmd::Command;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).expect("summary"))
        .expect("json")
}

fn learn(d: &Path, manifest: &str, out: &str, threads: &str, config: Option<&Path>) {
    let mut cmd = footslam();
    cmd.args([
        "learn",
        "--particles",
        "400",
        "--threads",
        threads,
        "--walks",
    ])
    .arg(d.join(manifest))
    .arg("--out")
    .arg(d.join(out));
    if let Some(c) = config {
        cmd.arg("--config").arg(c);
    }
    cmd.assert().success();
}

#[test]
fn walks_with_known_starts_are_iterated_independently_of_threads() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    for s in [31u64, 32, 33] {
        footslam()
            .args(["simulate", "--building", "office", "--laps", "1", "--seed"])
            .arg(s.to_string())
            .arg("--out")
            .arg(d.join(format!("sim-{s}")))
            .assert()
            .success();
    }
    // The office walks start at the origin facing east.
    let rows = [31, 32, 33].map(|s| format!("sim-{s}/steps.csv,\"0,0,0\"\n"));
    std::fs::write(
        d.join("walks.csv"),
        format!("steps,start\n{}", rows.concat()),
    )
    .expect("w");
    let rows = [31, 32, 33].map(|s| format!("sim-{s}/steps.csv\n"));
    std::fs::write(d.join("free.csv"), format!("steps\n{}", rows.concat())).expect("w");
    std::fs::write(d.join("alone.toml"), "iterations = 0\n").expect("config");

    learn(d, "walks.csv", "one", "1", None);
    learn(d, "walks.csv", "two", "2", None);
    learn(d, "walks.csv", "alone", "2", Some(&d.join("alone.toml")));
    learn(d, "free.csv", "free", "2", None);

    assert_eq!(summary(&d.join("one"))["iterations"], 2);
    assert_eq!(summary(&d.join("alone"))["iterations"], 0);
    // Walks in frames of their own (no start, no GPS) share no map to iterate with.
    assert_eq!(summary(&d.join("free"))["iterations"], 0);
    let read = |run: &str, file: &str| std::fs::read(d.join(run).join(file)).expect(file);
    let table = std::fs::read_to_string(d.join("one/walks.csv")).expect("walks.csv");
    assert_eq!(table.lines().count(), 4, "a header and one row per walk");
    assert!(table.starts_with("walk,") && table.contains("quality.verdict"));
    for file in ["merged.geojson", "walk-1/track.csv", "walk-3/track.csv"] {
        assert_eq!(read("one", file), read("two", file), "{file}: thread count");
    }
    // The iterations changed the walks: each saw the others' map.
    assert_ne!(
        read("one", "walk-2/track.csv"),
        read("alone", "walk-2/track.csv")
    );
}

#[test]
fn phone_grade_walks_learn_better_than_dead_reckoning() {
    // Walks drawn from the phone error model measured on real traces (`--sensor phone`):
    // the learned track's aligned p95 is at most 0.6× dead reckoning's.
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    for s in ["1", "2"] {
        let sim = d.join(format!("sim-{s}"));
        footslam()
            .args([
                "simulate", "--sensor", "phone", "--laps", "2", "--seed", s, "--out",
            ])
            .arg(&sim)
            .assert()
            .success();
        let config = std::fs::read_to_string(sim.join("config.json")).expect("config");
        assert!(config.contains("\"length_sigma\": 0.1"), "{config}");
        let run = d.join(format!("learn-{s}"));
        footslam()
            .args(["learn", "--particles", "5000", "--seed", s, "--steps"])
            .arg(sim.join("steps.csv"))
            .arg("--out")
            .arg(&run)
            .assert()
            .success();
        let out = footslam()
            .args(["eval", "--json", "--align", "rigid", "--truth"])
            .arg(sim.join("truth.csv"))
            .arg("--track")
            .arg(run.join("track.csv"))
            .arg("--steps")
            .arg(sim.join("steps.csv"))
            .output()
            .expect("eval");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        let (learned, dr) = (
            v["track"]["p95"].as_f64().expect("p95"),
            v["dead_reckoning"]["p95"].as_f64().expect("p95"),
        );
        eprintln!("phone-grade walk {s}: learned p95 {learned:.2} m, dead reckoning {dr:.2} m");
        assert!(
            learned <= 0.6 * dr,
            "walk {s}: {learned:.2} m against {dr:.2} m"
        );
    }
}
