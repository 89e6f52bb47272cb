//! Radio survey while tracking (Woodman & Harle 2009, sec. 4): once the tracker has localised
//! the walker, each WiFi scan is added, once, to the radio-map cell of the position estimated
//! at the first step after the scan ("the most recent scan to have been completed since the
//! last position update, if one exists").

use super::path_tree::SmoothedStep;
use super::tracker::{TrackStep, Tracker};
use crate::error::{Error, Result};
use crate::geometry::Pose2;
use crate::map::{CellConfig, CellMap, FloorPlan, FloorTopology, RadioMap, TopologyConfig};
use crate::model::wifi_distance::{HeldOut, Normalisation, calibrate_epsilon, leave_one_out_ndist};
use crate::sensor::{Step, WifiScan};

/// What one survey pass added.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SurveyCounts {
    /// Scans added to a cell.
    pub added: usize,
    /// Scans from localisation on whose step had no estimate or no cell.
    pub skipped: usize,
}

/// Where a walk's scans went: `(scan index, cell)` per scan added after localisation.
pub type Assignments = Vec<(usize, Option<usize>)>;

/// For each scan of `scans` (in time order) completed after the first localised step of
/// `reports`, the first step at or after it: `(scan index, cell)`, the cell being that of
/// the step's estimate (its surface found on the estimate's level, nearest its height), or
/// `None` when the step has no estimate or it is in no cell.
#[must_use]
pub fn survey_assignments(
    cells: &CellMap,
    topology: &FloorTopology,
    reports: &[TrackStep],
    scans: &[WifiScan],
) -> Assignments {
    let Some(first) = reports.iter().position(|r| r.localised) else {
        return Vec::new();
    };
    let placed: Vec<PlacedStep> = reports[first..]
        .iter()
        .map(|r| PlacedStep {
            t: r.t,
            cell: r.estimate.and_then(|c| {
                let surface = topology.locate(c.x, c.y, Some(c.level), Some(c.z))?;
                cells.cell_at(surface, c.x, c.y)
            }),
        })
        .collect();
    assign_scans(&placed, scans)
}

/// A step whose place is known, and the radio-map cell it is in (`None`: no cell).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedStep {
    /// Time of the step, seconds.
    pub t: f64,
    /// The cell of the step's position.
    pub cell: Option<usize>,
}

/// One step of a known path: `(t, x, y, level)`.
pub type PathPoint = (f64, f64, f64, i32);

/// The [`PathPoint`]s of a walk whose poses after each step are known (FootSLAM's most
/// probable path: one pose per step of `steps`), all on `level`.
#[must_use]
pub fn path_points(steps: &[Step], poses: &[Pose2], level: i32) -> Vec<PathPoint> {
    steps
        .iter()
        .zip(poses)
        .map(|(s, p)| (s.t, p.x, p.y, level))
        .collect()
}

/// The steps of a walk whose whole path is known — FootSLAM's most probable path, in its
/// learned map's frame (`learn --wifi`) — each with the cell of `cells` it lies in:
/// `path` holds `(t, x, y, level)` per step.
pub fn path_steps(
    cells: &CellMap,
    topology: &FloorTopology,
    path: impl IntoIterator<Item = PathPoint>,
) -> Vec<PlacedStep> {
    path.into_iter()
        .map(|(t, x, y, level)| PlacedStep {
            t,
            cell: topology
                .locate(x, y, Some(level), None)
                .and_then(|s| cells.cell_at(s, x, y)),
        })
        .collect()
}

/// For each scan of `scans` (in time order) completed after the first step of `steps` —
/// the walk's steps from the first one whose place is known — the cell of the first step
/// at or after it: `(scan index, cell)`. Several scans between two steps: the most recent
/// one counts; scans completed by the first step belong to the time before it, except the
/// latest of them (the most recent scan at that update).
#[must_use]
pub fn assign_scans(steps: &[PlacedStep], scans: &[WifiScan]) -> Assignments {
    let Some(first) = steps.first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut next = scans.partition_point(|s| s.t <= first.t).saturating_sub(1);
    for step in steps {
        let mut latest = None;
        while next < scans.len() && scans[next].t <= step.t {
            latest = Some(next);
            next += 1;
        }
        if let Some(i) = latest {
            out.push((i, step.cell));
        }
    }
    out
}

/// The whole-walk placement of a run for [`survey_assignments`]: each step of `reports` with
/// its smoothed answer (`smoothed`, one per step) as the estimate where the whole walk makes
/// the place certain (then `localised`), and no estimate where it leaves several hypotheses —
/// so every scan whose place the walk settles is placed, those before the filter's first fix
/// included, and an ambiguous one is left out, not guessed.
#[must_use]
pub fn whole_walk_reports(reports: &[TrackStep], smoothed: &[SmoothedStep]) -> Vec<TrackStep> {
    reports
        .iter()
        .zip(smoothed)
        .map(|(r, s)| TrackStep {
            estimate: s.estimate.filter(|_| s.certain),
            localised: s.certain,
            clusters: Some(s.hypotheses),
            ..r.clone()
        })
        .collect()
}

/// Where a survey places a tracked walk's scans: the whole-walk answer where the tracker
/// keeps its ancestry ([`whole_walk_reports`]), else the filtered `reports`.
#[must_use]
pub fn placed_steps(tracker: &Tracker, reports: Vec<TrackStep>) -> Vec<TrackStep> {
    match tracker.smoothed() {
        Some(smoothed) => whole_walk_reports(&reports, &smoothed[1..]),
        None => reports,
    }
}

/// The share of surveyed scans allowed outside their own cell's region when calibrating a
/// radio map's `ε` ([`calibrate_map`]'s `miss`; the paper's ε gave 0.00028 per step on its
/// building).
pub const EPSILON_MISS: f64 = 0.001;

/// Adds to `map` each scan of `scans` completed after localisation, in the cell of the next
/// step's estimate: `assignments` are the walk's [`survey_assignments`] over `map`'s cells.
pub fn survey_walk(
    map: &mut RadioMap,
    assignments: &Assignments,
    scans: &[WifiScan],
) -> SurveyCounts {
    let mut counts = SurveyCounts::default();
    for &(scan, cell) in assignments {
        match cell {
            Some(c) => {
                map.cells[c].radio.add_scan(&scans[scan]);
                counts.added += 1;
            }
            None => counts.skipped += 1,
        }
    }
    counts
}

/// A radio map surveyed along known paths ([`survey_paths`]).
#[derive(Debug, Clone)]
pub struct PathSurvey {
    /// The plan's rooms and cells.
    pub cells: CellMap,
    /// The radio map, `ε` calibrated.
    pub map: RadioMap,
    /// Per walk: scans added and left out.
    pub counts: Vec<SurveyCounts>,
    /// The held-out distances `ε` was chosen from.
    pub held: Vec<HeldOut>,
}

/// The survey of walks whose paths are known — FootSLAM's most probable paths on the plan
/// learned from their map (`learn --wifi`: no plan drawn by anyone, no tracker): every scan
/// goes to the cell of `plan` of the first step at or after it, and `ε` is calibrated on the
/// walks' own scans as [`calibrate_map`] does (`missing_rssi`, `miss`). `walks` holds per
/// walk its `(t, x, y, level)` per step and its scans in time order.
///
/// # Errors
///
/// As [`FloorTopology::build`] for a plan with an invalid surface or barrier, and as
/// [`CellMap::build`] for an invalid `cells`; [`Error::NotEnough`] when no scan falls in a cell of
/// the plan.
pub fn survey_paths(
    plan: &FloorPlan,
    walks: &[(Vec<PathPoint>, &[WifiScan])],
    cells: &CellConfig,
    missing_rssi: f64,
    miss: f64,
) -> Result<PathSurvey> {
    let topology = FloorTopology::build(plan, &TopologyConfig::default())?;
    let cells = CellMap::build(plan, &topology, cells)?;
    let mut map = RadioMap::empty(&cells);
    let mut calibration: Vec<(Assignments, &[WifiScan])> = Vec::with_capacity(walks.len());
    let mut counts = Vec::with_capacity(walks.len());
    for (path, scans) in walks {
        let placed = path_steps(&cells, &topology, path.iter().copied());
        let assignments = assign_scans(&placed, scans);
        counts.push(survey_walk(&mut map, &assignments, scans));
        calibration.push((assignments, scans));
    }
    if counts.iter().all(|c| c.added == 0) {
        return Err(Error::not_enough(
            "no WiFi scan fell in a cell of the plan: nothing to make a radio map of",
            "",
        ));
    }
    let held = calibrate_map(&mut map, &calibration, missing_rssi, miss);
    Ok(PathSurvey {
        cells,
        map,
        counts,
        held,
    })
}

/// Sets `map.epsilon` and `map.epsilon_sqrt` to the region thresholds `ε` (the paper's
/// distance and the one divided by `√k`) that a share `1 − miss` of the surveyed scans'
/// leave-one-visit-out distances to their own cells fall under (the paper's way of choosing
/// ε, sec. 5.3, on the survey itself): `walks` are each walk's [`survey_assignments`] and
/// scans. Without any distance (e.g. only merged maps) the thresholds are left as they are.
/// Returns the held-out distances.
pub fn calibrate_map(
    map: &mut RadioMap,
    walks: &[(Assignments, &[WifiScan])],
    missing_rssi: f64,
    miss: f64,
) -> Vec<HeldOut> {
    let held: Vec<HeldOut> = walks
        .iter()
        .flat_map(|(assignments, scans)| leave_one_out_ndist(map, assignments, scans, missing_rssi))
        .collect();
    for norm in Normalisation::ALL {
        let d: Vec<f64> = held.iter().map(|h| h.ndist(norm)).collect();
        if let Some(epsilon) = calibrate_epsilon(&d, miss) {
            *norm.epsilon_of_mut(map) = Some(epsilon);
        }
    }
    held
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
            start: Some(StartPose::from(sim.start)),
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
        let assignments = survey_assignments(&cells, &topology, &reports, &sim.wifi);
        let counts = survey_walk(&mut map, &assignments, &sim.wifi);
        assert!(counts.added > sim.wifi.len() * 9 / 10, "{counts:?}");
        assert!(counts.added <= sim.wifi.len());
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
