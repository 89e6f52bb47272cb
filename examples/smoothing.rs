//! Filtered against smoothed (whole-walk) tracking on simulated three-floor buildings from
//! unknown starts, on seeds the tests do not use (a held-out set): per walk, the p95 error
//! after the first fix of the filtered estimate and of the smoothed answer's certain steps,
//! the certain steps before the fix, certain steps > 3 m off, and the run time with and
//! without the ancestry.
//!
//! `cargo run --release --example smoothing [FIRST_SEED] [LAST_SEED]` (default 11 20).

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::eval::{score_smoothed, score_tracking};
use footslam::filter::{Tracker, TrackerConfig};
use footslam::map::{FloorTopology, TopologyConfig};
use footslam::sim::{TowerSimConfig, simulate_tower};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: u64| -> Result<u64, Box<dyn std::error::Error>> {
        Ok(std::env::args()
            .nth(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let (first, last) = (arg(1, 11)?, arg(2, 20)?);
    println!(
        "building   seed  p95 filtered  p95 smoothed  certain before fix  wrong  time online  time smoothed"
    );
    let mut worst = 0.0f64;
    for identical in [false, true] {
        for seed in first..=last {
            let mut config = TowerSimConfig {
                seed,
                ..Default::default()
            };
            config.building.identical_floors = identical;
            config.noise.length_scale = if seed % 2 == 0 { 1.04 } else { 0.96 };
            let sim = simulate_tower(&config)?;
            let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default())?;
            let run = |smoothing: bool| -> footslam::Result<_> {
                let started = Instant::now();
                let config = TrackerConfig {
                    seed,
                    smoothing,
                    ..Default::default()
                };
                let mut tracker = Tracker::new(&topology, &config)?;
                let reports = sim
                    .steps
                    .steps()
                    .iter()
                    .map(|s| tracker.update(s))
                    .collect::<footslam::Result<Vec<_>>>()?;
                let smoothed = tracker.smoothed();
                Ok((reports, smoothed, started.elapsed().as_secs_f64()))
            };
            let (_, _, online_s) = run(false)?;
            let (reports, smoothed, smoothed_s) = run(true)?;
            let smoothed: Vec<_> = smoothed.unwrap_or_default().into_iter().skip(1).collect();
            let filtered = score_tracking(&sim.truth.poses, &reports);
            let whole = score_smoothed(&sim.truth.poses, &reports, &smoothed);
            let p95 = |e: Option<&footslam::eval::ErrorReport>| e.map_or(f64::NAN, |e| e.p95);
            worst = worst.max(p95(whole.errors_after_fix.as_ref()));
            println!(
                "{:<9} {seed:>5}  {:>10.3} m  {:>10.3} m  {:>18}  {:>5}  {:>9.2} s  {:>11.2} s",
                if identical { "identical" } else { "differ" },
                p95(filtered.errors.as_ref()),
                p95(whole.errors_after_fix.as_ref()),
                whole.certain_before_fix,
                whole.certain_wrong,
                online_s,
                smoothed_s
            );
        }
    }
    println!("worst smoothed p95 after the fix: {worst:.3} m");
    Ok(())
}
