//! Synthetic buildings, walkers and step sensors, for the demo, the tests and the benches.
//!
//! [`simulate`] builds an [`Office`], walks it ([`simulate_walk`]) and measures the walk
//! ([`measure_steps`]), the way the walks of Robertson et al. 2009 (sec. 4.1) were recorded:
//! laps of a corridor loop with rooms entered and left, seen through a foot-mounted IMU.
//!
//! Everything lives in the walk frame of the step-trace convention: the walk starts at the
//! origin facing east, so dead-reckoning the measured trace from `Pose2::default()` follows the
//! truth up to the sensor errors, and the floor plan is placed accordingly (see [`office`]).
//!
//! * [`office`] — the office floor plan (corridor loop, rooms, doors)
//! * [`office_config`] — the office's dimensions
//! * [`rooms`] — rooms along the loop, their doors and anchors
//! * [`route`] — polylines with rounded corners, walked by arc length
//! * [`tour`] — the plan of the walk: laps of the loop with detours into rooms
//! * [`walk_config`] — the tour's laps and room visits and the walker's gait
//! * [`walker`] — the walker striding along the planned route, and its true poses
//! * [`step_sensor`] — step measurements with foot-mounted-grade errors and heading drift
//! * [`wifi`] — access points, path loss, shadowing and the scans a walker records
//! * [`magnetic`] — the Earth's field bent by steel, and each step's magnetometer reading
//! * [`campus`], [`campus_walk`], [`gps_receiver`], [`compass`] — the office in a yard with a
//!   front door, outdoor–indoor–outdoor walks, the GPS fixes taken outdoors and a compass's
//!   disturbed headings ([`simulate_campus`])
//! * [`tower`], [`tower_config`], [`tower_walk`] — a multi-floor building with two
//!   stairwells of treads, its dimensions, and long tours through it from a random start
//!   ([`simulate_tower`])
//! * [`survey_tour`] — survey tours of such a building: every room swept, every flight walked

pub mod campus;
pub mod campus_walk;
pub mod compass;
pub mod gps_receiver;
pub mod magnetic;
pub mod office;
pub mod office_config;
pub mod rooms;
pub mod route;
pub mod step_sensor;
mod stride;
pub mod survey_tour;
pub mod tour;
pub mod tower;
pub mod tower_config;
pub mod tower_walk;
pub mod walk_config;
pub mod walker;
pub mod wifi;

pub use campus::{Campus, CampusConfig};
pub use campus_walk::{CampusSimConfig, CampusSimulation, CampusWalk, simulate_campus};
pub use compass::CompassSimConfig;
pub use gps_receiver::{GpsErrorSummary, GpsRecord, GpsSimConfig, receive_fixes};
pub use magnetic::{FieldSimConfig, MagneticWorld};
pub use office::{Office, Room, office_floor};
pub use office_config::OfficeConfig;
pub use step_sensor::{StepNoiseConfig, measure_steps, measure_steps_from};
pub use tower::{Tower, TowerRoom};
pub use tower_config::TowerConfig;
pub use tower_walk::{
    TourKind, TowerWalkConfig, floor_changes, floor_resolved_at, simulate_tower_walk,
};
pub use walk_config::WalkConfig;
pub use walker::simulate_walk;
pub use wifi::{FieldPoint, RadioWorld, WifiSimConfig, expected_field};

use crate::error::Result;
use crate::map::FloorPlan;
use crate::sensor::step::StepTrace;
use crate::sensor::{StepFields, TruePath, TruePose};
use serde::{Deserialize, Serialize};

/// Stream number of the walker's generator.
const WALK_STREAM: u64 = 1;
/// Stream number of the step sensor's generator.
const NOISE_STREAM: u64 = 2;
/// Stream number of the access points' placement and shadowing.
const RADIO_STREAM: u64 = 3;
/// Stream number of the WiFi scans' noise and timing.
const SCAN_STREAM: u64 = 4;
/// Stream number of the magnetometer's noise.
const MAGNETOMETER_STREAM: u64 = 5;

/// Everything a simulation needs; every default in one place:
///
/// | field    | default                                                                  |
/// |----------|--------------------------------------------------------------------------|
/// | `seed`   | 0                                                                        |
/// | `office` | 30 m × 18 m corridor loop, 1.8 m wide; 16 rooms 4 m × 4 m; 0.9 m doors; 0.2 m walls ([`OfficeConfig`]) |
/// | `walk`   | 3 laps, 2–4 rooms per lap (half revisits after the first), 0.7 ± 0.05 m strides at 1.8 Hz ([`WalkConfig`]) |
/// | `noise`  | 0.02 m stride noise, 0.5° heading-change noise, 15° total drift, 0.02 m height noise ([`StepNoiseConfig`]) |
/// | `field`  | off; when on, a 48 µT field dipping 65° with a steel anomaly per 2.5 m square over the plan (from `field.seed`), read at 0.4 µT ([`FieldSimConfig`]) |
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// Seed of every random draw; the walker and the sensor use independent streams derived
    /// from it. Default 0.
    pub seed: u64,
    /// The building.
    pub office: OfficeConfig,
    /// The tour.
    pub walk: WalkConfig,
    /// The step sensor's errors.
    pub noise: StepNoiseConfig,
    /// The building's magnetic field and the magnetometer's readings of it.
    pub field: FieldSimConfig,
}

impl SimConfig {
    /// Checks every component's configuration.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) from the first section that fails its `validate`:
    /// [`OfficeConfig`], [`WalkConfig`], [`StepNoiseConfig`], [`FieldSimConfig`].
    pub fn validate(&self) -> crate::error::Result<()> {
        self.office.validate()?;
        self.walk.validate()?;
        self.noise.validate()?;
        self.field.validate()
    }
}

/// A simulated walk: the building, the truth and what the sensor measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// The office's walkable surfaces, in the walk frame.
    pub plan: FloorPlan,
    /// True poses, one per step.
    pub truth: TruePath,
    /// Measured steps, one per true pose.
    pub steps: StepTrace,
    /// The magnetometer's reading at each step, when `field.enabled`.
    pub field: Option<StepFields>,
}

/// The magnetometer's readings along `truth` in a field simulated over `plan`, when
/// `field.enabled`.
fn field_readings(
    plan: &FloorPlan,
    field: FieldSimConfig,
    truth: &TruePath,
    seed: u64,
) -> Result<Option<StepFields>> {
    field
        .enabled
        .then(|| {
            MagneticWorld::of_plan(plan, field)
                .readings_along(truth, stream_seed(seed, MAGNETOMETER_STREAM))
        })
        .transpose()
}

/// Runs the simulation described by `config`; equal configurations give equal results.
///
/// # Errors
///
/// [`Error::Config`](crate::Error::Config) when `config` fails [`SimConfig::validate`] or the
/// office's rooms do not fit ([`Office::new`]); [`Error::Simulation`](crate::Error::Simulation)
/// when the walk leaves the floor or a measured step is implausible (a preset's bug), or when
/// the simulated magnetic field's anomalies add up beyond 2000 µT.
pub fn simulate(config: &SimConfig) -> Result<Simulation> {
    config.validate()?;
    let office = Office::new(&config.office)?;
    let truth = simulate_walk(&office, &config.walk, stream_seed(config.seed, WALK_STREAM))?;
    let steps = measure_steps(
        &truth,
        &config.noise,
        stream_seed(config.seed, NOISE_STREAM),
    )?;
    let field = field_readings(&office.plan, config.field, &truth, config.seed)?;
    Ok(Simulation {
        plan: office.plan,
        truth,
        steps,
        field,
    })
}

/// Everything a multi-floor simulation needs; every default in one place:
///
/// | field      | default                                                               |
/// |------------|-----------------------------------------------------------------------|
/// | `seed`     | 0                                                                     |
/// | `building` | 3 floors, 40 m corridor, rooms both sides, two switchback stairwells ([`TowerConfig`]) |
/// | `walk`     | 12 minutes from a random start, 35 % of legs to another floor ([`TowerWalkConfig`]) |
/// | `noise`    | foot-mounted-grade step errors ([`StepNoiseConfig`])                  |
/// | `wifi`     | 8 access points a floor, scans every 2 s ([`WifiSimConfig`]); the access points and shadowing come from `wifi.radio_seed`, so walks of one building share them |
/// | `field`    | off; as the office's ([`FieldSimConfig`]), one field per floor from `field.seed` |
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TowerSimConfig {
    /// Seed of the walk and the sensor (the building's layout has its own `layout_seed`).
    pub seed: u64,
    /// The building.
    pub building: TowerConfig,
    /// The tour.
    pub walk: TowerWalkConfig,
    /// The step sensor's errors.
    pub noise: StepNoiseConfig,
    /// The access points and the receiver's scans.
    pub wifi: WifiSimConfig,
    /// The building's magnetic field and the magnetometer's readings of it.
    pub field: FieldSimConfig,
}

/// A simulated multi-floor walk.
#[derive(Debug, Clone, PartialEq)]
pub struct TowerSimulation {
    /// The building's walkable surfaces.
    pub plan: FloorPlan,
    /// Where the walker stands before the first step (heading: before the first step).
    pub start: TruePose,
    /// True poses, one per step.
    pub truth: TruePath,
    /// Measured steps, one per true pose.
    pub steps: StepTrace,
    /// The access points and their signals.
    pub radio: RadioWorld,
    /// The WiFi scans recorded along the walk.
    pub wifi: Vec<crate::sensor::WifiScan>,
    /// The magnetometer's reading at each step, when `field.enabled`.
    pub field: Option<StepFields>,
}

impl TowerSimulation {
    /// The true path as `(x, y, level)`, from the start before the first step to the last
    /// step.
    #[must_use]
    pub fn true_points(&self) -> Vec<(f64, f64, i32)> {
        std::iter::once(&self.start)
            .chain(&self.truth.poses)
            .map(|p| (p.x, p.y, p.level))
            .collect()
    }

    /// The expected RSSI of every access point on a grid of `spacing` metres over the
    /// building's walkable surfaces ([`expected_field`]).
    ///
    /// # Errors
    ///
    /// As [`FloorTopology::build`](crate::map::FloorTopology::build) on `self.plan`: a surface that
    /// is not a valid polygon.
    pub fn expected_field(&self, spacing: f64) -> Result<Vec<FieldPoint>> {
        let topology =
            crate::map::FloorTopology::build(&self.plan, &crate::map::TopologyConfig::default())?;
        Ok(expected_field(&self.radio, &topology, spacing))
    }
}

/// Runs the multi-floor simulation described by `config`; equal configurations give equal
/// results.
///
/// # Errors
///
/// [`Error::Config`](crate::Error::Config) when a section of `config` fails its `validate`
/// ([`TowerConfig`], [`TowerWalkConfig`], [`StepNoiseConfig`], [`WifiSimConfig`],
/// [`FieldSimConfig`]); [`Error::Simulation`](crate::Error::Simulation) when the walk leaves the
/// building or a measured step is implausible (a preset's bug), or when the simulated magnetic
/// field's anomalies add up beyond 2000 µT.
pub fn simulate_tower(config: &TowerSimConfig) -> Result<TowerSimulation> {
    config.building.validate()?;
    config.walk.validate()?;
    config.noise.validate()?;
    config.wifi.validate()?;
    config.field.validate()?;
    let tower = Tower::new(&config.building)?;
    let topology =
        crate::map::FloorTopology::build(&tower.plan, &crate::map::TopologyConfig::default())?;
    let (start, truth) = simulate_tower_walk(
        &tower,
        &topology,
        &config.walk,
        stream_seed(config.seed, WALK_STREAM),
    )?;
    let steps = measure_steps_from(
        &truth,
        &start,
        &config.noise,
        stream_seed(config.seed, NOISE_STREAM),
    )?;
    let radio = RadioWorld::new(
        &topology,
        &config.wifi,
        stream_seed(config.wifi.radio_seed, RADIO_STREAM),
    )?;
    let wifi = radio.scans_along(&start, &truth, stream_seed(config.seed, SCAN_STREAM));
    let field = field_readings(&tower.plan, config.field, &truth, config.seed)?;
    Ok(TowerSimulation {
        plan: tower.plan,
        start,
        truth,
        steps,
        radio,
        wifi,
        field,
    })
}

/// The seed of independent stream `stream` of a run seeded with `seed` (`SplitMix64`'s
/// finaliser applied twice, so nearby seeds and streams give unrelated generators).
#[must_use]
pub fn stream_seed(seed: u64, stream: u64) -> u64 {
    crate::random::mix(seed ^ crate::random::mix(stream))
}

/// The steps of a default office simulation seeded with `seed`, with as many laps as
/// needed to reach `steps` steps, cut to exactly that many (for benches and scaling runs).
///
/// # Errors
///
/// As [`simulate`]; [`Error::Config`](crate::Error::Config) (`walk.laps`) when `steps` needs more
/// than 1000 laps (about 150 000 steps).
pub fn office_walk_steps(steps: usize, seed: u64) -> Result<Vec<crate::sensor::Step>> {
    let mut config = SimConfig {
        seed,
        ..Default::default()
    };
    config.walk.laps = 1;
    loop {
        let sim = simulate(&config)?;
        if sim.steps.len() >= steps {
            return Ok(sim.steps.steps()[..steps].to_vec());
        }
        // About 150 steps a lap: add enough laps at once.
        config.walk.laps += 1 + (steps - sim.steps.len()) / 150;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Pose2;

    #[test]
    fn default_simulation_is_deterministic_and_consistent() {
        let config = SimConfig::default();
        let sim = simulate(&config).expect("simulation");
        assert_eq!(sim, simulate(&config).expect("again"));
        assert_eq!(sim.steps.len(), sim.truth.len());
        assert!(
            (400..=700).contains(&sim.truth.len()),
            "{}",
            sim.truth.len()
        );
        assert!(
            sim.truth
                .poses
                .iter()
                .all(|p| sim.plan.is_walkable(p.x, p.y, Some(0)))
        );
        // The trace drifts: dead reckoning ends metres, not kilometres, from the truth.
        let end = sim
            .steps
            .dead_reckon(Pose2::default())
            .last()
            .copied()
            .unwrap_or_default();
        let truth_end = sim.truth.poses[sim.truth.len() - 1];
        let error = (end.x - truth_end.x).hypot(end.y - truth_end.y);
        assert!(error > 0.5 && error < 40.0, "{error} m");
        let other = simulate(&SimConfig { seed: 2, ..config }).expect("seed 2");
        assert_ne!(other.truth, sim.truth);
    }

    #[test]
    fn config_round_trips_through_json_with_defaults_filled_in() {
        let config: SimConfig =
            serde_json::from_str(r#"{"seed": 9, "walk": {"laps": 2}}"#).expect("json");
        assert_eq!(config.seed, 9);
        assert_eq!(config.walk.laps, 2);
        assert_eq!(config.office, OfficeConfig::default());
        let text = serde_json::to_string(&config).expect("serialise");
        assert_eq!(
            serde_json::from_str::<SimConfig>(&text).expect("parse"),
            config
        );
        assert!(serde_json::from_str::<SimConfig>(r#"{"sead": 9}"#).is_err());
        let bad = SimConfig {
            walk: WalkConfig {
                laps: 0,
                ..Default::default()
            },
            ..config
        };
        assert!(simulate(&bad).is_err());
    }

    #[test]
    fn streams_differ() {
        assert_ne!(stream_seed(1, WALK_STREAM), stream_seed(1, NOISE_STREAM));
        assert_ne!(stream_seed(1, WALK_STREAM), stream_seed(2, WALK_STREAM));
    }
}
