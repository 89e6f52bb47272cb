//! How many of a dataset's ground-truth waypoints lie on a floor plan's walkable area: the
//! check that an imported plan fits the walks (a waypoint off the plan is a place the
//! tracker cannot put the walker), for each choice of an ILC floor's walkable area.

use super::ilc_floor::{IlcFloor, Walkable};
use crate::error::Result;
use crate::io::Waypoint;
use crate::map::FloorPlan;
use serde::Serialize;

/// Below this share of waypoints on the walkable area an import is suspect (walkers went
/// where the plan does not reach).
pub const MIN_SHARE_ON: f64 = 0.95;

/// Waypoints on a plan's walkable area, of all.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct WalkableShare {
    /// Waypoints on the walkable area (any level).
    pub on: usize,
    /// Waypoints.
    pub total: usize,
}

impl WalkableShare {
    /// The share of `waypoints` on `plan`'s walkable area.
    #[must_use]
    pub fn of(plan: &FloorPlan, waypoints: &[Waypoint]) -> Self {
        let on = waypoints
            .iter()
            .filter(|w| plan.is_walkable(w.x, w.y, None))
            .count();
        Self {
            on,
            total: waypoints.len(),
        }
    }

    /// Waypoints off the walkable area.
    #[must_use]
    pub fn off(self) -> usize {
        self.total - self.on
    }

    /// Fewer than [`MIN_SHARE_ON`] of the waypoints on the walkable area.
    #[must_use]
    pub fn suspect(self) -> bool {
        (self.on as f64) < MIN_SHARE_ON * self.total as f64
    }
}

/// The share of `waypoints` on each choice of `floor`'s walkable area, outline first, where
/// `plan` is the floor's plan for `chosen` (not built again).
///
/// # Errors
///
/// As [`IlcFloor::plan`], for the choice other than `chosen`, whose plan is built here.
pub fn walkable_shares(
    floor: &IlcFloor,
    chosen: Walkable,
    plan: &FloorPlan,
    waypoints: &[Waypoint],
) -> Result<[(Walkable, WalkableShare); 2]> {
    let share = |choice: Walkable| -> Result<(Walkable, WalkableShare)> {
        let share = if choice == chosen {
            WalkableShare::of(plan, waypoints)
        } else {
            WalkableShare::of(&floor.plan(choice)?.0, waypoints)
        };
        Ok((choice, share))
    };
    Ok([share(Walkable::Outline)?, share(Walkable::Corridors)?])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::FloorPolygon;
    use geo::{LineString, Polygon};

    fn square(size: f64) -> FloorPlan {
        let ring = LineString::from(vec![
            (0.0, 0.0),
            (size, 0.0),
            (size, size),
            (0.0, size),
            (0.0, 0.0),
        ]);
        FloorPlan {
            polygons: vec![FloorPolygon {
                polygon: Polygon::new(ring, vec![]),
                level: 0,
                z: 0.0,
                name: None,
                room: None,
            }],
            barriers: Vec::new(),
        }
    }

    fn at(x: f64, y: f64) -> Waypoint {
        Waypoint {
            t: 0.0,
            x,
            y,
            level: None,
        }
    }

    #[test]
    fn counts_the_waypoints_on_the_plan() {
        let w: Vec<Waypoint> = (0..20).map(|i| at(0.5 + f64::from(i), 1.0)).collect();
        // 10 m square: 10 of 20 on it.
        let share = WalkableShare::of(&square(10.0), &w);
        assert_eq!((share.on, share.total, share.off()), (10, 20, 10));
        assert!(share.suspect());
        // 19 of 20 is 95 %: not suspect.
        let share = WalkableShare::of(&square(19.0), &w);
        assert_eq!(share.on, 19);
        assert!(!share.suspect());
        assert!(!WalkableShare::of(&square(1.0), &[]).suspect());
    }
}
