//! A pedestrian walking the planned tour of the office ([`super::tour`]) stride by stride.
//!
//! The route's corners are rounded ([`Route`]) and walked with strides of random length at a
//! jittered step rate, with a small, smooth sideways wander; each true pose is where a stride
//! ends, with the direction of motion over it as heading.
//!
//! Every true position is on the floor by construction: waypoints lie on corridor centre lines,
//! door axes and inside convex rooms; corner roundings stay in triangles of such points (their
//! radius is capped at half the corridor width and at the entry depth); and the wander is only
//! applied where it keeps the walker on the floor.

use super::office::Office;
use super::route::Route;
use super::stride::strides;
use super::tour::plan_route;
use super::walk_config::WalkConfig;
use crate::error::{Error, Result};
use crate::geometry::angle::wrap_angle;
use crate::sensor::truth::{TruePath, TruePose};
use geo::Coord;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;

/// Walks `config.laps` laps of `office` with room visits, drawing from a generator seeded with
/// `seed`. Poses follow the [`TruePath`] convention (the walk starts at the origin facing east).
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`WalkConfig::validate`]; [`Error::Simulation`] when the
/// route leaves the office's floor (a layout bug).
pub fn simulate_walk(office: &Office, config: &WalkConfig, seed: u64) -> Result<TruePath> {
    config.validate()?;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let waypoints = plan_route(office, config, &mut rng);
    walk_waypoints(&office.config, &office.plan, &waypoints, config, &mut rng)
}

/// Walks through `waypoints` over `plan`, the corners rounded no wider than the office's
/// corridors and room entries (`office`) allow.
pub(super) fn walk_waypoints(
    office: &super::office_config::OfficeConfig,
    plan: &crate::map::FloorPlan,
    waypoints: &[Coord<f64>],
    config: &WalkConfig,
    rng: &mut Pcg64Mcg,
) -> Result<TruePath> {
    let cap = (office.corridor_width / 2.0).min(office.entry_depth);
    let route = Route::rounded(waypoints, config.corner_radius.min(cap));
    walk(plan, &route, config, rng)
}

/// Walks `route` stride by stride over the surfaces of `plan` (level 0), from the route's
/// first point.
fn walk(
    plan: &crate::map::FloorPlan,
    route: &Route,
    config: &WalkConfig,
    rng: &mut Pcg64Mcg,
) -> Result<TruePath> {
    let on_floor = |q: Coord<f64>| plan.is_walkable(q.x, q.y, Some(0));
    let mut previous = route.at(0.0).0;
    let mut poses = Vec::with_capacity((route.length() / config.step_length_mean) as usize + 1);
    for stride in strides(route, config.gait(), |_| None, rng) {
        let on_route = stride.on_route;
        if !on_floor(on_route) {
            return Err(Error::Simulation(format!(
                "simulated route leaves the floor at ({:.3}, {:.3}); the building's layout is inconsistent",
                on_route.x, on_route.y
            )));
        }
        let q = if on_floor(stride.wandered) {
            stride.wandered
        } else {
            on_route
        };
        let heading = wrap_angle((q.y - previous.y).atan2(q.x - previous.x));
        poses.push(TruePose {
            t: stride.t,
            x: q.x,
            y: q.y,
            z: 0.0,
            level: 0,
            heading,
        });
        previous = q;
    }
    Ok(TruePath { poses })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::office_config::OfficeConfig;
    use geo::Contains;

    fn office() -> Office {
        Office::new(&OfficeConfig::default()).expect("office")
    }

    /// Eastward crossings of `x = 10` in the south corridor (between doors): one per lap.
    fn laps(path: &TruePath) -> usize {
        path.poses
            .windows(2)
            .filter(|w| w[0].x < 10.0 && w[1].x >= 10.0 && w[1].y.abs() < 0.9)
            .count()
    }

    /// Entries into rooms (a pose in a room whose previous pose is not).
    fn room_visits(office: &Office, path: &TruePath) -> usize {
        let inside = |p: &TruePose| {
            office
                .rooms
                .iter()
                .position(|r| r.area.to_polygon().contains(&Coord { x: p.x, y: p.y }))
        };
        path.poses
            .windows(2)
            .filter(|w| inside(&w[1]).is_some() && inside(&w[1]) != inside(&w[0]))
            .count()
    }

    #[test]
    fn default_walk_has_three_laps_with_room_visits_on_the_floor() {
        let o = office();
        let config = WalkConfig::default();
        for seed in 0..12 {
            let path = simulate_walk(&o, &config, seed).expect("walk");
            assert!(
                (400..=700).contains(&path.len()),
                "seed {seed}: {} steps",
                path.len()
            );
            assert_eq!(laps(&path), 3, "seed {seed}");
            let visits = room_visits(&o, &path);
            assert!((6..=12).contains(&visits), "seed {seed}: {visits} visits");
            for p in &path.poses {
                assert!(
                    o.plan.is_walkable(p.x, p.y, Some(0)),
                    "seed {seed}: ({}, {}) off the floor",
                    p.x,
                    p.y
                );
            }
            // Strides, timing and the end point are realistic.
            let first = path.poses[0];
            assert!(first.x > 0.3 && first.y.abs() < 0.2 && first.heading.abs() < 0.3);
            let last = path.poses[path.len() - 1];
            assert!(last.x.hypot(last.y) < 0.5, "ends near the start: {last:?}");
            let speed = path.length() / last.t;
            assert!((1.0..1.5).contains(&speed), "speed {speed} m/s");
            assert!(
                path.poses
                    .windows(2)
                    .all(|w| w[1].t > w[0].t && w[1].heading.abs() <= std::f64::consts::PI)
            );
        }
    }

    #[test]
    fn rooms_inside_and_outside_the_loop_are_visited() {
        let o = office();
        let (mut inside, mut outside) = (false, false);
        for seed in 0..6 {
            let path = simulate_walk(&o, &WalkConfig::default(), seed).expect("walk");
            for p in &path.poses {
                for r in o
                    .rooms
                    .iter()
                    .filter(|r| r.area.to_polygon().contains(&Coord { x: p.x, y: p.y }))
                {
                    *(if r.inside_loop {
                        &mut inside
                    } else {
                        &mut outside
                    }) = true;
                }
            }
        }
        assert!(inside && outside);
    }

    #[test]
    fn walks_are_deterministic_per_seed() {
        let o = office();
        let config = WalkConfig::default();
        let a = simulate_walk(&o, &config, 7).expect("walk");
        assert_eq!(a, simulate_walk(&o, &config, 7).expect("walk"));
        assert_ne!(a, simulate_walk(&o, &config, 8).expect("walk"));
    }

    #[test]
    fn room_free_single_lap_follows_the_centre_line() {
        let o = office();
        let config = WalkConfig {
            laps: 1,
            min_rooms_per_lap: 0,
            max_rooms_per_lap: 0,
            wander_sigma: 0.0,
            ..Default::default()
        };
        let path = simulate_walk(&o, &config, 1).expect("walk");
        assert_eq!(room_visits(&o, &path), 0);
        // 88.8 m less the rounded corners' savings, in 0.7 m strides.
        assert!(
            (path.length() - o.lap_length()).abs() < 1.0,
            "{}",
            path.length()
        );
        assert!((120..=135).contains(&path.len()), "{}", path.len());
        assert!(path.poses.iter().all(|p| p.x.abs() < 1e-9
            || p.y.abs() < 1e-9
            || (p.x - 28.2).abs() < 1e-9
            || (p.y - 16.2).abs() < 1e-9
            || p.x.min(p.y).min(28.2 - p.x).min(16.2 - p.y) < 0.6));
    }

    #[test]
    fn invalid_walks_are_rejected() {
        let o = office();
        for config in [
            WalkConfig {
                laps: 0,
                ..Default::default()
            },
            WalkConfig {
                min_rooms_per_lap: 5,
                ..Default::default()
            },
            WalkConfig {
                step_frequency: f64::NAN,
                ..Default::default()
            },
            WalkConfig {
                revisit_probability: 1.5,
                ..Default::default()
            },
        ] {
            assert!(
                matches!(simulate_walk(&o, &config, 0), Err(Error::Config { .. })),
                "{config:?}"
            );
        }
        let config = WalkConfig {
            step_frequency: 9.0,
            ..Default::default()
        };
        let e = simulate_walk(&o, &config, 0).expect_err("out of range");
        assert_eq!(
            e.to_string(),
            "invalid configuration: walk.step_frequency = 9: must be in [0.2, 5] Hz"
        );
    }
}
