//! Known-map tracking from unknown starts on the simulated three-floor building: steps to
//! localise, whether that was the right place, tracking error and floor accuracy afterwards,
//! for many seeds, on floors that differ and on identical floors.
//!
//! ```sh
//! cargo run --release --example track_starts -- 10 [1.04 [differ|identical]]   # seeds 1..=10
//! ```

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::eval::score_tracking;
use footslam::filter::{Tracker, TrackerConfig};
use footslam::map::{FloorTopology, TopologyConfig};
use footslam::sim::{TowerSimConfig, floor_resolved_at, simulate_tower};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: u64 = std::env::args()
        .nth(1)
        .map_or(Ok(10), |a| a.parse())
        .map_err(|e| format!("seeds: {e}"))?;
    // Step lengths off by this factor for the whole walk: too long on even seeds, as much
    // too short on odd ones (as `tests/accuracy/track_accuracy.rs`).
    let scale: f64 = std::env::args()
        .nth(2)
        .map_or(Ok(1.04), |a| a.parse())
        .map_err(|e| format!("length scale: {e}"))?;
    let buildings: Vec<bool> = match std::env::args().nth(3).as_deref() {
        Some("differ") => vec![false],
        Some("identical") => vec![true],
        _ => vec![false, true],
    };
    println!(
        "{:<10} {:>4} {:>7} {:>8} {:>6} {:>7} {:>7} {:>6} {:>7} {:>6}",
        "floors",
        "seed",
        "steps",
        "resolved",
        "local",
        "right",
        "p95 m",
        "max m",
        "floor%",
        "deaths"
    );
    for identical in buildings {
        let mut localise = Vec::new();
        let mut p95s = Vec::new();
        for seed in 1..=n {
            let mut config = TowerSimConfig {
                seed,
                ..Default::default()
            };
            config.building.identical_floors = identical;
            config.noise.length_scale = if seed % 2 == 0 { scale } else { 2.0 - scale };
            let sim = simulate_tower(&config)?;
            let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default())?;
            let mut tracker_config = TrackerConfig {
                seed,
                ..Default::default()
            };
            if let Ok(v) = std::env::var("SIGMA_L") {
                tracker_config.length_sigma = v.parse()?;
            }
            if let Ok(v) = std::env::var("MINP") {
                tracker_config.kld.min_particles = v.parse()?;
            }
            let mut tracker = Tracker::new(&topology, &tracker_config)?;
            let reports: Vec<_> = sim
                .steps
                .steps()
                .iter()
                .map(|s| tracker.update(s))
                .collect::<Result<_, _>>()?;
            let score = score_tracking(&sim.truth.poses, &reports);
            let resolved = floor_resolved_at(&sim.start, &sim.truth, topology.levels());
            let e = score.errors.as_ref();
            println!(
                "{:<10} {:>4} {:>7} {:>8} {:>6} {:>7} {:>7.3} {:>6.2} {:>7.1} {:>6}",
                if identical { "identical" } else { "differ" },
                seed,
                sim.steps.len(),
                resolved.map_or("-".into(), |r| (r + 1).to_string()),
                score
                    .steps_to_localise
                    .map_or("never".into(), |s| s.to_string()),
                score.right_cluster,
                e.map_or(f64::NAN, |e| e.p95),
                e.map_or(f64::NAN, |e| e.max),
                100.0 * score.floor_accuracy.unwrap_or(f64::NAN),
                score.deaths
            );
            localise.push(score.steps_to_localise.unwrap_or(usize::MAX));
            p95s.push(e.map_or(f64::INFINITY, |e| e.p95));
        }
        let finite: Vec<f64> = localise
            .iter()
            .filter(|&&s| s != usize::MAX)
            .map(|&s| s as f64)
            .collect();
        println!(
            "  mean steps to localise {:.1}, worst {}; mean p95 {:.3} m, worst {:.3} m",
            finite.iter().sum::<f64>() / finite.len().max(1) as f64,
            localise.iter().max().copied().unwrap_or(0),
            p95s.iter().sum::<f64>() / p95s.len().max(1) as f64,
            p95s.iter().copied().fold(0.0, f64::max)
        );
    }
    Ok(())
}
