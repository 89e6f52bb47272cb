//! probe
#![allow(clippy::print_stdout)]
use footslam::eval::rf_localisation::survey_simulation;
use footslam::filter::{RfConfig, RfLocaliser, TrackerConfig};
use footslam::map::{CellMap, FloorTopology, TopologyConfig};
use footslam::sim::{TourKind, TowerSimConfig, simulate_tower};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut base = TowerSimConfig::default();
    base.wifi.aps_per_floor = 8;
    let mut survey = TowerSimConfig { seed: 1000, ..base };
    survey.walk.tour = TourKind::Survey;
    survey.walk.minutes = 30.0;
    let sim = simulate_tower(&survey)?;
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default())?;
    let cells = CellMap::build(&sim.plan, &topology, &Default::default())?;
    let map = survey_simulation(&sim, &topology, &cells, &TrackerConfig::default(), -96.0, 0.001)?;
    let rf = RfLocaliser::new(&map, &topology, &RfConfig::default())?;
    for seed in [2u64, 3] {
        let mut c = TowerSimConfig { seed, ..base };
        c.walk.minutes = 1.0;
        let s = simulate_tower(&c)?;
        for scan in s.wifi.iter().take(12) {
            let k = s.truth.poses.iter().position(|p| p.t >= scan.t).unwrap_or(0);
            let p = &s.truth.poses[k];
            let f = rf.prior_region(scan);
            let v = f.at(p.level, p.x as f32, p.y as f32);
            let inside = f.values().iter().filter(|v| **v == 0.0).count();
            println!("seed {seed} t {:.1} true ({:.1},{:.1},L{}) value {v} inside {inside}/{}", scan.t, p.x, p.y, p.level, f.values().len());
        }
    }
    Ok(())
}
