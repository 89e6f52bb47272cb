//! RF-assisted localisation (Woodman & Harle 2009, sec. 6) on the simulated three-floor
//! building: a radio map surveyed on simulated survey walks (`footslam simulate --tour
//! survey`), then random starts localised without it and with it (containment, eqs. 12–13;
//! probabilistic, eq. 14; prior region only) on the same walks with the same seeds.
//!
//! ```sh
//! cargo run --release --example rf_starts -- 20 400 1   # starts, 1.8 Hz steps of walking, survey walks
//! APS=4 cargo run --release --example rf_starts        # 4 access points a floor
//! EVERY_STEP=1 cargo run --release --example rf_starts  # the latest scan at every step
//! DISTANCE=paper cargo run --release --example rf_starts # the paper's ndist (÷ k, not √k)
//! ```

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::eval::rf_localisation::{
    RfComparison, SimulatedSurvey, compare_localisation, radio_map_rms, simulate_survey,
    steps_or_all,
};
use footslam::filter::{RfConfig, RfLocaliser, RfMode, TrackerConfig};
use footslam::model::wifi_distance::Normalisation;
use footslam::sim::{TowerSimConfig, simulate_tower};
use rayon::prelude::*;
use std::time::Instant;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const MODES: [(RfMode, &str); 3] = [
    (RfMode::Containment, "containment"),
    (RfMode::Probabilistic, "probabilistic"),
    (RfMode::PriorOnly, "prior only"),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize| std::env::args().nth(i);
    let starts: u64 = arg(1).map_or(Ok(20), |a| a.parse())?;
    let steps: usize = arg(2).map_or(Ok(400), |a| a.parse())?;
    let surveys: u64 = arg(3).map_or(Ok(1), |a| a.parse())?;
    let mut base = TowerSimConfig::default();
    if let Ok(v) = std::env::var("APS") {
        base.wifi.aps_per_floor = v.parse()?;
    }
    // SURVEY_SEED / START_SEED: first seed of the survey walks (1000) and of the starts (1).
    let env_seed = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (survey_seed, start_seed) = (env_seed("SURVEY_SEED", 1000), env_seed("START_SEED", 1));
    let started = Instant::now();
    let SimulatedSurvey {
        tours: sims,
        topology,
        cells,
        map,
    } = simulate_survey(&base, survey_seed, surveys)?;
    let (coverage, scans) = map.coverage();
    let (rms, pairs) = radio_map_rms(&map, &cells, &topology, &sims[0].radio, 0.5, 3);
    let walk_s: f64 = sims
        .iter()
        .map(|s| s.truth.poses.last().map_or(0.0, |p| p.t))
        .sum();
    println!(
        "survey: {:.1} min of walking, coverage {:.1} %, {scans:.1} scans a covered cell, RMS {rms:.2} dB over {pairs} cell/AP pairs, epsilon {:.2} dBm (paper's distance), {:.2} dBm (÷ √k)",
        walk_s / 60.0,
        100.0 * coverage,
        map.epsilon.unwrap_or(f64::NAN),
        map.epsilon_sqrt.unwrap_or(f64::NAN)
    );
    // DISTANCE=paper|sqrt, by the config's own names.
    let distance: Option<Normalisation> = std::env::var("DISTANCE")
        .ok()
        .map(|v| serde_json::from_value(serde_json::Value::String(v)))
        .transpose()?;
    let localisers = MODES
        .iter()
        .map(|&(mode, _)| {
            RfLocaliser::new(
                &map,
                &topology,
                &RfConfig {
                    mode,
                    likelihood: footslam::model::wifi_likelihood::LikelihoodConfig {
                        exponent: std::env::var("EXPONENT").ok().and_then(|v| v.parse().ok()),
                        ..Default::default()
                    },
                    // EVERY_STEP=1: the latest scan at every step, where the particles are then.
                    every_step: std::env::var("EVERY_STEP").is_ok(),
                    distance,
                    ..Default::default()
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let rfs: Vec<&RfLocaliser> = localisers.iter().collect();
    let minutes = steps as f64 / 1.8 / 60.0;
    let results: Vec<(u64, RfComparison)> = (start_seed..start_seed + starts)
        .into_par_iter()
        .map(|seed| {
            let mut config = TowerSimConfig { seed, ..base };
            config.walk.minutes = minutes;
            let sim = simulate_tower(&config).map_err(|e| e.to_string())?;
            let tracker = TrackerConfig {
                seed,
                ..Default::default()
            };
            let c =
                compare_localisation(&sim, &topology, &rfs, &tracker).map_err(|e| e.to_string())?;
            Ok((seed, c))
        })
        .collect::<Result<_, String>>()?;
    let show = |s: Option<usize>| s.map_or("never".to_string(), |s| s.to_string());
    println!(
        "seed  steps  plain(n0, steps)  rf n0  containment  probabilistic  prior-only   (* = first fix > 3 m off, ! = lost)"
    );
    for (seed, c) in &results {
        let runs: Vec<String> =
            c.rf.iter()
                .map(|r| {
                    format!(
                        "{:>5}{}{}",
                        show(r.score.steps_to_localise),
                        if r.first_fix_wrong() { "*" } else { " " },
                        if r.lost() { "!" } else { " " }
                    )
                })
                .collect();
        println!(
            "{seed:>4} {:>6} {:>9} {:>7} {:>6}   {}",
            c.steps,
            c.plain_initial,
            c.rf[0].initial.unwrap_or(0),
            show(c.plain.steps_to_localise),
            runs.join("        ")
        );
    }
    let k = results.len().max(1) as f64;
    let mean =
        |f: &dyn Fn(&RfComparison) -> f64| results.iter().map(|(_, c)| f(c)).sum::<f64>() / k;
    let plain_steps = mean(&|c| steps_or_all(&c.plain, c.steps) as f64);
    let plain_n0 = mean(&|c| c.plain_initial as f64);
    let plain_p50 = mean(&|c| c.plain.errors.as_ref().map_or(f64::NAN, |e| e.p50));
    println!(
        "without the radio map: mean {plain_steps:.1} steps to localise, mean p50 error after {plain_p50:.2} m, prior {plain_n0:.0} particles"
    );
    for (m, &(_, name)) in MODES.iter().enumerate() {
        let rf_steps = mean(&|c| steps_or_all(&c.rf[m].score, c.steps) as f64);
        let n0 = mean(&|c| c.rf[m].initial.unwrap_or(0) as f64);
        let p50 = mean(&|c| c.rf[m].score.errors.as_ref().map_or(f64::NAN, |e| e.p50));
        let wrong = results
            .iter()
            .filter(|(_, c)| c.rf[m].first_fix_wrong())
            .count();
        let lost = results.iter().filter(|(_, c)| c.rf[m].lost()).count();
        println!(
            "{name:>13}: mean {rf_steps:.1} steps ({:.2} of without), first fix > 3 m off {wrong}/{}, lost {lost}/{}, mean p50 error after {p50:.2} m, prior {n0:.0} particles ({:.1}× fewer)",
            rf_steps / plain_steps,
            results.len(),
            results.len(),
            plain_n0 / n0.max(1.0)
        );
    }
    println!("{:.1} s", started.elapsed().as_secs_f64());
    Ok(())
}
