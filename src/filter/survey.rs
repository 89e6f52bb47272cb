//! Radio survey while tracking (Woodman & Harle 2009, sec. 5): once the tracker has localised
//! the walker, the most recent WiFi scan at each step is added to the radio-map cell the
//! step's estimated position falls in.

use super::tracker::TrackStep;
use crate::map::{CellMap, FloorTopology, RadioMap};
use crate::sensor::WifiScan;

/// What one survey pass added.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SurveyCounts {
    /// Steps whose estimate fell in a cell and had a scan before them.
    pub added: usize,
    /// Steps from localisation on without an estimate, a cell, or an earlier scan.
    pub skipped: usize,
}

/// Adds to `map` (built over `cells`) the most recent scan of `scans` (in time order) at each
/// step of `reports` from the first localised step on, in the cell of the step's estimate
/// (its surface found on the estimate's level, nearest its height).
pub fn survey_walk(
    map: &mut RadioMap,
    cells: &CellMap,
    topology: &FloorTopology,
    reports: &[TrackStep],
    scans: &[WifiScan],
) -> SurveyCounts {
    let mut counts = SurveyCounts::default();
    let Some(first) = reports.iter().position(|r| r.localised) else {
        return counts;
    };
    let mut next_scan = 0; // scans[..next_scan] are at or before the current step
    for r in &reports[first..] {
        while next_scan < scans.len() && scans[next_scan].t <= r.t {
            next_scan += 1;
        }
        let cell = r.estimate.and_then(|c| {
            let surface = topology.locate(c.x, c.y, Some(c.level), Some(c.z))?;
            cells.cell_at(surface, c.x, c.y)
        });
        match (cell, next_scan.checked_sub(1)) {
            (Some(cell), Some(latest)) => {
                map.cells[cell].radio.add_scan(&scans[latest]);
                counts.added += 1;
            }
            _ => counts.skipped += 1,
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::{StartPose, Tracker, TrackerConfig};
    use crate::map::TopologyConfig;
    use crate::sim::{TowerSimConfig, expected_field, simulate_tower};

    #[test]
    fn a_tracked_walk_fills_cells_with_readings_close_to_the_truth() {
        let mut config = TowerSimConfig {
            seed: 4,
            ..Default::default()
        };
        config.walk.minutes = 10.0;
        let sim = simulate_tower(&config).expect("sim");
        let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
        let cells = CellMap::build(&sim.plan, &topology, &Default::default()).expect("cells");
        let tracker_config = TrackerConfig {
            start: Some(StartPose {
                x: sim.start.x,
                y: sim.start.y,
                heading: sim.start.heading,
                level: Some(sim.start.level),
            }),
            ..Default::default()
        };
        let mut tracker = Tracker::new(&topology, &tracker_config).expect("tracker");
        let reports: Vec<TrackStep> = sim
            .steps
            .steps()
            .iter()
            .map(|s| tracker.update(s).expect("step"))
            .collect();
        let mut map = RadioMap::empty(&cells);
        let counts = survey_walk(&mut map, &cells, &topology, &reports, &sim.wifi);
        assert!(counts.added > reports.len() * 9 / 10, "{counts:?}");
        let (share, per_cell) = map.coverage();
        assert!(share > 0.1 && per_cell >= 1.0, "{share} {per_cell}");
        // Mean RSSI per covered cell against the expected field at the cell's points.
        let field = expected_field(&sim.radio, &topology, 1.0);
        let aps = sim.radio.access_points();
        let mut squared = Vec::new();
        for (i, cell) in map.cells.iter().enumerate() {
            for (a, ap) in aps.iter().enumerate() {
                let Some(stats) = cell.radio.aps.get(&ap.bssid) else {
                    continue;
                };
                if stats.n < 8 || cell.radio.misses(&ap.bssid) > 0 {
                    continue; // near the detection floor the mean of heard readings is biased
                }
                let truth: Vec<f64> = field
                    .iter()
                    .filter(|(level, x, y, _)| {
                        topology
                            .locate(*x, *y, Some(*level), None)
                            .and_then(|s| cells.cell_at(s, *x, *y))
                            == Some(i)
                    })
                    .map(|r| r.3[a])
                    .collect();
                if truth.is_empty() {
                    continue;
                }
                let expected = truth.iter().sum::<f64>() / truth.len() as f64;
                let mean = stats.mean().expect("mean");
                squared.push((mean - expected).powi(2));
            }
        }
        assert!(squared.len() > 50, "{} cell/AP pairs", squared.len());
        let rms = (squared.iter().sum::<f64>() / squared.len() as f64).sqrt();
        eprintln!(
            "coverage {share:.3}, {per_cell:.1} scans a cell, RMS {rms:.2} dB over {} pairs",
            squared.len()
        );
        assert!(rms < 4.0, "RMS {rms:.2} dB over {} pairs", squared.len());
    }
}
