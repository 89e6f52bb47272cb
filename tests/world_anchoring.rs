//! FootSLAM anchored to the world (GPS, outline, maps merged across walks) on simulated
//! outdoor–indoor–outdoor walks of the campus office, end to end through the CLI.
//!
//! * Each walk alone: the absolute p95 error of the learned path (no alignment, in the
//!   simulator's frame) is at most the p95 error of the walk's own GPS fixes plus 1.5 m; with
//!   the building's rough outline (each side off by up to 1.5 m) it is no worse (within
//!   0.5 m, a hexagon) and better on average over the seeds.
//! * Five successive walks of one building, each seeded with the merge of the maps before
//!   it: the fifth walk's absolute p95 error is at most 60 % of a first walk's — the mean
//!   over the same five walks each learned alone, without a prior map.
//!
//! Runs use 5,000 particles (a quarter of the default) to keep the tests short.

use assert_cmd::Command;
use footslam::dataset::read_trajectory;
use footslam::eval::{Alignment, position_errors};
use std::path::{Path, PathBuf};

const ORIGIN: &str = "48.15,11.57";
const PARTICLES: &str = "5000";

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn simulate(dir: &Path, seed: u64, walks: usize) -> PathBuf {
    let sim = dir.join(format!("sim-{seed}"));
    footslam()
        .args(["simulate", "--building", "campus", "--origin", ORIGIN])
        .args(["--seed", &seed.to_string(), "--walks", &walks.to_string(), "--out"])
        .arg(&sim)
        .assert()
        .success();
    sim
}

fn learn(steps: &Path, gps: &Path, out: &Path, seed: u64, extra: &[&Path], flags: &[&str]) {
    let mut cmd = footslam();
    cmd.args(["learn", "--particles", PARTICLES, "--origin", ORIGIN, "--seed"])
        .arg(seed.to_string())
        .arg("--steps")
        .arg(steps)
        .arg("--gps")
        .arg(gps)
        .arg("--out")
        .arg(out);
    for (flag, path) in flags.iter().zip(extra) {
        cmd.arg(flag).arg(path);
    }
    cmd.assert().success();
}

/// Absolute p95 error of a track against the truth, metres.
fn p95(truth: &Path, track: &Path) -> f64 {
    let truth = read_trajectory(truth).expect("truth");
    let track = read_trajectory(track).expect("track");
    position_errors(&truth, &track, Alignment::None)
        .expect("errors")
        .p95
}

/// The p95 error of walk `i`'s GPS fixes, from the simulator's summary.
fn gps_p95(sim: &Path, i: usize) -> f64 {
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(sim.join("summary.json")).expect("summary"))
            .expect("json");
    summary["walks"][i]["gps_error_p95_m"].as_f64().expect("p95")
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn outdoor_indoor_outdoor_walks_are_anchored_and_the_outline_helps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (mut alone_sum, mut outline_sum) = (0.0, 0.0);
    let seeds = [21, 22, 23];
    for seed in seeds {
        let sim = simulate(dir.path(), seed, 1);
        let (steps, gps, truth) = (sim.join("steps.csv"), sim.join("gps.csv"), sim.join("truth.csv"));
        let alone = dir.path().join(format!("alone-{seed}"));
        learn(&steps, &gps, &alone, seed, &[], &[]);
        let with = dir.path().join(format!("outline-{seed}"));
        learn(&steps, &gps, &with, seed, &[&sim.join("outline.geojson")], &["--outline"]);
        let (a, o, g) = (p95(&truth, &alone.join("track.csv")), p95(&truth, &with.join("track.csv")), gps_p95(&sim, 0));
        eprintln!("seed {seed}: GPS p95 {g:.2} m; learned p95 {a:.2} m alone, {o:.2} m with the outline");
        assert!(a <= g + 1.5, "seed {seed}: p95 {a:.2} m > GPS {g:.2} m + 1.5 m");
        assert!(o <= g + 1.5, "seed {seed}: with outline p95 {o:.2} m > GPS {g:.2} m + 1.5 m");
        assert!(o <= a + 0.5, "seed {seed}: the outline made it worse: {o:.2} m vs {a:.2} m");
        alone_sum += a;
        outline_sum += o;
    }
    let n = seeds.len() as f64;
    eprintln!("mean p95: {:.2} m alone, {:.2} m with the outline", alone_sum / n, outline_sum / n);
    assert!(outline_sum < alone_sum, "the outline does not help on average");
}

#[test]
#[allow(clippy::print_stderr)]
fn five_successive_walks_improve_with_merged_maps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let seed = 31;
    let sim = simulate(dir.path(), seed, 5);
    // Every walk alone, as a batch (walk i learned with seed `seed + i`).
    let alone = dir.path().join("alone");
    footslam()
        .args(["learn", "--particles", PARTICLES, "--origin", ORIGIN, "--seed"])
        .arg(seed.to_string())
        .arg("--steps")
        .arg(&sim)
        .arg("--out")
        .arg(&alone)
        .assert()
        .success();
    let walk = |k: usize| sim.join(format!("walk-{k}"));
    let alone_errors: Vec<f64> = (1..=5)
        .map(|k| p95(&walk(k).join("truth.csv"), &alone.join(format!("walk-{k}/track.csv"))))
        .collect();
    // Walk 1 is a first walk; walk k > 1 starts from the merge of the maps before it.
    let mut maps = vec![alone.join("walk-1/map.geojson")];
    let mut sequence = vec![alone_errors[0]];
    for k in 2..=5 {
        let merged = dir.path().join(format!("merged-{}.geojson", k - 1));
        footslam().arg("merge").args(&maps).arg("--out").arg(&merged).assert().success();
        let out = dir.path().join(format!("seq-{k}"));
        let (steps, gps) = (walk(k).join("steps.csv"), walk(k).join("gps.csv"));
        learn(&steps, &gps, &out, seed + k as u64 - 1, &[&merged], &["--prior-map"]);
        sequence.push(p95(&walk(k).join("truth.csv"), &out.join("track.csv")));
        maps.push(out.join("map.geojson"));
    }
    let first = alone_errors.iter().sum::<f64>() / 5.0;
    eprintln!("walks alone: p95 {alone_errors:.2?} m (mean {first:.2} m)");
    eprintln!("in sequence with merged prior maps: p95 {sequence:.2?} m");
    assert!(
        sequence[4] <= 0.6 * first,
        "fifth walk {:.2} m is not 60 % of a first walk's {first:.2} m",
        sequence[4]
    );
}
