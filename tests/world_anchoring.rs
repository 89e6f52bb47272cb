//! FootSLAM anchored to the world (GPS, outline, maps merged across walks) on simulated
//! outdoor–indoor–outdoor walks of the campus office, end to end through the CLI.
//!
//! * Each walk alone (six walks, each learned with four filter seeds): the absolute p95 error
//!   of the learned path (no alignment, in the simulator's frame) is at most the p95 error of
//!   the walk's own GPS fixes plus 1.5 m, with and without the building's rough outline
//!   (each side off by up to 1.5 m); with the outline every walk's mean p95 is no worse than
//!   without (within 1 m, the noise of a difference of two means of four runs) and the mean
//!   over the walks is better.
//! * Five successive walks of one building, each seeded with the merged map of the walks
//!   before it: the fifth walk's absolute p95 error is at most 60 % of a first walk's — the
//!   mean over the same five walks each learned alone, without a prior map — averaged over
//!   two buildings' worth of walks (seeds).
//! * Walks that enter under GPS and never come back out (GPS sees only the way to the
//!   entrance, so the fixes bound the start point, not the map's rotation): each walk's
//!   absolute p95 is at most its GPS-fix p95 plus 1.5 m, with and without a compass
//!   `heading` column, with and without the outline; and five such walks merged in
//!   sequence bring the fifth walk's p95 to at most 60 % of a first walk's and below the
//!   mean GPS-fix p95, averaged over six buildings' worth of walks.
//!
//! Runs use 5,000 particles (a quarter of the default) to keep the tests short.

use assert_cmd::Command;
use footslam::eval::{Alignment, position_errors};
use footslam::io::read_trajectory;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

const ORIGIN: &str = "48.15,11.57";
const PARTICLES: &str = "5000";
/// Filter seeds per walk in the outline comparison.
const FILTER_SEEDS: u64 = 4;
/// "No worse": a walk's mean p95 with the outline at most this much above without, metres
/// (the noise of a difference of two means of four runs: one run's p95 moves by 1–3 m
/// with the filter seed alone).
const NO_WORSE: f64 = 1.0;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn simulate(dir: &Path, seed: u64, walks: usize, laps: usize) -> PathBuf {
    simulate_with(dir, seed, walks, laps, &[])
}

/// `footslam simulate --building campus` with extra `flags`, into its own folder.
fn simulate_with(dir: &Path, seed: u64, walks: usize, laps: usize, flags: &[&str]) -> PathBuf {
    let sim = dir.join(format!("sim-{seed}{}", flags.concat()));
    footslam()
        .args(["simulate", "--building", "campus", "--origin", ORIGIN])
        .args([
            "--seed",
            &seed.to_string(),
            "--walks",
            &walks.to_string(),
            "--laps",
            &laps.to_string(),
        ])
        .args(flags)
        .arg("--out")
        .arg(&sim)
        .assert()
        .success();
    sim
}

/// `footslam learn` with the tests' particles, origin and `seed`, writing to `out`.
fn learn_command(seed: u64, out: &Path) -> Command {
    let mut cmd = footslam();
    cmd.args(["learn", "--particles", PARTICLES, "--origin", ORIGIN])
        .arg("--seed")
        .arg(seed.to_string())
        .arg("--out")
        .arg(out);
    cmd
}

/// `learn` of one walk with GPS, plus `files` given as `(flag, path)`.
fn learn(steps: &Path, gps: &Path, out: &Path, seed: u64, files: &[(&str, &Path)]) {
    let mut cmd = learn_command(seed, out);
    cmd.arg("--steps").arg(steps).arg("--gps").arg(gps);
    for (flag, path) in files {
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
    summary["walks"][i]["gps_error_p95_m"]
        .as_f64()
        .expect("p95")
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn outdoor_indoor_outdoor_walks_are_anchored_and_the_outline_helps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let walks: Vec<u64> = (21..=26).collect();
    let sims: Vec<PathBuf> = walks
        .iter()
        .map(|&w| simulate(dir.path(), w, 1, 3))
        .collect();
    // Every walk learned with four filter seeds, with and without the outline: one run's
    // p95 varies by 1–3 m with the seed alone, more than the outline changes it.
    let runs: Vec<(usize, u64, bool)> = (0..walks.len())
        .flat_map(|w| (1..=FILTER_SEEDS).flat_map(move |f| [(w, f, false), (w, f, true)]))
        .collect();
    let p95s: Vec<f64> = runs
        .par_iter()
        .map(|&(w, f, outline)| {
            let sim = &sims[w];
            let out = dir.path().join(format!("run-{}-{f}-{outline}", walks[w]));
            let (steps, gps) = (sim.join("steps.csv"), sim.join("gps.csv"));
            let shape = sim.join("outline.geojson");
            let extra = outline.then_some(("--outline", shape.as_path()));
            learn(&steps, &gps, &out, f, extra.as_slice());
            p95(&sim.join("truth.csv"), &out.join("track.csv"))
        })
        .collect();
    let mean_of = |w: usize, outline: bool| {
        let v: Vec<f64> = runs
            .iter()
            .zip(&p95s)
            .filter(|((rw, _, o), _)| *rw == w && *o == outline)
            .map(|(_, p)| *p)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (mut alone_sum, mut outline_sum) = (0.0, 0.0);
    for (w, sim) in sims.iter().enumerate() {
        let g = gps_p95(sim, 0);
        for ((_, f, outline), p) in runs.iter().zip(&p95s).filter(|((rw, ..), _)| *rw == w) {
            assert!(
                *p <= g + 1.5,
                "walk {} seed {f} (outline: {outline}): p95 {p:.2} m > GPS {g:.2} m + 1.5 m",
                walks[w]
            );
        }
        let (a, o) = (mean_of(w, false), mean_of(w, true));
        eprintln!(
            "walk {}: GPS p95 {g:.2} m; learned p95 (mean of {FILTER_SEEDS} seeds) {a:.2} m alone, {o:.2} m with the outline",
            walks[w]
        );
        assert!(
            o <= a + NO_WORSE,
            "walk {}: the outline makes it worse: {o:.2} m against {a:.2} m",
            walks[w]
        );
        alone_sum += a;
        outline_sum += o;
    }
    let n = walks.len() as f64;
    let (alone, outline) = (alone_sum / n, outline_sum / n);
    eprintln!("mean p95: {alone:.2} m alone, {outline:.2} m with the outline");
    assert!(
        outline < alone,
        "the outline is not better on average: {outline:.2} m against {alone:.2} m"
    );
}

/// One building's five walks: each alone (a batch), then in sequence, each walk after the
/// first learned from the previous walk's merged map. Returns (alone p95s, sequence p95s).
fn five_walks(dir: &Path, seed: u64) -> (Vec<f64>, Vec<f64>) {
    five_walks_of(&simulate(dir, seed, 5, 3), dir, seed)
}

/// [`five_walks`] of the five walks simulated in `sim`.
fn five_walks_of(sim: &Path, dir: &Path, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let tag = sim.file_name().and_then(|n| n.to_str()).unwrap_or("sim");
    let alone = dir.join(format!("alone-{tag}"));
    // Each walk alone: no FeetSLAM iterations over the batch (they would share the maps).
    let config = dir.join("alone.toml");
    std::fs::write(&config, "iterations = 0\n").expect("config");
    learn_command(seed, &alone)
        .arg("--steps")
        .arg(sim)
        .arg("--config")
        .arg(&config)
        .assert()
        .success();
    let walk = |k: usize| sim.join(format!("walk-{k}"));
    let alone_errors: Vec<f64> = (1..=5)
        .map(|k| {
            p95(
                &walk(k).join("truth.csv"),
                &alone.join(format!("walk-{k}/track.csv")),
            )
        })
        .collect();
    let mut prior = alone.join("walk-1/map.geojson");
    let mut sequence = vec![alone_errors[0]];
    for k in 2..=5 {
        let out = dir.join(format!("seq-{tag}-{k}"));
        let (steps, gps) = (walk(k).join("steps.csv"), walk(k).join("gps.csv"));
        // Walk k of the batch had seed `seed + k - 1`: the same draws, only the prior differs.
        learn(
            &steps,
            &gps,
            &out,
            seed + k as u64 - 1,
            &[("--prior-map", &prior)],
        );
        sequence.push(p95(&walk(k).join("truth.csv"), &out.join("track.csv")));
        prior = out.join("merged.geojson");
    }
    (alone_errors, sequence)
}

#[test]
#[allow(clippy::print_stderr)]
fn five_successive_walks_improve_with_merged_maps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (mut first, mut fifth) = (0.0, 0.0);
    let seeds = [31, 32];
    for seed in seeds {
        let (alone, sequence) = five_walks(dir.path(), seed);
        let mean = alone.iter().sum::<f64>() / 5.0;
        eprintln!(
            "seed {seed}: walks alone p95 {alone:.2?} m (mean {mean:.2} m); in sequence {sequence:.2?} m"
        );
        first += mean;
        fifth += sequence[4];
    }
    let n = seeds.len() as f64;
    let (first, fifth) = (first / n, fifth / n);
    eprintln!(
        "first walks {first:.2} m, fifth walk with merged prior {fifth:.2} m ({:.0} %)",
        100.0 * fifth / first
    );
    assert!(
        fifth <= 0.6 * first,
        "fifth walk {fifth:.2} m is not 60 % of a first walk's {first:.2} m"
    );
}

#[test]
#[allow(clippy::print_stderr)]
fn walks_that_stay_indoors_are_anchored_by_the_entrance_with_and_without_a_compass() {
    let dir = tempfile::tempdir().expect("tempdir");
    let walks: Vec<u64> = (41..=44).collect();
    let variants: [&[&str]; 2] = [&["--entrance-only"], &["--entrance-only", "--compass"]];
    let sims: Vec<(u64, usize, PathBuf)> = walks
        .iter()
        .flat_map(|&w| (0..2).map(move |v| (w, v)))
        .map(|(w, v)| (w, v, simulate_with(dir.path(), w, 1, 3, variants[v])))
        .collect();
    let runs: Vec<(usize, bool)> = (0..sims.len())
        .flat_map(|i| [(i, false), (i, true)])
        .collect();
    let p95s: Vec<f64> = runs
        .par_iter()
        .map(|&(i, outline)| {
            let (w, v, sim) = &sims[i];
            let out = dir.path().join(format!("in-{w}-{v}-{outline}"));
            let shape = sim.join("outline.geojson");
            let extra = outline.then_some(("--outline", shape.as_path()));
            learn(
                &sim.join("steps.csv"),
                &sim.join("gps.csv"),
                &out,
                1,
                extra.as_slice(),
            );
            p95(&sim.join("truth.csv"), &out.join("track.csv"))
        })
        .collect();
    for (&(i, outline), p) in runs.iter().zip(&p95s) {
        let (w, v, sim) = &sims[i];
        let g = gps_p95(sim, 0);
        let compass = *v == 1;
        eprintln!(
            "walk {w} (compass: {compass}, outline: {outline}): p95 {p:.2} m, GPS p95 {g:.2} m"
        );
        assert!(
            *p <= g + 1.5,
            "walk {w} (compass: {compass}, outline: {outline}): p95 {p:.2} m > GPS {g:.2} m + 1.5 m"
        );
    }
    // The summary says where the heading came from and how well it is known.
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("in-41-1-true/summary.json")).expect("summary"),
    )
    .expect("json");
    assert_eq!(summary["heading"]["start_source"], "compass");
    let spread = summary["heading"]["final_sigma_deg"]
        .as_f64()
        .expect("spread");
    assert!(spread > 0.0 && spread < 20.0, "{spread}");
}

#[test]
#[allow(clippy::print_stderr)]
fn five_walks_that_stay_indoors_improve_with_merged_maps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (mut first, mut fifth, mut gps) = (0.0, 0.0, 0.0);
    let seeds: Vec<u64> = (31..=36).collect();
    for &seed in &seeds {
        let sim = simulate_with(dir.path(), seed, 5, 3, &["--entrance-only"]);
        let (alone, sequence) = five_walks_of(&sim, dir.path(), seed);
        let mean = alone.iter().sum::<f64>() / 5.0;
        let g = (0..5).map(|i| gps_p95(&sim, i)).sum::<f64>() / 5.0;
        eprintln!(
            "seed {seed}: walks alone p95 {alone:.2?} m (mean {mean:.2} m); in sequence {sequence:.2?} m; mean GPS p95 {g:.2} m"
        );
        first += mean;
        fifth += sequence[4];
        gps += g;
    }
    let n = seeds.len() as f64;
    let (first, fifth, gps) = (first / n, fifth / n, gps / n);
    eprintln!(
        "first walks {first:.2} m, fifth walk with merged prior {fifth:.2} m ({:.0} %), mean GPS p95 {gps:.2} m",
        100.0 * fifth / first
    );
    assert!(
        fifth <= 0.6 * first,
        "fifth walk {fifth:.2} m is not 60 % of a first walk's {first:.2} m"
    );
    assert!(
        fifth <= gps,
        "fifth walk {fifth:.2} m above the GPS p95 {gps:.2} m"
    );
}
