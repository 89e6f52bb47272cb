//! Outdoor–indoor–outdoor walks on the [`Campus`] (Robertson et al. 2009, sec. 4.1): from a
//! random point in the yard round to the front door, in through the lobby, the office tour
//! of [`super::tour`] (laps of the corridor with room visits), out again and away to another
//! random point in the yard — with the step sensor's and a GPS receiver's measurements, and
//! optionally a compass ([`super::compass`]). With `walk_out = false` the walk ends where the
//! tour does, indoors: GPS sees only the way to the entrance.
//!
//! Several walks of one building share the campus and the rough outline and differ in
//! everything drawn at random: the route outdoors and indoors, the step errors and the GPS
//! errors (one generator per walk, derived from the seed and the walk's number).

use super::campus::{Campus, CampusConfig};
use super::compass::{CompassSimConfig, read_compass};
use super::gps_receiver::{GpsRecord, GpsSimConfig, receive_fixes};
use super::office_config::OfficeConfig;
use super::step_sensor::{StepNoiseConfig, measure_steps_from};
use super::tour::plan_route;
use super::walk_config::WalkConfig;
use super::walker::walk_waypoints;
use super::{NOISE_STREAM, WALK_STREAM, stream_seed};
use crate::error::Result;
use crate::geometry::LocalFrame;
use crate::map::FloorPlan;
use crate::sensor::step::StepTrace;
use crate::sensor::truth::{TruePath, TruePose};
use geo::{Coord, Polygon};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Stream number of the GPS receiver's generator.
const GPS_STREAM: u64 = 5;
/// Stream number of the rough outline.
const OUTLINE_STREAM: u64 = 6;
/// Stream number of the compass's generator.
const COMPASS_STREAM: u64 = 7;
/// Walk `k`'s streams derive from stream `WALKS_STREAM + k` of the seed.
const WALKS_STREAM: u64 = 100;

/// Everything a campus simulation needs; every default in one place:
///
/// | field    | default                                                              |
/// |----------|----------------------------------------------------------------------|
/// | `seed`   | 0                                                                    |
/// | `walks`  | 1                                                                    |
/// | `office` | the default office ([`OfficeConfig`])                                |
/// | `campus` | 15 m yard, 1.8 m lobby, 1.2 m front door, outline known to ±1.5 m ([`CampusConfig`]) |
/// | `walk`   | the office tour's defaults: 3 laps with room visits ([`WalkConfig`])  |
/// | `walk_out` | true: the walk leaves the building again at the end                 |
/// | `noise`  | foot-mounted-grade step errors, 15° drift ([`StepNoiseConfig`])       |
/// | `gps`    | 1 Hz outdoors, 3 m Gauss–Markov bias (300 s), 1.5 m noise, 1 % outliers ([`GpsSimConfig`]) |
/// | `compass` | off; when on, 5° noise, 20° disturbance indoors over 5 m ([`CompassSimConfig`]) |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CampusSimConfig {
    /// Seed of every random draw. Default 0.
    pub seed: u64,
    /// Number of walks of the building. Default 1.
    pub walks: usize,
    /// The office.
    pub office: OfficeConfig,
    /// Its grounds.
    pub campus: CampusConfig,
    /// The indoor tour.
    pub walk: WalkConfig,
    /// Walk back out to the yard after the tour (false: the walk ends indoors, GPS sees
    /// only the way in). Default true.
    pub walk_out: bool,
    /// The step sensor's errors.
    pub noise: StepNoiseConfig,
    /// The GPS receiver's errors.
    pub gps: GpsSimConfig,
    /// The compass (absolute heading per step).
    pub compass: CompassSimConfig,
}

impl Default for CampusSimConfig {
    fn default() -> Self {
        Self {
            seed: 0,
            walks: 1,
            office: OfficeConfig::default(),
            campus: CampusConfig::default(),
            walk: WalkConfig::default(),
            walk_out: true,
            noise: StepNoiseConfig::default(),
            gps: GpsSimConfig::default(),
            compass: CompassSimConfig::default(),
        }
    }
}

/// One simulated walk.
#[derive(Debug, Clone, PartialEq)]
pub struct CampusWalk {
    /// Where the walker stands at `t = 0`, facing the first leg.
    pub start: TruePose,
    /// True poses, one per step.
    pub truth: TruePath,
    /// Measured steps.
    pub steps: StepTrace,
    /// GPS fixes (outdoors only) and their errors.
    pub gps: GpsRecord,
}

/// A simulated campus and its walks.
#[derive(Debug, Clone, PartialEq)]
pub struct CampusSimulation {
    /// Every walkable surface, indoors and out.
    pub plan: FloorPlan,
    /// The building's outline as a user would know it (each side off by up to the error).
    pub outline: Polygon<f64>,
    /// The walks.
    pub walks: Vec<CampusWalk>,
}

/// Runs the campus simulation described by `config`, placing GPS fixes on the globe with
/// `frame` (the plan's frame); equal configurations give equal results.
///
/// # Errors
///
/// - [`Error::Config`](crate::Error::Config) when `walks` is outside [1, 1000], or a section of
///   `config` fails its `validate` (the walk, noise, GPS, compass, office or campus).
/// - [`Error::Simulation`](crate::Error::Simulation) when a simulated route leaves the floor or a
///   simulated step is implausible: a layout the preset got wrong, not the caller.
pub fn simulate_campus(config: &CampusSimConfig, frame: &LocalFrame) -> Result<CampusSimulation> {
    crate::error::check_range("walks", config.walks as f64, 1.0..=1000.0, "")?;
    config.walk.validate()?;
    config.noise.validate()?;
    config.gps.validate()?;
    config.compass.validate()?;
    let campus = Campus::new(&config.office, &config.campus)?;
    let mut outline_rng = Pcg64Mcg::seed_from_u64(stream_seed(config.seed, OUTLINE_STREAM));
    let outline = campus.rough_outline(config.campus.outline_error, &mut outline_rng);
    let walks = (1..=config.walks as u64)
        .map(|k| {
            simulate_one(
                &campus,
                config,
                stream_seed(config.seed, WALKS_STREAM + k),
                frame,
            )
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(CampusSimulation {
        plan: campus.plan,
        outline,
        walks,
    })
}

fn simulate_one(
    campus: &Campus,
    config: &CampusSimConfig,
    seed: u64,
    frame: &LocalFrame,
) -> Result<CampusWalk> {
    let mut rng = Pcg64Mcg::seed_from_u64(stream_seed(seed, WALK_STREAM));
    let (arrive, leave) = (outdoor_leg(campus, &mut rng), outdoor_leg(campus, &mut rng));
    let tour = plan_route(&campus.office, &config.walk, &mut rng);
    let mut waypoints = arrive.clone();
    waypoints.extend(tour);
    if config.walk_out {
        waypoints.extend(leave.iter().rev());
    }
    let truth = walk_waypoints(
        &campus.office.config,
        &campus.plan,
        &waypoints,
        &config.walk,
        &mut rng,
    )?;
    let (p0, p1) = (waypoints[0], waypoints[1]);
    let start = TruePose {
        t: 0.0,
        x: p0.x,
        y: p0.y,
        z: 0.0,
        level: 0,
        heading: (p1.y - p0.y).atan2(p1.x - p0.x),
    };
    let steps = measure_steps_from(
        &truth,
        &start,
        &config.noise,
        stream_seed(seed, NOISE_STREAM),
    )?;
    let steps = read_compass(
        steps,
        &start,
        &truth,
        |x, y| campus.is_outdoors(x, y),
        &config.compass,
        stream_seed(seed, COMPASS_STREAM),
    )?;
    let gps = receive_fixes(
        &start,
        &truth,
        |x, y| campus.is_outdoors(x, y),
        frame,
        &config.gps,
        stream_seed(seed, GPS_STREAM),
    )?;
    Ok(CampusWalk {
        start,
        truth,
        steps,
        gps,
    })
}

/// Waypoints from a random point in the yard beside the building (west or east) round to
/// the south yard, to the front door, through the lobby to the corridor's south-west corner
/// (where the office tour starts and ends).
fn outdoor_leg(campus: &Campus, rng: &mut Pcg64Mcg) -> Vec<Coord<f64>> {
    let (lo, hi) = (campus.outline.min(), campus.outline.max());
    let yard = lo.x - campus.grounds.min().x;
    let side_x = if rng.random_bool(0.5) {
        lo.x - yard / 2.0
    } else {
        hi.x + yard / 2.0
    };
    let y = rng.random_range(lo.y..hi.y);
    let band = lo.y - yard / 2.0;
    let door = campus.door;
    let front = Coord {
        x: door.x,
        y: lo.y - 1.5,
    };
    vec![
        Coord { x: side_x, y },
        Coord { x: side_x, y: band },
        Coord { x: door.x, y: band },
        front,
        door,
        campus.lobby,
        Coord { x: 0.0, y: 0.0 },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_start_and_end_outdoors_under_gps_and_tour_the_office() {
        let frame = LocalFrame::new(48.0, 11.0).expect("frame");
        let config = CampusSimConfig {
            walks: 2,
            ..Default::default()
        };
        let sim = simulate_campus(&config, &frame).expect("campus");
        assert_eq!(sim.walks.len(), 2);
        assert_ne!(sim.walks[0].truth, sim.walks[1].truth);
        let campus = Campus::new(&config.office, &config.campus).expect("campus");
        for w in &sim.walks {
            assert!(campus.is_outdoors(w.start.x, w.start.y));
            let last = w.truth.poses.last().expect("poses");
            assert!(campus.is_outdoors(last.x, last.y));
            let indoors = w
                .truth
                .poses
                .iter()
                .filter(|p| !campus.is_outdoors(p.x, p.y))
                .count();
            assert!(indoors > 350, "{indoors} steps indoors");
            assert!(
                w.truth
                    .poses
                    .iter()
                    .all(|p| sim.plan.is_walkable(p.x, p.y, Some(0)))
            );
            // Fixes only outdoors, about one a second there; none indoors.
            assert!(w.gps.fixes.len() > 40, "{} fixes", w.gps.fixes.len());
            let mean = w.gps.errors.iter().sum::<f64>() / w.gps.errors.len() as f64;
            assert!(mean < 20.0, "mean GPS error {mean} m");
            assert_eq!(w.steps.len(), w.truth.len());
        }
        assert_eq!(sim, simulate_campus(&config, &frame).expect("again"));
    }
}
