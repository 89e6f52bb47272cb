//! Survey tours through a [`Tower`]: every room of every floor swept lane by lane, every
//! corridor walked end to end and both stairwells walked between every pair of floors — the
//! walks a surveyor makes to build a radio map (Woodman & Harle 2009, sec. 4: coverage grows
//! with the share of cells walked through).
//!
//! The tour starts on floor 0 at the west end of the corridor. Floor `k` is surveyed towards
//! the east end when `k` is even and the west end when odd: room after room in the order of
//! their doors along the corridor, each swept in lanes `lane_spacing` apart (along the room's
//! longer side, from the lane nearest the door); at the far end of the corridor the stairs go
//! up. From the top floor the tour comes back down by the stairwells not yet walked, crossing
//! each intermediate floor's corridor, so that every flight of both stairwells is walked once.

use super::tower::Tower;
use geo::{Coord, Rect};

/// The survey tour's waypoints (starting on level 0) for a building whose rooms are swept
/// in lanes at most `lane_spacing` apart, at least `margin` from the walls.
#[must_use]
pub fn survey_waypoints(tower: &Tower, lane_spacing: f64, margin: f64) -> Vec<Coord<f64>> {
    let c = &tower.config;
    let floors = c.level_count();
    let length = c.corridor_length;
    let mut w = vec![Coord { x: 0.5, y: 0.0 }];
    for level in 0..floors {
        let eastward = level % 2 == 0;
        let mut rooms: Vec<_> = tower.rooms.iter().filter(|r| r.level == level).collect();
        rooms.sort_by(|a, b| a.corridor.x.total_cmp(&b.corridor.x));
        if !eastward {
            rooms.reverse();
        }
        for r in rooms {
            w.extend([r.corridor, r.door, r.entry]);
            w.extend(sweep(r.area, margin, lane_spacing, r.entry));
            w.extend([r.entry, r.door, r.corridor]);
        }
        let end = if eastward { length - 0.5 } else { 0.5 };
        w.push(Coord { x: end, y: 0.0 });
        if level + 1 < floors {
            w.extend(tower.stair_waypoints(eastward, true));
        }
    }
    // Down by the stairwells not yet walked: between floors k and k + 1 the way up used the
    // east stairs when k is even, so the way down takes the west stairs, and vice versa.
    for level in (1..floors).rev() {
        let east = (level - 1) % 2 != 0;
        w.push(Coord {
            x: if east { length - 0.5 } else { 0.5 },
            y: 0.0,
        });
        w.extend(tower.stair_waypoints(east, false));
    }
    w
}

/// Lanes across a rectangular room, entered at `entry`: along its longer side, at most
/// `spacing` apart and `margin` from the walls, from the lane nearest the entry, each lane
/// starting at the end nearest the entry's side (boustrophedon).
fn sweep(area: Rect<f64>, margin: f64, spacing: f64, entry: Coord<f64>) -> Vec<Coord<f64>> {
    let (lo, hi) = (area.min(), area.max());
    let along_y = hi.y - lo.y >= hi.x - lo.x;
    // (across, along) coordinates: lanes run along `along` at fixed `across` values.
    let (a0, a1, l0, l1, ea, el) = if along_y {
        (lo.x, hi.x, lo.y, hi.y, entry.x, entry.y)
    } else {
        (lo.y, hi.y, lo.x, hi.x, entry.y, entry.x)
    };
    let lanes = |from: f64, to: f64| -> Vec<f64> {
        let (from, to) = (from + margin, to - margin);
        if to <= from {
            return vec![(from + to) / 2.0];
        }
        let n = ((to - from) / spacing.max(0.1)).ceil().max(1.0) as usize;
        (0..=n)
            .map(|i| from + (to - from) * i as f64 / n as f64)
            .collect()
    };
    let mut across = lanes(a0, a1);
    if (ea - across[0]).abs() > (ea - across[across.len() - 1]).abs() {
        across.reverse();
    }
    let ends = {
        let (n, f) = (
            (l0 + margin).min(l1 - margin),
            (l1 - margin).max(l0 + margin),
        );
        if (el - n).abs() <= (el - f).abs() {
            (n, f)
        } else {
            (f, n)
        }
    };
    let point = |a: f64, l: f64| {
        if along_y {
            Coord { x: a, y: l }
        } else {
            Coord { x: l, y: a }
        }
    };
    across
        .iter()
        .enumerate()
        .flat_map(|(i, &a)| {
            let (s, e) = if i % 2 == 0 { ends } else { (ends.1, ends.0) };
            [point(a, s), point(a, e)]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::TowerConfig;

    #[test]
    fn lanes_cover_a_room_within_the_spacing() {
        let room = Rect::new((0.0, 1.2), (5.0, 7.2));
        let lanes = sweep(room, 0.6, 2.0, Coord { x: 1.0, y: 2.0 });
        // 3.8 m across at ≤ 2 m: 3 lanes, 6 points, starting near the entry.
        assert_eq!(lanes.len(), 6);
        assert!((lanes[0].x - 0.6).abs() < 1e-9 && (lanes[0].y - 1.8).abs() < 1e-9);
        assert!((lanes[1].y - 6.6).abs() < 1e-9);
        assert!((lanes[5].x - 4.4).abs() < 1e-9);
        for p in &lanes {
            assert!(p.x >= 0.6 - 1e-9 && p.x <= 4.4 + 1e-9 && p.y >= 1.8 - 1e-9);
        }
    }

    #[test]
    fn the_walked_survey_stays_on_the_plan_and_ends_with_the_tour() {
        use crate::map::{FloorTopology, TopologyConfig};
        use crate::sim::{TourKind, TowerWalkConfig, simulate_tower_walk};
        let tower = Tower::new(&TowerConfig::default()).expect("tower");
        let topology = FloorTopology::build(&tower.plan, &TopologyConfig::default()).expect("topo");
        let config = TowerWalkConfig {
            tour: TourKind::Survey,
            minutes: 60.0,
            ..Default::default()
        };
        let (start, path) = simulate_tower_walk(&tower, &topology, &config, 5).expect("walk");
        let minutes = path.poses.last().expect("poses").t / 60.0;
        assert!((15.0..40.0).contains(&minutes), "{minutes} min");
        crate::sim::tower_walk::walk_on_plan(&topology, &start, &path)
            .unwrap_or_else(|i| panic!("step {i} through a wall"));
        let mut levels = [0usize; 3];
        for p in &path.poses {
            levels[p.level as usize] += 1;
        }
        assert!(levels.iter().all(|&n| n > 300), "{levels:?}");
        assert_eq!((start.level, path.poses.last().expect("end").level), (0, 0));
    }

    #[test]
    fn the_tour_enters_every_room_and_both_stairwells_between_floors() {
        let tower = Tower::new(&TowerConfig::default()).expect("tower");
        let w = survey_waypoints(&tower, 1.5, 0.6);
        for r in &tower.rooms {
            assert!(
                w.iter().any(|p| r.area.min().x < p.x
                    && p.x < r.area.max().x
                    && r.area.min().y < p.y
                    && p.y < r.area.max().y),
                "room at {:?} not entered",
                r.corridor
            );
        }
        // Every flight at both ends: the half landings are west of x = -2.5 or east of 42.5,
        // visited four times each way (two pairs of floors, two stairwells).
        let west = w.iter().filter(|p| p.x < -4.0).count();
        let east = w.iter().filter(|p| p.x > 44.0).count();
        assert_eq!((west, east), (8, 8));
    }
}
