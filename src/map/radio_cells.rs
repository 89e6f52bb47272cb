//! Rooms and cells of a floor plan, the units of a radio map (Woodman & Harle 2009, sec. 4.1):
//! each room's bounding box is split into the fewest equal boxes with no edge longer than the
//! granularity, and a cell is the room's floor fragments inside one box. A cell never spans
//! two rooms.
//!
//! A **room** is a set of surfaces on one level: those sharing an explicit `room` property,
//! or else those joined by connections longer than `door_width` in total (a door — a shorter
//! passage — separates rooms; a corridor split into pieces, or a room split into several
//! polygons, stays one room), or by a connection between surfaces of different heights (a
//! stair's riser: the treads of a flight, like the stepped floor of a lecture theatre, belong
//! to the room they rise from — the paper's cells are 3D boxes of a room). Surfaces of
//! different levels are never one room.

use super::floor_plan::FloorPlan;
use super::floor_topology::{FloorTopology, SegmentKind};
use crate::error::{Error, Result};
use geo::{BooleanOps, BoundingRect, MultiPolygon, Rect};
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Fragments smaller than this are dropped from a cell, square metres.
const MIN_FRAGMENT_AREA: f64 = 1e-4;
/// An extent at most this much longer than a whole number of cells is rounding (GeoJSON
/// coordinates are kept to about a millimetre), not another row of cells, metres.
const EXTENT_SLACK: f64 = 2e-3;
/// Surfaces whose heights differ by more than this are joined by a stair's riser, metres.
const RISER_MIN: f64 = 1e-3;

/// Cell division's parameters; every default in one place.
///
/// | field         | default | meaning                                                    |
/// |---------------|---------|------------------------------------------------------------|
/// | `granularity` | 3 m     | longest edge of a cell's box                               |
/// | `door_width`  | 1.2 m   | connections this short or shorter are doors between rooms  |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CellConfig {
    /// Longest edge of a cell's box, metres.
    pub granularity: f64,
    /// Total connection length at or below which two surfaces are separate rooms, metres.
    pub door_width: f64,
}

impl Default for CellConfig {
    fn default() -> Self {
        Self {
            granularity: 3.0,
            door_width: 1.2,
        }
    }
}

impl CellConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `granularity` is outside [0.25, 100] m or `door_width` outside
    /// [0, 10] m.
    pub fn validate(&self) -> Result<()> {
        if !(self.granularity.is_finite() && (0.25..=100.0).contains(&self.granularity)) {
            return Err(crate::error::Error::config(
                "cells.granularity",
                self.granularity,
                "must be in [0.25, 100] metres",
            ));
        }
        if !(self.door_width.is_finite() && (0.0..=10.0).contains(&self.door_width)) {
            return Err(crate::error::Error::config(
                "cells.door_width",
                self.door_width,
                "must be in [0, 10] metres",
            ));
        }
        Ok(())
    }
}

/// A room: surfaces of one level.
#[derive(Debug, Clone, PartialEq)]
pub struct Room {
    /// The explicit `room` property, when the surfaces carry one.
    pub name: Option<String>,
    /// Floor level.
    pub level: i32,
    /// Its surfaces (indices into the plan's polygons).
    pub surfaces: Vec<u32>,
    /// Bounding box (min x, min y, max x, max y).
    pub bbox: [f64; 4],
    /// Boxes across and along: `nx × ny`, each at most the granularity on a side.
    pub boxes: (usize, usize),
}

/// One cell: the fragments of a room inside one box of its grid.
#[derive(Debug, Clone, PartialEq)]
pub struct RadioCell {
    /// Index of the room.
    pub room: usize,
    /// Floor level.
    pub level: i32,
    /// Box column and row in the room's grid.
    pub box_index: (usize, usize),
    /// The floor area of the cell.
    pub area: MultiPolygon<f64>,
}

/// The rooms and cells of a plan, with a point-to-cell lookup.
#[derive(Debug, Clone)]
pub struct CellMap {
    rooms: Vec<Room>,
    cells: Vec<RadioCell>,
    surface_room: Vec<usize>,
    /// Cell id of each (room, box); `usize::MAX` for boxes without floor.
    box_cell: Vec<Vec<usize>>,
}

impl CellMap {
    /// Divides every room of `plan` (whose `topology` tells the connections) into cells.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`CellConfig::validate`]; [`Error::Mismatch`] when
    /// `topology` has another number of surfaces than `plan` (built from another plan).
    pub fn build(plan: &FloorPlan, topology: &FloorTopology, config: &CellConfig) -> Result<Self> {
        config.validate()?;
        if plan.polygons.len() != topology.len() {
            return Err(Error::mismatch(
                "the topology was not built from this plan",
                "build the topology from the plan it is used with",
            ));
        }
        let groups = find_rooms(plan, topology, config.door_width);
        let mut rooms = Vec::with_capacity(groups.len());
        let mut surface_room = vec![0; plan.polygons.len()];
        let mut cells = Vec::new();
        let mut box_cell = Vec::with_capacity(groups.len());
        for (r, surfaces) in groups.into_iter().enumerate() {
            let parts: Vec<&geo::Polygon<f64>> = surfaces
                .iter()
                .map(|&s| &plan.polygons[s as usize].polygon)
                .collect();
            let bbox = parts
                .iter()
                .filter_map(|p| p.bounding_rect())
                .map(|b| [b.min().x, b.min().y, b.max().x, b.max().y])
                .reduce(|a, b| {
                    [
                        a[0].min(b[0]),
                        a[1].min(b[1]),
                        a[2].max(b[2]),
                        a[3].max(b[3]),
                    ]
                })
                .unwrap_or([0.0; 4]);
            // The fewest equal boxes with no edge longer than the granularity (an edge longer
            // by rounding only — a plan read back from WGS84 — does not need another box).
            let boxes = |extent: f64| {
                (((extent - EXTENT_SLACK) / config.granularity).ceil() as usize).max(1)
            };
            let (nx, ny) = (boxes(bbox[2] - bbox[0]), boxes(bbox[3] - bbox[1]));
            let (w, h) = (
                (bbox[2] - bbox[0]) / nx as f64,
                (bbox[3] - bbox[1]) / ny as f64,
            );
            let mut ids = vec![usize::MAX; nx * ny];
            for j in 0..ny {
                for i in 0..nx {
                    let x0 = bbox[0] + i as f64 * w;
                    let y0 = bbox[1] + j as f64 * h;
                    let cell_box = Rect::new((x0, y0), (x0 + w, y0 + h)).to_polygon();
                    // The room's surfaces in the box, dissolved into one valid multipolygon:
                    // adjacent surfaces (a stair's treads, a room drawn in parts) share edges,
                    // which GEOS-based tools reject as self-intersections.
                    let mut area = MultiPolygon::new(Vec::new());
                    for p in &parts {
                        let piece = p.intersection(&cell_box);
                        if geo::Area::unsigned_area(&piece) > MIN_FRAGMENT_AREA {
                            area = area.union(&piece);
                        }
                    }
                    area.0
                        .retain(|p| geo::Area::unsigned_area(p) > MIN_FRAGMENT_AREA);
                    if geo::Area::unsigned_area(&area) > MIN_FRAGMENT_AREA {
                        ids[j * nx + i] = cells.len();
                        cells.push(RadioCell {
                            room: r,
                            level: plan.polygons[surfaces[0] as usize].level,
                            box_index: (i, j),
                            area,
                        });
                    }
                }
            }
            for &s in &surfaces {
                surface_room[s as usize] = r;
            }
            box_cell.push(ids);
            rooms.push(Room {
                name: plan.polygons[surfaces[0] as usize].room.clone(),
                level: plan.polygons[surfaces[0] as usize].level,
                surfaces,
                bbox,
                boxes: (nx, ny),
            });
        }
        Ok(Self {
            rooms,
            cells,
            surface_room,
            box_cell,
        })
    }

    /// The rooms.
    #[must_use]
    pub fn rooms(&self) -> &[Room] {
        &self.rooms
    }

    /// The cells.
    #[must_use]
    pub fn cells(&self) -> &[RadioCell] {
        &self.cells
    }

    /// The room of a surface.
    #[must_use]
    pub fn room_of(&self, surface: u32) -> usize {
        self.surface_room[surface as usize]
    }

    /// The cell holding `(x, y)` on `surface` (the point's room's box; boxes are closed on
    /// their low sides), or `None` when that box holds no floor.
    #[must_use]
    pub fn cell_at(&self, surface: u32, x: f64, y: f64) -> Option<usize> {
        let r = *self.surface_room.get(surface as usize)?;
        let room = &self.rooms[r];
        let (nx, ny) = room.boxes;
        let b = room.bbox;
        let index = |v: f64, lo: f64, hi: f64, n: usize| {
            let f = if hi > lo { (v - lo) / (hi - lo) } else { 0.0 };
            ((f * n as f64).floor().max(0.0) as usize).min(n - 1)
        };
        let (i, j) = (index(x, b[0], b[2], nx), index(y, b[1], b[3], ny));
        let id = self.box_cell[r][j * nx + i];
        (id != usize::MAX).then_some(id)
    }
}

/// Surfaces grouped into rooms, each group in ascending order, groups by their first surface.
fn find_rooms(plan: &FloorPlan, topology: &FloorTopology, door_width: f64) -> Vec<Vec<u32>> {
    let n = plan.polygons.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let join = |parent: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (root(parent, a), root(parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    };
    // Explicit rooms: the same `room` on the same level.
    let mut named: FxHashMap<(i32, &str), usize> = FxHashMap::default();
    for (i, f) in plan.polygons.iter().enumerate() {
        if let Some(room) = f.room.as_deref() {
            let first = *named.entry((f.level, room)).or_insert(i);
            join(&mut parent, first, i);
        }
    }
    // Wide passages, and stairs' risers, between surfaces without an explicit room.
    let mut shared: FxHashMap<(u32, u32), f64> = FxHashMap::default();
    for s in topology.segments() {
        if let SegmentKind::Connection { a, b } = s.kind {
            *shared.entry((a.min(b), a.max(b))).or_default() +=
                (s.b[0] - s.a[0]).hypot(s.b[1] - s.a[1]);
        }
    }
    let mut wide: Vec<((u32, u32), f64)> = shared.into_iter().collect();
    wide.sort_by_key(|(k, _)| *k);
    for ((a, b), length) in wide {
        let (fa, fb) = (&plan.polygons[a as usize], &plan.polygons[b as usize]);
        let riser = (fa.z - fb.z).abs() > RISER_MIN;
        if (length > door_width || riser)
            && fa.room.is_none()
            && fb.room.is_none()
            && fa.level == fb.level
        {
            join(&mut parent, a as usize, b as usize);
        }
    }
    let mut groups: FxHashMap<usize, Vec<u32>> = FxHashMap::default();
    for i in 0..n {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(i as u32);
    }
    let mut groups: Vec<Vec<u32>> = groups.into_values().collect();
    groups.sort_by_key(|g| g[0]);
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{FloorPolygon, TopologyConfig};

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64, room: Option<&str>) -> FloorPolygon {
        FloorPolygon {
            polygon: Rect::new((x0, y0), (x1, y1)).to_polygon(),
            level: 0,
            z: 0.0,
            name: None,
            room: room.map(str::to_string),
        }
    }

    fn build(plan: &FloorPlan, granularity: f64) -> CellMap {
        let topology = FloorTopology::build(plan, &TopologyConfig::default()).expect("topology");
        CellMap::build(
            plan,
            &topology,
            &CellConfig {
                granularity,
                ..Default::default()
            },
        )
        .expect("cells")
    }

    #[test]
    fn doors_separate_rooms_and_wide_passages_join_pieces() {
        // A 10 m corridor in two pieces (joined over 2 m), a door, and a 7 × 4 m room.
        let plan = FloorPlan {
            polygons: vec![
                rect(0.0, 0.0, 5.0, 2.0, None),
                rect(5.0, 0.0, 10.0, 2.0, None),
                rect(2.0, 2.0, 2.9, 2.2, None),
                rect(0.0, 2.2, 7.0, 6.2, None),
            ],
            ..Default::default()
        };
        let cells = build(&plan, 3.0);
        // Rooms: the corridor, the door, the room.
        assert_eq!(cells.rooms().len(), 3);
        assert_eq!(cells.room_of(0), cells.room_of(1));
        assert_ne!(cells.room_of(0), cells.room_of(3));
        let room = &cells.rooms()[cells.room_of(3)];
        // 7 m × 4 m at 3 m: 3 × 2 boxes of 2.33 m × 2 m.
        assert_eq!(room.boxes, (3, 2));
        // At 2 m, 4 m is two boxes, also when rounding makes it a hair longer.
        assert_eq!(
            build(&plan, 2.0 * (1.0 - 1e-12)).rooms()[cells.room_of(3)].boxes,
            (4, 2)
        );
        assert_eq!(build(&plan, 2.0).rooms()[cells.room_of(3)].boxes, (4, 2));
        let corridor = &cells.rooms()[cells.room_of(0)];
        assert_eq!(corridor.boxes, (4, 1));
        // Cells cover each room's area exactly, never crossing rooms.
        let area: f64 = cells
            .cells()
            .iter()
            .filter(|c| c.room == cells.room_of(3))
            .map(|c| geo::Area::unsigned_area(&c.area))
            .sum();
        assert!((area - 28.0).abs() < 1e-6);
        let a = cells.cell_at(3, 0.5, 2.5).expect("cell");
        let b = cells.cell_at(3, 6.5, 6.0).expect("cell");
        assert_ne!(a, b);
        assert_eq!(cells.cells()[a].box_index, (0, 0));
        assert_eq!(cells.cells()[b].box_index, (2, 1));
        assert_eq!(cells.cell_at(0, 1.0, 1.0), cells.cell_at(1, 1.0, 1.0));
    }

    #[test]
    fn a_stairs_treads_join_the_landing_they_rise_from() {
        // A landing and three 1 m wide treads rising 0.2 m each: narrower than a door, but
        // joined by risers; a door-width step at the same height still separates.
        let tread = |i: f64| FloorPolygon {
            z: 0.2 * (i + 1.0),
            ..rect(3.0 + 0.3 * i, 0.0, 3.3 + 0.3 * i, 1.0, None)
        };
        let plan = FloorPlan {
            polygons: vec![
                rect(0.0, 0.0, 3.0, 2.0, None),
                tread(0.0),
                tread(1.0),
                tread(2.0),
                rect(0.0, -1.0, 1.0, 0.0, None),
            ],
            ..Default::default()
        };
        let cells = build(&plan, 3.0);
        let landing = cells.room_of(0);
        assert!((1..4).all(|s| cells.room_of(s) == landing));
        assert_ne!(cells.room_of(4), landing);
    }

    #[test]
    fn explicit_rooms_win_and_l_shapes_leave_empty_boxes() {
        // An L-shaped room of two polygons named alike, touching over 1 m only.
        let plan = FloorPlan {
            polygons: vec![
                rect(0.0, 0.0, 6.0, 1.0, Some("lab")),
                rect(0.0, 1.0, 1.0, 6.0, Some("lab")),
            ],
            ..Default::default()
        };
        let cells = build(&plan, 3.0);
        assert_eq!(cells.rooms().len(), 1);
        assert_eq!(cells.rooms()[0].name.as_deref(), Some("lab"));
        // 2 × 2 boxes; the one away from both arms holds no floor.
        assert_eq!(cells.cells().len(), 3);
        assert_eq!(
            cells
                .cell_at(0, 5.0, 0.5)
                .map(|c| cells.cells()[c].box_index),
            Some((1, 0))
        );
        assert_eq!(cells.cell_at(1, 4.0, 4.0), None);
    }

    #[test]
    fn the_tower_divides_into_cells_on_every_floor() {
        let tower = crate::sim::Tower::new(&Default::default()).expect("tower");
        let cells = build(&tower.plan, 3.0);
        for level in 0..3 {
            assert!(cells.cells().iter().filter(|c| c.level == level).count() > 80);
        }
        // Every room's cells add up to its floor area.
        let plan_area: f64 = tower
            .plan
            .polygons
            .iter()
            .map(|p| geo::Area::unsigned_area(&p.polygon))
            .sum();
        let cell_area: f64 = cells
            .cells()
            .iter()
            .map(|c| geo::Area::unsigned_area(&c.area))
            .sum();
        assert!(
            (plan_area - cell_area).abs() < 1e-3 * plan_area,
            "{plan_area} {cell_area}"
        );
        assert!(
            CellConfig {
                granularity: 0.0,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
