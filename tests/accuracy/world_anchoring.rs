//! FootSLAM anchored to the world (GPS, outline, maps merged across walks) on simulated
//! outdoor–indoor–outdoor walks of the campus office, simulated, learned and scored through
//! the library (`footslam::sim`, `footslam::pipeline::learn`, `footslam::eval`) as `footslam
//! simulate --building campus` and `footslam learn` run them.
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

use crate::common::{
    Anchors, learn_walks_with, learned_track, nearest_rank_p95, p95, recorded, recorded_fixes,
    recorded_truth, stored, truth_track,
};
use footslam::eval::Alignment;
use footslam::filter::FootSlamConfig;
use footslam::geometry::LocalFrame;
use footslam::io::map_geojson::StoredMap;
use footslam::io::{TimedPoint, read_outline, write_outline};
use footslam::pipeline::{LearnConfig, LearnWalk, Learned, WalkRun};
use footslam::sim::{CampusSimConfig, simulate_campus};
use geo::Polygon;
use rayon::prelude::*;

/// The frame the campus is placed in (`--origin`).
const ORIGIN: (f64, f64) = (48.15, 11.57);
const PARTICLES: usize = 5000;
/// Filter seeds per walk in the outline comparison.
const FILTER_SEEDS: u64 = 4;
/// "No worse": a walk's mean p95 with the outline at most this much above without, metres
/// (the noise of a difference of two means of four runs: one run's p95 moves by 1–3 m
/// with the filter seed alone).
const NO_WORSE: f64 = 1.0;

fn origin() -> LocalFrame {
    LocalFrame::new(ORIGIN.0, ORIGIN.1).expect("origin")
}

/// A simulated walk as the tests use it: what `learn` reads of it (its steps and GPS fixes
/// as its files record them), its truth (as `truth.csv` records it) and the p95 error of its
/// fixes (the simulator's `gps_error_p95_m`), metres.
struct Walk {
    input: LearnWalk,
    truth: Vec<TimedPoint>,
    gps_p95: f64,
}

/// A simulated campus: the building's rough outline (as `outline.geojson` records it) and
/// the walks.
struct Campus {
    outline: Polygon<f64>,
    walks: Vec<Walk>,
}

/// The campus and its `walks` walks of `laps` laps (`footslam simulate --building campus`);
/// `entrance_only` and `compass` as its flags.
fn simulate(seed: u64, walks: usize, laps: usize, entrance_only: bool, compass: bool) -> Campus {
    let mut config = CampusSimConfig {
        seed,
        walks,
        walk_out: !entrance_only,
        ..Default::default()
    };
    config.walk.laps = laps;
    config.compass.enabled |= compass;
    let sim = simulate_campus(&config, &origin()).expect("simulate");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("outline.geojson");
    write_outline(&path, &sim.outline, &origin()).expect("write outline");
    let outline = read_outline(&path, &origin()).expect("read outline");
    let walks = sim
        .walks
        .iter()
        .map(|w| Walk {
            input: LearnWalk {
                trace: recorded(&w.steps),
                fixes: recorded_fixes(&w.gps.fixes),
                ..Default::default()
            },
            truth: truth_track(&recorded_truth(&w.truth).poses),
            gps_p95: nearest_rank_p95(&w.gps.errors),
        })
        .collect();
    Campus { outline, walks }
}

/// `learn` of walks with GPS in the campus frame with the tests' particles and `seed`, with
/// the outline and a prior map when given.
fn learn(
    walks: &[LearnWalk],
    seed: u64,
    outline: Option<&Polygon<f64>>,
    prior_map: Option<&StoredMap>,
    mut config: LearnConfig,
) -> Learned {
    let anchors = Anchors {
        frame: origin(),
        outline,
        prior_map,
    };
    config.footslam = FootSlamConfig {
        particles: PARTICLES,
        seed,
        ..config.footslam
    };
    learn_walks_with(walks, anchors, &config)
}

/// Absolute p95 error of a walk's learned path against its truth, metres.
fn walk_p95(walk: &Walk, run: &WalkRun) -> f64 {
    p95(
        &walk.truth,
        &learned_track(&walk.input.trace, run),
        Alignment::None,
    )
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn outdoor_indoor_outdoor_walks_are_anchored_and_the_outline_helps() {
    let walks: Vec<u64> = (21..=26).collect();
    let sims: Vec<Campus> = walks
        .iter()
        .map(|&w| simulate(w, 1, 3, false, false))
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
            let shape = outline.then_some(&sim.outline);
            let walk = &sim.walks[0];
            let input = std::slice::from_ref(&walk.input);
            let learned = learn(input, f, shape, None, Default::default());
            walk_p95(walk, &learned.walks[0])
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
        let g = sim.walks[0].gps_p95;
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

/// One building's five walks (simulated in `sim`): each alone (a batch), then in sequence,
/// each walk after the first learned from the previous walk's merged map. Returns (alone
/// p95s, sequence p95s).
fn five_walks_of(sim: &Campus, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let walks: Vec<LearnWalk> = sim.walks.iter().map(|w| w.input.clone()).collect();
    // Each walk alone: no FeetSLAM iterations over the batch (they would share the maps).
    let alone_config = LearnConfig {
        iterations: 0,
        ..Default::default()
    };
    let alone = learn(&walks, seed, None, None, alone_config);
    let alone_errors: Vec<f64> = sim
        .walks
        .iter()
        .zip(&alone.walks)
        .map(|(walk, run)| walk_p95(walk, run))
        .collect();
    // The first walk's map.geojson: one walk's counts.
    let mut prior = stored(&alone.walks[0].estimate.map, origin(), 1);
    let mut sequence = vec![alone_errors[0]];
    for k in 2..=5 {
        // Walk k of the batch had seed `seed + k - 1`: the same draws, only the prior differs.
        let walk = &sim.walks[k - 1];
        let seed = seed + k as u64 - 1;
        let learned = learn(
            &walks[k - 1..k],
            seed,
            None,
            Some(&prior),
            Default::default(),
        );
        sequence.push(walk_p95(walk, &learned.walks[0]));
        // Its merged.geojson: the prior and this walk's map in this walk's frame.
        prior = stored(
            &learned.combined.merged_with_prior[0],
            origin(),
            prior.walks + 1,
        );
    }
    (alone_errors, sequence)
}

#[test]
#[allow(clippy::print_stderr)]
fn five_successive_walks_improve_with_merged_maps() {
    let (mut first, mut fifth) = (0.0, 0.0);
    let seeds = [31, 32];
    for seed in seeds {
        let (alone, sequence) = five_walks_of(&simulate(seed, 5, 3, false, false), seed);
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
    let walks: Vec<u64> = (41..=44).collect();
    // Variant 0: `--entrance-only`; variant 1: with `--compass` too.
    let sims: Vec<(u64, usize, Campus)> = walks
        .iter()
        .flat_map(|&w| (0..2).map(move |v| (w, v)))
        .map(|(w, v)| (w, v, simulate(w, 1, 3, true, v == 1)))
        .collect();
    let runs: Vec<(usize, bool)> = (0..sims.len())
        .flat_map(|i| [(i, false), (i, true)])
        .collect();
    // Each run's p95, and where its start heading came from and the map's final heading
    // spread (summary.json's `heading`), degrees.
    let results: Vec<(f64, &str, f64)> = runs
        .par_iter()
        .map(|&(i, outline)| {
            let (_, _, sim) = &sims[i];
            let shape = outline.then_some(&sim.outline);
            let walk = &sim.walks[0];
            let input = std::slice::from_ref(&walk.input);
            let learned = learn(input, 1, shape, None, Default::default());
            let run = &learned.walks[0];
            let spread = run.filter.heading_spread().to_degrees();
            (walk_p95(walk, run), run.start_source, spread)
        })
        .collect();
    for (&(i, outline), (p, ..)) in runs.iter().zip(&results) {
        let (w, v, sim) = &sims[i];
        let g = sim.walks[0].gps_p95;
        let compass = *v == 1;
        eprintln!(
            "walk {w} (compass: {compass}, outline: {outline}): p95 {p:.2} m, GPS p95 {g:.2} m"
        );
        assert!(
            *p <= g + 1.5,
            "walk {w} (compass: {compass}, outline: {outline}): p95 {p:.2} m > GPS {g:.2} m + 1.5 m"
        );
    }
    // Where the heading came from and how well it is known: walk 41 with the compass and
    // the outline.
    let (_, source, spread) = results[runs
        .iter()
        .position(|&(i, outline)| sims[i].0 == 41 && sims[i].1 == 1 && outline)
        .expect("run")];
    assert_eq!(source, "compass");
    assert!(spread > 0.0 && spread < 20.0, "{spread}");
}

#[test]
#[allow(clippy::print_stderr)]
fn five_walks_that_stay_indoors_improve_with_merged_maps() {
    let (mut first, mut fifth, mut gps) = (0.0, 0.0, 0.0);
    let seeds: Vec<u64> = (31..=36).collect();
    for &seed in &seeds {
        let sim = simulate(seed, 5, 3, true, false);
        let (alone, sequence) = five_walks_of(&sim, seed);
        let mean = alone.iter().sum::<f64>() / 5.0;
        let g = sim.walks.iter().map(|w| w.gps_p95).sum::<f64>() / 5.0;
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
