//! Long tours through a [`Tower`]: from a random place on a random floor, room after room,
//! changing floors by the stairs, walked stride by stride.
//!
//! The tour starts inside a random room (or, sometimes, on the corridor) facing the way it
//! goes. Each leg walks out of the current room, along the corridor and, with probability
//! `floor_change_probability`, up or down the nearest stairwell to another floor (the first
//! change of floor always goes to the farthest floor, so that the floor becomes knowable
//! early), then into another room and to one or more random points inside it. A true pose's
//! height and level are those of the surface under the foot.

use super::route::Route;
use super::stride::{Gait, strides};
use super::tower::Tower;
use crate::error::{Error, Result};
use crate::geometry::angle::wrap_angle;
use crate::map::FloorTopology;
use crate::sensor::truth::{TruePath, TruePose};
use geo::Coord;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Points walked to inside a room are redrawn while nearer than this to the previous one.
const MIN_ROOM_LEG: f64 = 1.0;

/// How the walker tours the building; every default in one place.
///
/// | field                        | default  | meaning                                       |
/// |------------------------------|----------|-----------------------------------------------|
/// | `minutes`                    | 12       | length of the walk                            |
/// | `floor_change_probability`   | 0.35     | chance that a leg goes to another floor       |
/// | `corridor_start_probability` | 0.25     | chance of starting on the corridor            |
/// | `max_points_per_room`        | 2        | most points walked to in a room               |
/// | `room_margin`                | 0.6 m    | distance of those points from the walls       |
/// | `step_frequency`             | 1.8 Hz   | steps per second                              |
/// | `step_period_jitter`         | 0.05     | relative jitter of a step's period            |
/// | `step_length_mean`           | 0.7 m    | mean stride                                   |
/// | `step_length_sigma`          | 0.05 m   | stride spread (kept within ±50 %)             |
/// | `corner_radius`              | 0.5 m    | rounding of the route's corners               |
/// | `wander_sigma`               | 0.03 m   | sideways wander about the route               |
/// | `tour`                       | random   | `random` legs, or a `survey` of every room ([`super::survey_tour`]) |
/// | `lane_spacing`               | 1.5 m    | survey: greatest distance between sweep lanes |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TowerWalkConfig {
    /// Length of the walk, minutes.
    pub minutes: f64,
    /// Chance that a leg goes to another floor.
    pub floor_change_probability: f64,
    /// Chance of starting on the corridor instead of in a room.
    pub corridor_start_probability: f64,
    /// Most points walked to inside a room (at least one).
    pub max_points_per_room: usize,
    /// Distance of those points from the room's walls, metres.
    pub room_margin: f64,
    /// Step rate, hertz.
    pub step_frequency: f64,
    /// Relative jitter (1σ) of each step's period.
    pub step_period_jitter: f64,
    /// Mean stride length, metres.
    pub step_length_mean: f64,
    /// Stride-length spread (1σ), metres.
    pub step_length_sigma: f64,
    /// Radius of rounded corners, metres.
    pub corner_radius: f64,
    /// Stationary spread (1σ) of the sideways wander, metres.
    pub wander_sigma: f64,
    /// The kind of tour.
    pub tour: TourKind,
    /// Survey tours: the greatest distance between the lanes a room is swept in, metres.
    pub lane_spacing: f64,
}

/// The kind of tour through the building.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TourKind {
    /// Room after random room from a random start, changing floors now and then.
    #[default]
    Random,
    /// Every room of every floor swept lane by lane, both stairwells walked between every
    /// pair of floors; `minutes` caps the walk, which ends where the tour ends.
    Survey,
}

impl Default for TowerWalkConfig {
    fn default() -> Self {
        Self {
            minutes: 12.0,
            floor_change_probability: 0.35,
            corridor_start_probability: 0.25,
            max_points_per_room: 2,
            room_margin: 0.6,
            step_frequency: 0.9,
            step_period_jitter: 0.05,
            step_length_mean: 1.4,
            step_length_sigma: 0.08,
            corner_radius: 0.5,
            wander_sigma: 0.03,
            tour: TourKind::Random,
            lane_spacing: 1.5,
        }
    }
}

impl TowerWalkConfig {
    /// The stride parameters.
    pub(super) fn gait(&self) -> Gait {
        Gait {
            frequency: self.step_frequency,
            period_jitter: self.step_period_jitter,
            length_mean: self.step_length_mean,
            length_sigma: self.step_length_sigma,
            wander_sigma: self.wander_sigma,
        }
    }

    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] naming the first field out of its range: `minutes` outside [0.1, 600], a
    /// probability outside [0, 1], `room_margin` outside [0.3, 5] m, `lane_spacing` outside
    /// [0.5, 20] m, …, or a gait field (e.g. `step_frequency` outside [0.2, 5] Hz).
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("walk.minutes", self.minutes, 0.1..=600.0, "min")?;
        crate::error::check_range(
            "walk.floor_change_probability",
            self.floor_change_probability,
            0.0..=1.0,
            "",
        )?;
        crate::error::check_range(
            "walk.corridor_start_probability",
            self.corridor_start_probability,
            0.0..=1.0,
            "",
        )?;
        crate::error::check_range(
            "walk.max_points_per_room",
            self.max_points_per_room as f64,
            1.0..=100.0,
            "",
        )?;
        crate::error::check_range("walk.room_margin", self.room_margin, 0.3..=5.0, "m")?;
        crate::error::check_range("walk.corner_radius", self.corner_radius, 0.0..=2.0, "m")?;
        crate::error::check_range("walk.lane_spacing", self.lane_spacing, 0.5..=20.0, "m")?;
        self.gait().validate()
    }
}

/// A tour of `tower` drawn from a generator seeded with `seed`: the start pose (before the
/// first step) and one true pose per step.
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`TowerWalkConfig::validate`]; [`Error::Simulation`] when
/// the route leaves `topology`'s plan (a `topology` not built from `tower`'s plan, or a layout
/// bug).
pub fn simulate_tower_walk(
    tower: &Tower,
    topology: &FloorTopology,
    config: &TowerWalkConfig,
    seed: u64,
) -> Result<(TruePose, TruePath)> {
    config.validate()?;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let needed = config.minutes * 60.0 * config.step_frequency * config.step_length_mean * 1.2;
    let (start_level, waypoints) = match config.tour {
        TourKind::Random => plan_tour(tower, config, needed, &mut rng),
        TourKind::Survey => (
            0,
            super::survey_tour::survey_waypoints(tower, config.lane_spacing, config.room_margin),
        ),
    };
    let cap = (tower.config.corridor_width / 2.0).min(tower.config.lane_width / 2.0);
    let route = Route::rounded(&waypoints, config.corner_radius.min(cap));
    let steps = (config.minutes * 60.0 * config.step_frequency).round() as usize;
    walk(
        tower,
        topology,
        &route,
        start_level,
        steps,
        config,
        &mut rng,
    )
}

/// The tour's waypoints and its starting level.
fn plan_tour(
    tower: &Tower,
    config: &TowerWalkConfig,
    needed: f64,
    rng: &mut Pcg64Mcg,
) -> (i32, Vec<Coord<f64>>) {
    let floors = tower.config.level_count();
    let mut level = rng.random_range(0..floors);
    let start_level = level;
    let on_level = |l: i32| -> Vec<usize> {
        (0..tower.rooms.len())
            .filter(|&i| tower.rooms[i].level == l)
            .collect()
    };
    let mut room = pick(&on_level(level), None, rng);
    let mut waypoints = Vec::new();
    if rng.random_bool(config.corridor_start_probability) {
        let x = rng.random_range(1.0..tower.config.corridor_length - 1.0);
        waypoints.push(Coord { x, y: 0.0 });
        waypoints.push(tower.rooms[room].corridor);
        enter(tower, room, config, &mut waypoints, rng);
    } else {
        let r = &tower.rooms[room];
        waypoints.push(point_in_room(r.area, config.room_margin, r.entry, rng));
    }
    let mut changed = false;
    while route_length(&waypoints) < needed {
        // Out of the room to the corridor.
        let r = tower.rooms[room];
        waypoints.extend([r.entry, r.door, r.corridor]);
        let mut target = level;
        if floors > 1 && rng.random_bool(config.floor_change_probability) {
            target = if changed {
                let other = rng.random_range(0..floors - 1);
                if other >= level { other + 1 } else { other }
            } else if level * 2 < floors - 1 {
                floors - 1
            } else {
                0
            };
            changed = true;
        }
        while level != target {
            let up = target > level;
            let east = waypoints
                .last()
                .is_some_and(|p| p.x > tower.config.corridor_length / 2.0);
            waypoints.extend(tower.stair_waypoints(east, up));
            level += if up { 1 } else { -1 };
        }
        room = pick(&on_level(level), Some(room), rng);
        waypoints.push(tower.rooms[room].corridor);
        enter(tower, room, config, &mut waypoints, rng);
    }
    (start_level, waypoints)
}

/// Walks from the corridor in front of `room` into it and to random points inside.
fn enter(
    tower: &Tower,
    room: usize,
    config: &TowerWalkConfig,
    waypoints: &mut Vec<Coord<f64>>,
    rng: &mut Pcg64Mcg,
) {
    let r = tower.rooms[room];
    waypoints.extend([r.door, r.entry]);
    let mut from = r.entry;
    for _ in 0..rng.random_range(1..=config.max_points_per_room) {
        from = point_in_room(r.area, config.room_margin, from, rng);
        waypoints.push(from);
    }
}

/// A random index of `candidates` other than `not` (when there is another).
fn pick(candidates: &[usize], not: Option<usize>, rng: &mut Pcg64Mcg) -> usize {
    let others: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&c| Some(c) != not)
        .collect();
    let pool = if others.is_empty() {
        candidates
    } else {
        &others
    };
    pool[rng.random_range(0..pool.len())]
}

/// A uniform point at least `margin` inside `area`, at least [`MIN_ROOM_LEG`] from `from`
/// when such a point is found in a few tries.
fn point_in_room(
    area: geo::Rect<f64>,
    margin: f64,
    from: Coord<f64>,
    rng: &mut Pcg64Mcg,
) -> Coord<f64> {
    let (lo, hi) = (area.min(), area.max());
    let mut p = area.center();
    for _ in 0..20 {
        p = Coord {
            x: rng.random_range(lo.x + margin..=(hi.x - margin).max(lo.x + margin)),
            y: rng.random_range(lo.y + margin..=(hi.y - margin).max(lo.y + margin)),
        };
        if (p.x - from.x).hypot(p.y - from.y) >= MIN_ROOM_LEG {
            break;
        }
    }
    p
}

fn route_length(points: &[Coord<f64>]) -> f64 {
    points
        .windows(2)
        .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
        .sum()
}

/// Walks `route` stride by stride for `steps` steps (fewer if the route ends first).
fn walk(
    tower: &Tower,
    topology: &FloorTopology,
    route: &Route,
    start_level: i32,
    steps: usize,
    config: &TowerWalkConfig,
    rng: &mut Pcg64Mcg,
) -> Result<(TruePose, TruePath)> {
    let h = tower.config.floor_height;
    let locate = |q: Coord<f64>, z: f64| topology.locate(q.x, q.y, None, Some(z));
    let (p0, d0) = route.at(0.0);
    let mut z = f64::from(start_level) * h;
    let s0 = locate(p0, z).ok_or_else(|| off_plan(p0))?;
    z = f64::from(topology.z(s0));
    let start = TruePose {
        t: 0.0,
        x: p0.x,
        y: p0.y,
        z,
        level: topology.level(s0),
        heading: d0.y.atan2(d0.x),
    };
    let mut previous = p0;
    let mut poses = Vec::with_capacity(steps);
    for stride in strides(route, config.gait(), |p| tower.stride_limit(p), rng).take(steps) {
        let (q, surface) = match locate(stride.wandered, z) {
            Some(surface) => (stride.wandered, surface),
            None => {
                let q = stride.on_route;
                (q, locate(q, z).ok_or_else(|| off_plan(q))?)
            }
        };
        z = f64::from(topology.z(surface));
        poses.push(TruePose {
            t: stride.t,
            x: q.x,
            y: q.y,
            z,
            level: topology.level(surface),
            heading: wrap_angle((q.y - previous.y).atan2(q.x - previous.x)),
        });
        previous = q;
    }
    Ok((start, TruePath { poses }))
}

fn off_plan(p: Coord<f64>) -> Error {
    Error::Simulation(format!(
        "simulated route leaves the building at ({:.3}, {:.3}); the layout is inconsistent",
        p.x, p.y
    ))
}

/// Indices of the steps at which the true level differs from the previous step's (or the
/// start's, for the first).
#[must_use]
pub fn floor_changes(start: &TruePose, truth: &TruePath) -> Vec<usize> {
    let mut level = start.level;
    let mut changes = Vec::new();
    for (i, p) in truth.poses.iter().enumerate() {
        if p.level != level {
            changes.push(i);
            level = p.level;
        }
    }
    changes
}

/// The first step by which the walk has visited both the lowest and the highest of
/// `levels` (inclusive), so that its floor sequence could only have started on one floor:
/// before it, a building of identical floors cannot tell the floor. `Some(0)` for one floor.
#[must_use]
pub fn floor_resolved_at(start: &TruePose, truth: &TruePath, levels: (i32, i32)) -> Option<usize> {
    if levels.0 == levels.1 {
        return Some(0);
    }
    let (mut lo, mut hi) = (start.level, start.level);
    for (i, p) in truth.poses.iter().enumerate() {
        lo = lo.min(p.level);
        hi = hi.max(p.level);
        if hi - lo >= levels.1 - levels.0 {
            return Some(i);
        }
    }
    None
}

#[cfg(test)]
/// The surface after each step of `path` from `start`, walked on `topology`; the first
/// step through a wall as the error.
pub(crate) fn walk_on_plan(
    topology: &FloorTopology,
    start: &TruePose,
    path: &TruePath,
) -> Result<Vec<u32>, usize> {
    let mut surface = topology
        .locate(start.x, start.y, Some(start.level), Some(start.z))
        .ok_or(0usize)?;
    let mut from = [start.x as f32, start.y as f32];
    let mut surfaces = Vec::with_capacity(path.len());
    for (i, p) in path.poses.iter().enumerate() {
        let to = [p.x as f32, p.y as f32];
        surface = topology.walk(surface, from, to).ok_or(i)?;
        surfaces.push(surface);
        from = to;
    }
    Ok(surfaces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::TopologyConfig;
    use crate::sim::TowerConfig;

    fn tower() -> (Tower, FloorTopology) {
        let tower = Tower::new(&TowerConfig::default()).expect("tower");
        let topology =
            FloorTopology::build(&tower.plan, &TopologyConfig::default()).expect("topology");
        (tower, topology)
    }

    #[test]
    fn tours_stay_on_the_plan_change_floors_and_agree_with_the_topology() {
        let (tower, topology) = tower();
        let config = TowerWalkConfig::default();
        for seed in 0..6 {
            let (start, path) =
                simulate_tower_walk(&tower, &topology, &config, seed).expect("walk");
            let expected = (config.minutes * 60.0 * config.step_frequency).round() as usize;
            assert_eq!(path.len(), expected, "seed {seed}");
            let changes = floor_changes(&start, &path);
            assert!(changes.len() >= 2, "seed {seed}: {changes:?}");
            assert!(floor_resolved_at(&start, &path, (0, 2)).is_some());
            // Every step is a legal move on the plan: the tracker's model of the building.
            let surfaces = walk_on_plan(&topology, &start, &path)
                .unwrap_or_else(|i| panic!("seed {seed} step {i}: through a wall"));
            let mut from = (start.x, start.y);
            for (i, (p, &to)) in path.poses.iter().zip(&surfaces).enumerate() {
                assert!(
                    (f64::from(topology.z(to)) - p.z).abs() < 1e-6,
                    "seed {seed} step {i}"
                );
                assert_eq!(topology.level(to), p.level);
                let d = (p.x - from.0).hypot(p.y - from.1);
                assert!(d < 2.2, "seed {seed} step {i}: {d} m");
                from = (p.x, p.y);
            }
        }
    }

    #[test]
    fn floor_resolution_needs_both_ends() {
        let pose = |level| TruePose {
            t: 0.0,
            x: 0.0,
            y: 0.0,
            z: 3.0 * f64::from(level),
            level,
            heading: 0.0,
        };
        let path = TruePath {
            poses: [1, 1, 2, 2, 1, 0, 0].map(pose).to_vec(),
        };
        assert_eq!(floor_changes(&pose(1), &path), vec![2, 4, 5]);
        assert_eq!(floor_resolved_at(&pose(1), &path, (0, 2)), Some(5));
        assert_eq!(floor_resolved_at(&pose(1), &path, (0, 3)), None);
        assert_eq!(floor_resolved_at(&pose(1), &path, (1, 1)), Some(0));
    }
}
