//! How much of the building a single scan's region (`ndist < ε`, Woodman & Harle 2009,
//! eqs. 2 and 12) keeps, on the simulated three-floor building: a radio map surveyed on
//! simulated survey walks, then every scan of some test walks (6 minutes each) scored
//! against it — the share of the floor area inside the region (what the prior's particle
//! count is proportional to), the share of it on the walker's own floor, and how often the
//! cell the walker is in at the next step (where a scan is applied) is left out (a miss);
//! then the same at the thresholds that would miss 0.1–5 % of these scans.
//!
//! ```sh
//! cargo run --release --example rf_regions -- 8 2          # test walks, survey walks
//! EPSILON=3.0 cargo run --release --example rf_regions     # another threshold
//! DISTANCE=paper cargo run --release --example rf_regions  # the paper's ndist (÷ k, not √k)
//! WIFI='{"floor_loss":20}' BUILDING='{"corridor_length":80}' cargo run --release --example rf_regions
//! ```

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::eval::rf_localisation::{SimulatedSurvey, simulate_survey};
use footslam::filter::{RfConfig, RfLocaliser};
use footslam::model::wifi_distance::Normalisation;
use footslam::sim::{TowerSimConfig, simulate_tower};
use geo::Area;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize| std::env::args().nth(i);
    let walks: u64 = arg(1).map_or(Ok(5), |a| a.parse())?;
    let surveys: u64 = arg(2).map_or(Ok(1), |a| a.parse())?;
    let mut base = TowerSimConfig::default();
    if let Ok(v) = std::env::var("WIFI") {
        base.wifi = serde_json::from_str(&v)?;
    }
    if let Ok(v) = std::env::var("BUILDING") {
        base.building = serde_json::from_str(&v)?;
    }
    let SimulatedSurvey {
        tours: sims,
        topology,
        cells,
        map,
    } = simulate_survey(&base, 1000, surveys)?;
    let epsilon = std::env::var("EPSILON").ok().and_then(|v| v.parse().ok());
    // DISTANCE=paper|sqrt, by the config's own names.
    let distance: Option<Normalisation> = std::env::var("DISTANCE")
        .ok()
        .map(|v| serde_json::from_value(serde_json::Value::String(v)))
        .transpose()?;
    let rf = RfLocaliser::new(
        &map,
        &topology,
        &RfConfig {
            epsilon,
            distance,
            ..Default::default()
        },
    )?;
    let areas: Vec<f64> = map.cells.iter().map(|c| c.area.unsigned_area()).collect();
    let total: f64 = areas.iter().sum();
    let share = |inside: &dyn Fn(usize) -> bool| {
        (0..areas.len())
            .filter(|&c| inside(c))
            .map(|c| areas[c])
            .sum::<f64>()
            / total
    };
    let (mut heard, mut misses, mut own_floor) = (0usize, 0usize, 0.0);
    let mut shares = Vec::new();
    let mut own_d: Vec<f64> = Vec::new();
    let mut all_d: Vec<Vec<Option<f64>>> = Vec::new();
    for seed in 1..=walks {
        let mut config = TowerSimConfig { seed, ..base };
        config.walk.minutes = 6.0;
        let sim = simulate_tower(&config)?;
        let poses = &sim.truth.poses;
        for scan in &sim.wifi {
            // The walker at the first step after the scan, where the tracker applies it.
            let Some(pose) = poses.get(poses.partition_point(|p| p.t < scan.t)) else {
                continue;
            };
            let Some(own) = topology
                .locate(pose.x, pose.y, Some(pose.level), None)
                .and_then(|s| cells.cell_at(s, pose.x, pose.y))
            else {
                continue;
            };
            heard += scan.readings.len();
            // The region of eqs. 2 and 12 (`RfLocaliser::in_region`), from the distances.
            let d = rf.ndist(scan);
            let inside: Vec<bool> = d
                .iter()
                .map(|d| d.is_none_or(|d| d < rf.epsilon()))
                .collect();
            let region = share(&|c| inside[c]);
            own_floor += share(&|c| inside[c] && map.cells[c].level == pose.level) / region;
            misses += usize::from(!inside[own]);
            shares.push(region);
            own_d.push(d[own].unwrap_or(0.0));
            all_d.push(d);
        }
    }
    let n = shares.len().max(1) as f64;
    let mean: f64 = shares.iter().sum::<f64>() / n;
    shares.sort_by(f64::total_cmp);
    println!(
        "{} APs, {:.1} heard a scan; {} distance, epsilon {:.2}; {} scans: region mean {:.1} % of the area ({:.1}× fewer particles), median {:.1} %, p90 {:.1} %; {:.0} % of it on the walker's floor; own cell missed {misses} ({:.2} %)",
        sims[0].radio.access_points().len(),
        heard as f64 / n,
        rf.distance().name(),
        rf.epsilon(),
        shares.len(),
        100.0 * mean,
        1.0 / mean,
        100.0 * shares[shares.len() / 2],
        100.0 * shares[shares.len() * 9 / 10],
        100.0 * own_floor / n,
        100.0 * misses as f64 / n
    );
    own_d.sort_by(f64::total_cmp);
    for miss in [0.001, 0.005, 0.01, 0.02, 0.05] {
        let rank = ((1.0 - miss) * own_d.len() as f64).ceil() as usize;
        let e = own_d[rank.clamp(1, own_d.len()) - 1] * 1.001;
        let region = all_d
            .iter()
            .map(|d| share(&|c| d[c].is_none_or(|d| d < e)))
            .sum::<f64>()
            / n;
        println!(
            "missing {:.1} % of these scans: epsilon {e:.2}, region {:.1} % ({:.1}×)",
            100.0 * miss,
            100.0 * region,
            1.0 / region
        );
    }
    Ok(())
}
