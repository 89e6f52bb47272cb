//! A synthetic multi-floor building, symmetric on purpose, for known-map tracking (the kind of
//! three-storey building of Woodman & Harle 2008, Fig. 4): on every floor a straight corridor
//! with rooms on both sides, and at each end of the corridor a stairwell of switchback stairs
//! built from treads.
//!
//! Frame: x east along the corridor (`0 ≤ x ≤ corridor_length`), y north, the corridor's
//! centre line on `y = 0`; floor `k` is level `k` at height `k × floor_height`.
//!
//! * The corridor is `corridor_width` wide; rooms lie `wall_thickness` beyond its sides, each
//!   joined to it by a door rectangle filling the wall gap; neighbouring rooms are
//!   `wall_thickness` apart.
//! * Optionally (`hall_width > 0`) one side of each floor has an open hall, open to the
//!   corridor over its whole width, where rooms would be.
//! * Room widths along the corridor, door positions and the hall's place come from a floor
//!   layout drawn from `layout_seed` (and the floor's index, unless `identical_floors`), so floors differ in
//!   layout and no floor is symmetric in itself; the stairwells and corridors are the same
//!   everywhere, and with `identical_floors` every floor is the same (the hard case: only
//!   changes of floor reveal the floor).
//! * West stairwell: a landing on every floor west of the corridor, then from each floor but
//!   the top a flight of treads running west in the north lane, a half landing, and a flight
//!   back east in the south lane arriving on the next floor's landing. Lanes are
//!   `wall_thickness` apart so their treads never touch. Each tread is one rise
//!   (`floor_height / (2 × treads + 2)`) above the previous; a tread's `level` is the nearest
//!   floor, `round(z / floor_height)` (the half landing belongs to the lower floor).
//! * The east stairwell is the west one turned 180° about the corridor's midpoint.

use super::tower_config::TowerConfig;

use crate::error::Result;
use crate::map::{FloorPlan, FloorPolygon};
use geo::{Coord, Rect};
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// One room with the anchors a walker steers by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TowerRoom {
    /// Floor level.
    pub level: i32,
    /// The room's floor.
    pub area: Rect<f64>,
    /// Point on the corridor's centre line in front of the door.
    pub corridor: Coord<f64>,
    /// Centre of the door.
    pub door: Coord<f64>,
    /// Point 0.8 m inside the room, straight in from the door.
    pub entry: Coord<f64>,
}

impl TowerRoom {
    /// The room `area` on `level` with its door at `door_x` on the corridor's north
    /// (`side` = 1) or south (−1) side.
    fn at(c: &TowerConfig, level: i32, area: Rect<f64>, door_x: f64, side: f64) -> Self {
        let (hw, t) = (c.corridor_width / 2.0, c.wall_thickness);
        Self {
            level,
            area,
            corridor: Coord { x: door_x, y: 0.0 },
            door: Coord {
                x: door_x,
                y: side * (hw + t / 2.0),
            },
            entry: Coord {
                x: door_x,
                y: side * (hw + t + 0.8),
            },
        }
    }
}

/// The building: its plan and the anchors of its rooms and stairs.
#[derive(Debug, Clone, PartialEq)]
pub struct Tower {
    /// Walkable surfaces.
    pub plan: FloorPlan,
    /// Rooms of every floor.
    pub rooms: Vec<TowerRoom>,
    /// The configuration.
    pub config: TowerConfig,
}

impl Tower {
    /// Builds the building for `config`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `config` fails [`TowerConfig::validate`].
    pub fn new(config: &TowerConfig) -> Result<Self> {
        config.validate()?;
        let c = config;
        let (l, hw, t) = (c.corridor_length, c.corridor_width / 2.0, c.wall_thickness);
        let mut polygons = Vec::new();
        let mut rooms = Vec::new();
        let h = c.floor_height;
        for (k, level) in (0..c.floors).zip(0i32..) {
            let z = k as f64 * h;
            let surface = |rect: Rect<f64>, z: f64, name: String| FloorPolygon {
                polygon: rect.to_polygon(),
                // The nearest floor; a half landing, exactly between, the lower one.
                level: (z / h - 1e-6).round() as i32,
                z,
                name: Some(name),
                room: None,
            };
            polygons.push(surface(
                Rect::new((0.0, -hw), (l, hw)),
                z,
                format!("corridor {k}"),
            ));
            let seed = if c.identical_floors {
                c.layout_seed
            } else {
                c.layout_seed ^ crate::random::mix(k as u64 + 1)
            };
            let mut rng = crate::random::stream(seed, 0, 0);
            let hall = hall_span(c, &mut rng);
            for north in [true, false] {
                let side = if north { 1.0 } else { -1.0 };
                let mut spans = Vec::new();
                match hall {
                    Some((on_north, x0, x1)) if on_north == north => {
                        let (y0, y1) = (hw, hw + t + c.room_depth);
                        let area = if north {
                            Rect::new((x0, y0), (x1, y1))
                        } else {
                            Rect::new((x0, -y1), (x1, -y0))
                        };
                        let tag = if north { "N" } else { "S" };
                        polygons.push(surface(area, z, format!("hall {k}{tag}")));
                        rooms.push(TowerRoom::at(c, level, area, (x0 + x1) / 2.0, side));
                        spans.extend(room_spans(c, &mut rng, t, x0 - t));
                        spans.extend(room_spans(c, &mut rng, x1 + t, l - t));
                    }
                    _ => spans.extend(room_spans(c, &mut rng, t, l - t)),
                }
                for (i, (x0, x1, door_x)) in spans.into_iter().enumerate() {
                    let (y0, y1) = (hw + t, hw + t + c.room_depth);
                    let area = if north {
                        Rect::new((x0, y0), (x1, y1))
                    } else {
                        Rect::new((x0, -y1), (x1, -y0))
                    };
                    let dw = c.door_width / 2.0;
                    let door = Rect::new((door_x - dw, side * hw), (door_x + dw, side * (hw + t)));
                    let tag = if north { "N" } else { "S" };
                    polygons.push(surface(area, z, format!("room {k}{tag}{}", i + 1)));
                    polygons.push(surface(door, z, format!("door {k}{tag}{}", i + 1)));
                    rooms.push(TowerRoom::at(c, level, area, door_x, side));
                }
            }
            for east in [false, true] {
                let place = |r: Rect<f64>| if east { turn_rect(r, l) } else { r };
                let end = if east { "east" } else { "west" };
                let landing = Rect::new(
                    (-c.landing_depth, -(t / 2.0 + c.lane_width)),
                    (0.0, t / 2.0 + c.lane_width),
                );
                polygons.push(surface(place(landing), z, format!("landing {k} {end}")));
                if k + 1 == c.floors {
                    continue;
                }
                for (rect, z, name) in flights(c, z) {
                    polygons.push(surface(place(rect), z, format!("{name} {k} {end}")));
                }
            }
        }
        Ok(Self {
            plan: FloorPlan {
                polygons,
                ..Default::default()
            },
            rooms,
            config: *config,
        })
    }

    /// The longest stride at `p` when it is in a stairwell beyond the floor landings: two
    /// treads (a foot-mounted sensor's stride spans one tread per foot); `None` elsewhere.
    #[must_use]
    pub fn stride_limit(&self, p: Coord<f64>) -> Option<f64> {
        let c = &self.config;
        let beyond = (-p.x).max(p.x - c.corridor_length) - c.landing_depth;
        (beyond > 0.0).then_some(2.0 * c.tread_depth)
    }

    /// Waypoints from the corridor's end at `level` through the stairwell at the west
    /// (`east = false`) or east end to the corridor's end one floor up (`up`) or down.
    #[must_use]
    pub fn stair_waypoints(&self, east: bool, up: bool) -> Vec<Coord<f64>> {
        let c = &self.config;
        let (lane, end, half) = (
            c.lane_centre(),
            c.flights_end(),
            c.flights_end() - c.lane_width / 2.0,
        );
        let landing = -c.landing_depth / 2.0;
        let mut w: Vec<Coord<f64>> = [
            (0.5, 0.0),
            (landing, 0.0),
            (landing, lane),
            (end, lane),
            (half, lane),
            (half, -lane),
            (end, -lane),
            (landing, -lane),
            (landing, 0.0),
            (0.5, 0.0),
        ]
        .into_iter()
        .map(|(x, y)| Coord { x, y })
        .collect();
        if !up {
            w.reverse();
        }
        if east {
            w.iter_mut().for_each(|p| *p = turn(*p, c.corridor_length));
        }
        w
    }
}

/// The floor's hall, if any: its side (north = true) and x extent, placed at random and
/// grown to the corridor's end or a neighbour room where the space left would be narrower
/// than a room.
fn hall_span(c: &TowerConfig, rng: &mut Pcg64Mcg) -> Option<(bool, f64, f64)> {
    let t = c.wall_thickness;
    let (lo, hi) = (t, c.corridor_length - t);
    if c.hall_width <= 0.0 || c.hall_width > hi - lo {
        return (c.hall_width > 0.0).then_some((rng.random_bool(0.5), lo, hi));
    }
    let north = rng.random_bool(0.5);
    let mut x0 = rng.random_range(lo..=hi - c.hall_width);
    let mut x1 = x0 + c.hall_width;
    if x0 - t - lo < c.min_room_width {
        x0 = lo;
    }
    if hi - (x1 + t) < c.min_room_width {
        x1 = hi;
    }
    Some((north, x0, x1))
}

/// Rooms along one side between `from` and `to`: `(x0, x1, door x)` from west to east, widths
/// drawn between the configured limits and the last room taking what is left; none when the
/// space is narrower than a room.
fn room_spans(c: &TowerConfig, rng: &mut Pcg64Mcg, from: f64, to: f64) -> Vec<(f64, f64, f64)> {
    let t = c.wall_thickness;
    let l = to;
    let mut spans = Vec::new();
    if to - from < c.min_room_width {
        return spans;
    }
    let mut x = from;
    loop {
        let left = l - x;
        let w = if left <= c.max_room_width {
            left
        } else {
            let w = rng.random_range(c.min_room_width..=c.max_room_width);
            // Never leave less than the narrowest room for the last one.
            if left - w - t < c.min_room_width {
                left
            } else {
                w
            }
        };
        let margin = 0.2 + c.door_width / 2.0;
        let door = x + rng.random_range(margin..=(w - margin).max(margin));
        spans.push((x, x + w, door));
        x += w + t;
        if x >= l - 1e-9 {
            break;
        }
    }
    spans
}

/// The stair surfaces from the floor at height `z` to the next: first flight (north lane,
/// running west), half landing, second flight (south lane, running east).
fn flights(c: &TowerConfig, z: f64) -> Vec<(Rect<f64>, f64, &'static str)> {
    let (d, r, n) = (c.tread_depth, c.rise(), c.treads);
    let (t, w) = (c.wall_thickness, c.lane_width);
    let x0 = -c.landing_depth;
    let north = (t / 2.0, t / 2.0 + w);
    let south = (-(t / 2.0 + w), -t / 2.0);
    let mut out = Vec::with_capacity(2 * n + 1);
    for i in 0..n {
        let (a, b) = (x0 - (i + 1) as f64 * d, x0 - i as f64 * d);
        out.push((
            Rect::new((a, north.0), (b, north.1)),
            z + (i + 1) as f64 * r,
            "tread up",
        ));
    }
    let end = c.flights_end();
    out.push((
        Rect::new((end - w, south.0), (end, north.1)),
        z + (n + 1) as f64 * r,
        "half landing",
    ));
    for j in 0..n {
        let (a, b) = (end + j as f64 * d, end + (j + 1) as f64 * d);
        out.push((
            Rect::new((a, south.0), (b, south.1)),
            z + (n + 2 + j) as f64 * r,
            "tread on",
        ));
    }
    out
}

/// `p` turned 180° about the corridor's midpoint.
fn turn(p: Coord<f64>, length: f64) -> Coord<f64> {
    Coord {
        x: length - p.x,
        y: -p.y,
    }
}

fn turn_rect(r: Rect<f64>, length: f64) -> Rect<f64> {
    Rect::new(turn(r.min(), length), turn(r.max(), length))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{FloorTopology, SegmentKind, TopologyConfig};

    #[test]
    fn three_floors_two_stairwells_and_connected_stairs() {
        let tower = Tower::new(&TowerConfig::default()).expect("tower");
        let plan = &tower.plan;
        let levels: std::collections::BTreeSet<i32> =
            plan.polygons.iter().map(|p| p.level).collect();
        assert_eq!(levels.len(), 3);
        let treads = plan
            .polygons
            .iter()
            .filter(|p| p.name.as_deref().is_some_and(|n| n.starts_with("tread")))
            .count();
        assert_eq!(treads, 2 * 2 * 2 * 8);
        let topology = FloorTopology::build(plan, &TopologyConfig::default()).expect("topology");
        // Every surface has a connection: nothing is unreachable.
        let mut connected = vec![false; plan.polygons.len()];
        for s in topology.segments() {
            if let SegmentKind::Connection { a, b } = s.kind {
                connected[a as usize] = true;
                connected[b as usize] = true;
            }
        }
        assert!(connected.iter().all(|&c| c));
        // Climbing the west stairs from floor 0 ends on floor 1's landing, 3 m up.
        let route = tower.stair_waypoints(false, true);
        let mut s = topology
            .locate(route[0].x, route[0].y, Some(0), None)
            .expect("start");
        for w in route.windows(2) {
            // Short hops, as a walker's steps.
            let n = ((w[1].x - w[0].x).hypot(w[1].y - w[0].y) / 0.5)
                .ceil()
                .max(1.0) as usize;
            for i in 0..n {
                let a = w[0] + (w[1] - w[0]) * (i as f64 / n as f64);
                let b = w[0] + (w[1] - w[0]) * ((i + 1) as f64 / n as f64);
                s = topology
                    .walk(s, [a.x as f32, a.y as f32], [b.x as f32, b.y as f32])
                    .unwrap_or_else(|| panic!("wall between {a:?} and {b:?}"));
            }
        }
        assert!((topology.z(s) - 3.0).abs() < 1e-6);
        assert_eq!(topology.level(s), 1);
        assert!(topology.total_area() > 3.0 * 500.0);
    }

    #[test]
    fn identical_floors_repeat_and_the_shell_turns_onto_itself() {
        let config = TowerConfig {
            identical_floors: true,
            ..Default::default()
        };
        let tower = Tower::new(&config).expect("tower");
        let rooms = |level: i32| -> Vec<Rect<f64>> {
            tower
                .rooms
                .iter()
                .filter(|r| r.level == level)
                .map(|r| r.area)
                .collect()
        };
        assert_eq!(rooms(0), rooms(1));
        assert_eq!(rooms(0), rooms(2));
        // Stairwells, landings and corridors: the same after a half turn.
        let shell: Vec<Rect<f64>> = tower
            .plan
            .polygons
            .iter()
            .filter(|p| {
                p.name
                    .as_deref()
                    .is_some_and(|n| !["room", "door", "hall"].iter().any(|p| n.starts_with(p)))
            })
            .map(|p| geo::BoundingRect::bounding_rect(&p.polygon).expect("rect"))
            .collect();
        for r in &shell {
            let t = turn_rect(*r, config.corridor_length);
            assert!(
                shell.iter().any(|q| (q.min() - t.min()).x.abs() < 1e-9
                    && (q.min() - t.min()).y.abs() < 1e-9
                    && (q.max() - t.max()).x.abs() < 1e-9),
                "{r:?}"
            );
        }
        // Different floors differ when not identical.
        let varied = Tower::new(&TowerConfig::default()).expect("tower");
        let widths = |level: i32| -> Vec<f64> {
            varied
                .rooms
                .iter()
                .filter(|r| r.level == level)
                .map(|r| r.area.width())
                .collect()
        };
        assert_ne!(widths(0), widths(1));
        assert!(
            Tower::new(&TowerConfig {
                treads: 2,
                ..Default::default()
            })
            .is_err()
        );
    }
}
