//! Scoring RF-assisted localisation against localisation without a radio map on the same
//! simulated walks (Woodman & Harle 2009, sec. 6), and scoring a surveyed radio map against
//! the simulator's expected RSSI field.

use super::tracking::{TrackingScore, score_tracking};
use crate::error::Result;
use crate::filter::{RfLocaliser, RfTracker, StartPose, TrackStep, Tracker, TrackerConfig};
use crate::filter::{calibrate_map, placed_steps, survey_assignments, survey_walk};
use crate::geometry::RigidTransform;
use crate::map::TopologyConfig;
use crate::map::{CellMap, FloorTopology, RadioMap};
use crate::sensor::Step;
use crate::sim::{
    RadioWorld, TourKind, TowerSimConfig, TowerSimulation, expected_field, simulate_tower,
};
use serde::Serialize;

/// One walk localised with and without the radio map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RfComparison {
    /// Steps of the walk.
    pub steps: usize,
    /// Without the radio map: uniform prior, steps only.
    pub plain: TrackingScore,
    /// Particles of the uniform prior.
    pub plain_initial: usize,
    /// With the radio map, one run per localiser asked for.
    pub rf: Vec<RfRun>,
}

/// One localisation with a radio map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RfRun {
    /// Its score.
    pub score: TrackingScore,
    /// Particles of the prior drawn in `R_prior` (`None` if no scan came).
    pub initial: Option<usize>,
}

impl RfRun {
    /// The run lost the walker: never localised, or the track from the first single cluster
    /// on is not the walker's (median error over 1 m, or on the right floor less than 95 %
    /// of the time) — the true hypothesis did not survive.
    #[must_use]
    pub fn lost(&self) -> bool {
        let s = &self.score;
        s.steps_to_localise.is_none()
            || s.errors.as_ref().is_none_or(|e| e.p50 > 1.0)
            || s.floor_accuracy.is_none_or(|f| f < 0.95)
    }

    /// The first single cluster was not the right place (farther than 3 m or on another
    /// floor; [`TrackingScore::right_cluster`]), or never came.
    #[must_use]
    pub fn first_fix_wrong(&self) -> bool {
        self.score.steps_to_localise.is_none() || !self.score.right_cluster
    }
}

/// Steps to localise, counting a walk never localised as all its steps (a lower bound).
#[must_use]
pub fn steps_or_all(score: &TrackingScore, steps: usize) -> usize {
    score.steps_to_localise.unwrap_or(steps)
}

/// A simulated building surveyed: its survey tours, the plan's topology and radio cells
/// (default granularity), and the radio map surveyed on the tours.
#[derive(Debug, Clone)]
pub struct SimulatedSurvey {
    /// The survey tours.
    pub tours: Vec<TowerSimulation>,
    /// The building's topology.
    pub topology: FloorTopology,
    /// Its radio cells.
    pub cells: CellMap,
    /// The radio map, calibrated (ε missing 0.1 % of the tours' scans, missing readings at
    /// −96 dBm).
    pub map: RadioMap,
}

/// Simulates `count` 30-minute survey tours (`TourKind::Survey`) of `base`'s building with
/// seeds `first_seed..`, and surveys them from their known starts with the default tracker.
///
/// # Errors
///
/// As [`simulate_tower`] for `base` (a section out of range, or a preset's layout bug), and as
/// [`survey_simulations`] on the tours.
pub fn simulate_survey(
    base: &TowerSimConfig,
    first_seed: u64,
    count: u64,
) -> Result<SimulatedSurvey> {
    let tours = (first_seed..first_seed + count.max(1))
        .map(|seed| {
            let mut survey = TowerSimConfig { seed, ..*base };
            survey.walk.tour = TourKind::Survey;
            survey.walk.minutes = 30.0;
            simulate_tower(&survey)
        })
        .collect::<Result<Vec<_>>>()?;
    let plan = &tours[0].plan;
    let topology = FloorTopology::build(plan, &TopologyConfig::default())?;
    let cells = CellMap::build(plan, &topology, &Default::default())?;
    let map = survey_simulations(
        &tours,
        &topology,
        &cells,
        &TrackerConfig::default(),
        -96.0,
        0.001,
    )?;
    Ok(SimulatedSurvey {
        tours,
        topology,
        cells,
        map,
    })
}

/// Tracks each of `sims` (walks of one building) from its known start, surveys their scans
/// into one map over `cells` and calibrates the map's thresholds (`epsilon`,
/// `epsilon_sqrt`) on all of them for a per-scan miss rate `miss` (missing readings at
/// `missing_rssi`).
///
/// # Errors
///
/// As [`Tracker::new`] with each walk's known start: `config` out of range, or a start that is not
/// on `topology`'s plan (a walk of another building).
pub fn survey_simulations(
    sims: &[TowerSimulation],
    topology: &FloorTopology,
    cells: &CellMap,
    config: &TrackerConfig,
    missing_rssi: f64,
    miss: f64,
) -> Result<RadioMap> {
    let mut map = RadioMap::empty(cells);
    let mut walks = Vec::with_capacity(sims.len());
    for sim in sims {
        let config = TrackerConfig {
            start: Some(StartPose::from(sim.start)),
            ..config.clone()
        };
        let mut tracker = Tracker::new(topology, &config)?;
        let reports = track_walk(sim, |s| tracker.update(s))?;
        let reports = placed_steps(&tracker, reports);
        let assignments = survey_assignments(cells, topology, &reports, &sim.wifi);
        survey_walk(&mut map, &assignments, &sim.wifi);
        walks.push((assignments, sim.wifi.as_slice()));
    }
    calibrate_map(&mut map, &walks, missing_rssi, miss);
    Ok(map)
}

/// Localises `sim`'s walk from an unknown start with one seed: without the radio map, and
/// with each of `rfs`.
///
/// # Errors
///
/// As [`Tracker::new`] and [`RfTracker::new`]: `config` out of range, or a plan with no walkable
/// surface; or as [`RfTracker::update`] when the tracker started by the first scan cannot place a
/// particle.
pub fn compare_localisation(
    sim: &TowerSimulation,
    topology: &FloorTopology,
    rfs: &[&RfLocaliser],
    config: &TrackerConfig,
) -> Result<RfComparison> {
    let config = TrackerConfig {
        start: None,
        ..config.clone()
    };
    let mut plain = Tracker::new(topology, &config)?;
    let plain_initial = plain.initial_particles();
    let reports = track_walk(sim, |s| plain.update(s))?;
    let plain_score = score_tracking(&sim.truth.poses, &reports);
    drop(plain);
    let mut rf = Vec::with_capacity(rfs.len());
    for localiser in rfs {
        let mut tracker = RfTracker::new(topology, &config, localiser, &sim.wifi)?;
        let reports = track_walk(sim, |s| tracker.update(s))?;
        rf.push(RfRun {
            score: score_tracking(&sim.truth.poses, &reports),
            initial: tracker.initial_particles(),
        });
    }
    Ok(RfComparison {
        steps: sim.steps.len(),
        plain: plain_score,
        plain_initial,
        rf,
    })
}

/// One report per step of `sim`'s walk from `update`.
fn track_walk(
    sim: &TowerSimulation,
    update: impl FnMut(&Step) -> Result<TrackStep>,
) -> Result<Vec<TrackStep>> {
    sim.steps.steps().iter().map(update).collect()
}

/// RMS difference, dB, between each cell's mean RSSI and the expected field averaged over
/// the cell's points of a `spacing` grid, over the (cell, access point) pairs with at least
/// `min_readings` readings and no misses (near the detection floor the mean of the readings
/// heard is biased upwards); with the number of pairs.
#[must_use]
pub fn radio_map_rms(
    map: &RadioMap,
    cells: &CellMap,
    topology: &FloorTopology,
    world: &RadioWorld,
    spacing: f64,
    min_readings: u32,
) -> (f64, usize) {
    radio_map_rms_in(
        map,
        cells,
        topology,
        world,
        topology,
        None,
        spacing,
        min_readings,
    )
}

/// [`radio_map_rms`] of a map in another frame — one cut from a learned plan
/// (`map_topology`, the learned plan's), with the truth's `topology` giving the field's
/// points — that `to_map` (e.g. the inverse of a track's rigid alignment) moves the truth's
/// points into; the levels are the truth's.
#[allow(clippy::too_many_arguments)]
#[must_use]
pub fn radio_map_rms_in(
    map: &RadioMap,
    cells: &CellMap,
    map_topology: &FloorTopology,
    world: &RadioWorld,
    topology: &FloorTopology,
    to_map: Option<&RigidTransform>,
    spacing: f64,
    min_readings: u32,
) -> (f64, usize) {
    let field = expected_field(world, topology, spacing);
    let mut points = vec![0usize; map.cells.len()];
    let mut per_cell: Vec<Vec<f64>> = vec![vec![0.0; world.access_points().len()]; map.cells.len()];
    for (level, x, y, rssi) in &field {
        let (x, y) = to_map.map_or((*x, *y), |t| t.apply((*x, *y)));
        let Some(c) = map_topology
            .locate(x, y, Some(*level), None)
            .and_then(|s| cells.cell_at(s, x, y))
        else {
            continue;
        };
        points[c] += 1;
        for (acc, r) in per_cell[c].iter_mut().zip(rssi) {
            *acc += r;
        }
    }
    let mut squared = 0.0;
    let mut pairs = 0;
    for (c, cell) in map.cells.iter().enumerate() {
        if points[c] == 0 {
            continue;
        }
        for (a, ap) in world.access_points().iter().enumerate() {
            let Some(stats) = cell.radio.aps.get(&ap.bssid) else {
                continue;
            };
            if stats.n < min_readings || cell.radio.misses(&ap.bssid) > 0 {
                continue;
            }
            let Some(mean) = stats.mean() else { continue };
            let expected = per_cell[c][a] / points[c] as f64;
            squared += (mean - expected).powi(2);
            pairs += 1;
        }
    }
    let rms = if pairs > 0 {
        (squared / pairs as f64).sqrt()
    } else {
        f64::NAN
    };
    (rms, pairs)
}
