//! The tour's plan: laps of the corridor's centre line from the origin, counter-clockwise,
//! with detours into rooms chosen at random (Robertson et al. 2009, sec. 4.1: "a number of rooms
//! were entered and then left ... This pattern was repeated two more times").
//!
//! A detour runs from the corridor in front of the door straight through the door to the
//! room's entry anchor, on to one or more random points inside the room, back to the entry and
//! out the same way.

use super::office::Office;
use super::walk_config::WalkConfig;
use geo::{Coord, Rect};
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// Points walked to inside a room are redrawn while nearer than this to the previous one,
/// metres.
const MIN_ROOM_LEG: f64 = 1.0;

/// The waypoints of the whole walk: corridor corners and room detours in lap order.
pub fn plan_route(office: &Office, config: &WalkConfig, rng: &mut Pcg64Mcg) -> Vec<Coord<f64>> {
    let corners = office.loop_corners();
    let (a, b) = office.config.centre_line_size();
    // Corners after the start, with their lap positions; the lap ends back at the origin.
    let turns = [
        (a, corners[1]),
        (a + b, corners[2]),
        (2.0 * a + b, corners[3]),
        (office.lap_length(), corners[0]),
    ];
    let mut visited: Vec<usize> = Vec::new();
    let mut waypoints = vec![corners[0]];
    for lap in 0..config.laps {
        let mut chosen = choose_rooms(office.rooms.len(), config, lap, &visited, rng);
        chosen.sort_unstable(); // rooms are in lap order
        for &i in &chosen {
            if !visited.contains(&i) {
                visited.push(i);
            }
        }
        let mut rooms = chosen.iter().map(|&i| &office.rooms[i]).peekable();
        for &(position, corner) in &turns {
            while let Some(room) = rooms.next_if(|r| r.lap_position < position) {
                waypoints.extend([room.corridor, room.entry]);
                let mut from = room.entry;
                for _ in 0..rng.random_range(1..=config.max_points_per_room) {
                    from = point_in_room(room.area, config.room_margin, from, rng);
                    waypoints.push(from);
                }
                waypoints.extend([room.entry, room.corridor]);
            }
            waypoints.push(corner);
        }
    }
    waypoints
}

/// Indices of the rooms to visit on lap `lap`: distinct within the lap; after the first lap
/// each pick is a room visited before with probability `revisit_probability`.
fn choose_rooms(
    n: usize,
    config: &WalkConfig,
    lap: usize,
    visited: &[usize],
    rng: &mut Pcg64Mcg,
) -> Vec<usize> {
    let k = rng
        .random_range(config.min_rooms_per_lap..=config.max_rooms_per_lap)
        .min(n);
    let mut chosen: Vec<usize> = Vec::with_capacity(k);
    while chosen.len() < k {
        let old: Vec<usize> = visited
            .iter()
            .copied()
            .filter(|i| !chosen.contains(i))
            .collect();
        let revisit = lap > 0 && !old.is_empty() && rng.random_bool(config.revisit_probability);
        let pick = if revisit {
            old[rng.random_range(0..old.len())]
        } else {
            let free: Vec<usize> = (0..n).filter(|i| !chosen.contains(i)).collect();
            free[rng.random_range(0..free.len())]
        };
        chosen.push(pick);
    }
    chosen
}

/// A uniform point in `area` at least `margin` from its walls (its centre when too small),
/// redrawn a few times while it is nearer than [`MIN_ROOM_LEG`] to `from`.
fn point_in_room(area: Rect<f64>, margin: f64, from: Coord<f64>, rng: &mut Pcg64Mcg) -> Coord<f64> {
    let (lo, hi) = (area.min(), area.max());
    let coordinate = |l: f64, h: f64, rng: &mut Pcg64Mcg| {
        if h - l > 2.0 * margin {
            rng.random_range(l + margin..h - margin)
        } else {
            (l + h) / 2.0
        }
    };
    let mut point = from;
    for _ in 0..8 {
        let x = coordinate(lo.x, hi.x, rng);
        point = Coord {
            x,
            y: coordinate(lo.y, hi.y, rng),
        };
        if (point.x - from.x).hypot(point.y - from.y) >= MIN_ROOM_LEG {
            break;
        }
    }
    point
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::office_config::OfficeConfig;
    use rand::SeedableRng;

    #[test]
    fn rooms_are_distinct_within_a_lap_and_revisited_later() {
        let config = WalkConfig {
            revisit_probability: 1.0,
            ..Default::default()
        };
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        let first = choose_rooms(16, &config, 0, &[], &mut rng);
        assert!((2..=4).contains(&first.len()));
        let mut sorted = first.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), first.len());
        // With certain revisits, a later lap picks old rooms while any are left.
        let second = choose_rooms(16, &config, 1, &first, &mut rng);
        let old = second.iter().filter(|i| first.contains(i)).count();
        assert_eq!(old, second.len().min(first.len()));
        assert!(choose_rooms(0, &config, 0, &[], &mut rng).is_empty());
    }

    #[test]
    fn route_starts_and_ends_at_the_origin_through_every_corner() {
        let office = Office::new(&OfficeConfig::default()).expect("office");
        let config = WalkConfig {
            laps: 2,
            ..Default::default()
        };
        let waypoints = plan_route(&office, &config, &mut Pcg64Mcg::seed_from_u64(1));
        let origin = Coord { x: 0.0, y: 0.0 };
        assert_eq!(waypoints.first(), Some(&origin));
        assert_eq!(waypoints.last(), Some(&origin));
        for corner in office.loop_corners() {
            assert_eq!(
                waypoints.iter().filter(|&&w| w == corner).count(),
                if corner == origin { 3 } else { 2 }
            );
        }
        // Every waypoint is on the floor.
        assert!(
            waypoints
                .iter()
                .all(|w| office.plan.is_walkable(w.x, w.y, Some(0)))
        );
    }
}
