//! `track --hexmap` (issue 14, part 3): a learned map's transition probabilities as the
//! tracker's motion prior, end to end through the CLI.
//!
//! Three walks of a one-floor simulated building are learned from their known starts with
//! their WiFi (`learn --walks`, so the learned frame is the truth's); new walkers are then
//! tracked from an unknown start on the learned plan with the learned radio map, with and
//! without `--hexmap merged.geojson`. The prior must make every walker's median error
//! smaller (it pulls particles onto the lanes the mapping walks trod) and must not slow
//! localisation by more than a few steps.

use assert_cmd::Command;
use footslam::eval::{Alignment, position_errors};
use footslam::io::read_trajectory;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("json")
}

/// `X,Y,HEADING,LEVEL` of a simulated walk's start.
fn start(sim: &Path) -> String {
    let s = &json(&sim.join("summary.json"))["start"];
    let n = |k: &str| s[k].as_f64().expect("start");
    format!("{},{},{},{}", n("x"), n("y"), n("heading"), n("level"))
}

fn simulate(dir: &Path, seed: u64) -> std::path::PathBuf {
    let sim = dir.join(format!("sim-{seed}"));
    footslam()
        .args(["simulate", "--building", "tower", "--floors", "1", "--seed"])
        .arg(seed.to_string())
        .arg("--out")
        .arg(&sim)
        .assert()
        .success();
    sim
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn a_learned_maps_transitions_sharpen_tracking_on_its_plan() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let mut manifest = String::from("steps,wifi,start\n");
    for seed in [21u64, 22, 23] {
        let sim = simulate(d, seed);
        manifest.push_str(&format!(
            "sim-{seed}/steps.csv,sim-{seed}/wifi.csv,\"{}\"\n",
            start(&sim)
        ));
    }
    std::fs::write(d.join("walks.csv"), manifest).expect("manifest");
    let learned = d.join("learn");
    footslam()
        .args(["learn", "--particles", "5000", "--walks"])
        .arg(d.join("walks.csv"))
        .arg("--out")
        .arg(&learned)
        .assert()
        .success();
    for seed in [30u64, 32] {
        let sim = simulate(d, seed);
        let run = |hexmap: bool| {
            let out = d.join(format!("track-{seed}-{hexmap}"));
            let mut cmd = footslam();
            cmd.arg("track")
                .arg("--plan")
                .arg(learned.join("merged_plan.geojson"))
                .args(["--plan-margin", "0.25", "--radiomap"])
                .arg(learned.join("radiomap.geojson"))
                .arg("--wifi")
                .arg(sim.join("wifi.csv"))
                .arg("--steps")
                .arg(sim.join("steps.csv"))
                .arg("--out")
                .arg(&out);
            if hexmap {
                cmd.arg("--hexmap").arg(learned.join("merged.geojson"));
            }
            cmd.assert().success();
            let summary = json(&out.join("summary.json"));
            assert_eq!(summary["hexmap_hexagons"].as_u64().is_some(), hexmap);
            let errors = position_errors(
                &read_trajectory(&sim.join("truth.csv")).expect("truth"),
                &read_trajectory(&out.join("track.csv")).expect("track"),
                Alignment::None,
            )
            .expect("errors");
            let localised = summary["steps_to_localise"].as_u64().expect("localised");
            (errors.p50, errors.p95, localised)
        };
        let (plain, hex) = (run(false), run(true));
        eprintln!("walker {seed}: plain (p50, p95, steps) {plain:?}, with --hexmap {hex:?}");
        assert!(hex.0 < plain.0, "walker {seed}: {hex:?} against {plain:?}");
        assert!(hex.1 < 1.2, "walker {seed}: {hex:?}");
        assert!(
            hex.2 <= plain.2 + 3,
            "walker {seed}: {hex:?} against {plain:?}"
        );
    }
    // A map in another frame (the plan placed elsewhere by --origin) is refused, naming it.
    let other = learned.join("merged.geojson");
    let sim = d.join("sim-30");
    let assert = footslam()
        .arg("track")
        .arg("--plan")
        .arg(learned.join("merged_plan.geojson"))
        .arg("--steps")
        .arg(sim.join("steps.csv"))
        .args(["--origin", "0.001,0"])
        .arg("--hexmap")
        .arg(&other)
        .arg("--out")
        .arg(d.join("refused"))
        .assert()
        .failure();
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
    assert!(
        stderr.contains("merged.geojson") && stderr.contains("frame"),
        "{stderr}"
    );
}
