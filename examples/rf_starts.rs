//! RF-assisted localisation (Woodman & Harle 2009, sec. 6) on the simulated three-floor
//! building: a radio map surveyed on one simulated survey walk, then many random starts
//! localised with and without it on the same walks.
//!
//! ```sh
//! cargo run --release --example rf_starts -- 20 400 containment   # starts, steps, mode
//! ```

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::eval::rf_localisation::{
    RfComparison, compare_localisation, radio_map_rms, survey_simulation,
};
use footslam::filter::{RfConfig, RfLocaliser, RfMode, TrackerConfig};
use footslam::map::{CellMap, FloorTopology, TopologyConfig};
use footslam::sim::{TourKind, TowerSimConfig, simulate_tower};
use rayon::prelude::*;
use std::time::Instant;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize| std::env::args().nth(i);
    let starts: u64 = arg(1).map_or(Ok(20), |a| a.parse())?;
    let steps: usize = arg(2).map_or(Ok(400), |a| a.parse())?;
    let mode = match arg(3).as_deref() {
        None | Some("containment") => RfMode::Containment,
        Some("probabilistic") => RfMode::Probabilistic,
        Some("prior") => RfMode::PriorOnly,
        Some(other) => return Err(format!("unknown mode {other}").into()),
    };
    let mut rf_outside = 0.0;
    let mut base = TowerSimConfig::default();
    if let Ok(v) = std::env::var("APS") {
        base.wifi.aps_per_floor = v.parse()?;
    }
    if let Ok(v) = std::env::var("OUTSIDE") {
        rf_outside = v.parse()?;
    }
    let mut survey = TowerSimConfig { seed: 1000, ..base };
    survey.walk.tour = TourKind::Survey;
    survey.walk.minutes = 30.0;
    let started = Instant::now();
    let sim = simulate_tower(&survey)?;
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default())?;
    let cells = CellMap::build(&sim.plan, &topology, &Default::default())?;
    let tracker = TrackerConfig::default();
    let map = survey_simulation(&sim, &topology, &cells, &tracker, -96.0, 0.001)?;
    let (coverage, scans) = map.coverage();
    let (rms, pairs) = radio_map_rms(&map, &cells, &topology, &sim.radio, 0.5, 3);
    let walk_s = sim.truth.poses.last().map_or(0.0, |p| p.t);
    println!(
        "survey: {:.1} min walk, coverage {:.1} %, {scans:.1} scans a cell, RMS {rms:.2} dB over {pairs} pairs ({:.1} s)",
        walk_s / 60.0,
        100.0 * coverage,
        started.elapsed().as_secs_f64()
    );
    let rf_config = RfConfig {
        mode,
        outside_weight: rf_outside,
        ..Default::default()
    };
    let rf = RfLocaliser::new(&map, &topology, &rf_config)?;
    println!("epsilon {:.2} dBm", rf.epsilon());
    let minutes = steps as f64 / 1.8 / 60.0;
    let results: Vec<(u64, RfComparison)> = (1..=starts)
        .into_par_iter()
        .map(|seed| {
            let mut config = TowerSimConfig { seed, ..base };
            config.walk.minutes = minutes;
            let sim = simulate_tower(&config).map_err(|e| e.to_string())?;
            let tracker = TrackerConfig {
                seed,
                ..Default::default()
            };
            let c = compare_localisation(&sim, &topology, &rf, &tracker)
                .map_err(|e| e.to_string())?;
            Ok((seed, c))
        })
        .collect::<Result<_, String>>()?;
    println!(
        "{:>4} {:>6} {:>9} {:>7} {:>6} {:>9} {:>7} {:>6}",
        "seed", "steps", "plain n0", "plain", "right", "rf n0", "rf", "right"
    );
    let (mut plain, mut with, mut fails, mut n_plain, mut n_rf) = (0, 0, 0, 0.0, 0.0);
    for (seed, c) in &results {
        let show = |s: Option<usize>| s.map_or("never".to_string(), |s| s.to_string());
        println!(
            "{seed:>4} {:>6} {:>9} {:>7} {:>6} {:>9} {:>7} {:>6}",
            c.steps,
            c.plain_initial,
            show(c.plain.steps_to_localise),
            c.plain.right_cluster,
            c.rf_initial.unwrap_or(0),
            show(c.rf.steps_to_localise),
            c.rf.right_cluster
        );
        if std::env::var("DETAIL").is_ok() {
            println!("      rf errors {:?} floor {:?} deaths {}", c.rf.errors.as_ref().map(|e| (e.p50, e.p95, e.max)), c.rf.floor_accuracy, c.rf.deaths);
        }
        plain += RfComparison::steps_or_all(&c.plain, c.steps);
        with += RfComparison::steps_or_all(&c.rf, c.steps);
        fails += usize::from(c.rf_failed());
        n_plain += c.plain_initial as f64;
        n_rf += c.rf_initial.unwrap_or(0) as f64;
    }
    let k = results.len().max(1) as f64;
    println!(
        "mode {mode:?}: mean steps to localise {:.1} without, {:.1} with (ratio {:.2}); RF failures {fails}/{}; mean prior {:.0} vs {:.0} particles ({:.1}× fewer); {:.1} s",
        plain as f64 / k,
        with as f64 / k,
        with as f64 / plain.max(1) as f64,
        results.len(),
        n_plain / k,
        n_rf / k,
        n_plain / n_rf.max(1.0),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
