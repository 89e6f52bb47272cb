//! A synthetic office floor: a rectangular corridor loop with rooms inside and outside it,
//! each joined to the corridor by one door — the kind of building walked in Robertson et al.
//! 2009 (sec. 4.1: "round the corridor ... a number of rooms were entered and then left").
//!
//! All surfaces are on level 0 at height 0. Walls are gaps between polygons: a room is
//! `wall_thickness` away from the corridor and from its neighbours, and its door is a thin
//! rectangle filling the wall gap, touching both the corridor and the room.
//!
//! The plan is placed in the walk frame of the step-trace convention: the origin is the centre
//! of the corridor's south-west corner and the walker starts there facing east (heading 0), so
//! the corridor's centre line runs along `y = 0` (south side), `x = a` (east), `y = b` (north)
//! and `x = 0` (west), with `a = loop_width − corridor_width` and
//! `b = loop_height − corridor_width`.

pub use super::rooms::Room;

use super::office_config::OfficeConfig;
use super::rooms::{Side, side_rooms};
use crate::error::Result;
use crate::map::{FloorPlan, FloorPolygon};
use geo::{Coord, Polygon, Rect};

/// The office floor plan with its rooms' anchors.
#[derive(Debug, Clone, PartialEq)]
pub struct Office {
    /// The walkable surfaces: `"corridor"` (one polygon with a hole), then `"room N"` and
    /// `"door N"` for each room.
    pub plan: FloorPlan,
    /// The rooms, in lap order.
    pub rooms: Vec<Room>,
    /// The configuration it was built from.
    pub config: OfficeConfig,
}

/// The office floor plan for `config` (see the module docs for its placement).
///
/// # Errors
///
/// As [`Office::new`].
pub fn office_floor(config: &OfficeConfig) -> Result<FloorPlan> {
    Office::new(config).map(|o| o.plan)
}

impl Office {
    /// Builds the office for a validated `config`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `config` fails [`OfficeConfig::validate`], or a
    /// side has more rooms (`rooms_per_long_side`, `rooms_per_short_side`) than fit along it.
    pub fn new(config: &OfficeConfig) -> Result<Self> {
        config.validate()?;
        let c = config.corridor_width;
        let (a, b) = config.centre_line_size();
        let outer = Rect::new((-c / 2.0, -c / 2.0), (a + c / 2.0, b + c / 2.0));
        let inner = Rect::new((c / 2.0, c / 2.0), (a - c / 2.0, b - c / 2.0));
        let hole = inner.to_polygon().exterior().clone();
        let corridor = Polygon::new(outer.to_polygon().exterior().clone(), vec![hole]);
        let mut placed = Vec::new();
        for side in [Side::South, Side::East, Side::North, Side::West] {
            for inside_loop in [false, true] {
                placed.extend(side_rooms(config, side, inside_loop)?);
            }
        }
        placed.sort_by(|p, q| p.anchors.lap_position.total_cmp(&q.anchors.lap_position));
        let mut polygons = vec![surface(corridor, "corridor".into())];
        let mut rooms = Vec::with_capacity(placed.len());
        for (i, room) in placed.into_iter().enumerate() {
            let name = format!("room {}", i + 1);
            polygons.push(surface(room.anchors.area.to_polygon(), name.clone()));
            polygons.push(surface(
                room.door_area.to_polygon(),
                format!("door {}", i + 1),
            ));
            rooms.push(Room {
                name,
                ..room.anchors
            });
        }
        let plan = FloorPlan {
            polygons,
            ..Default::default()
        };
        Ok(Self {
            plan,
            rooms,
            config: *config,
        })
    }

    /// The corners of the corridor's centre line in lap order from the origin: south-west
    /// (the origin), south-east, north-east, north-west.
    pub fn loop_corners(&self) -> [Coord<f64>; 4] {
        let (a, b) = self.config.centre_line_size();
        [(0.0, 0.0), (a, 0.0), (a, b), (0.0, b)].map(Coord::from)
    }

    /// Length of one lap of the corridor's centre line, metres.
    #[must_use]
    pub fn lap_length(&self) -> f64 {
        let (a, b) = self.config.centre_line_size();
        2.0 * (a + b)
    }
}

fn surface(polygon: Polygon<f64>, name: String) -> FloorPolygon {
    FloorPolygon {
        polygon,
        level: 0,
        z: 0.0,
        name: Some(name),
        room: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;
    use geo::{Area, Contains, Intersects};

    fn office() -> Office {
        Office::new(&OfficeConfig::default()).expect("default office")
    }

    fn named<'a>(o: &'a Office, name: &str) -> &'a FloorPolygon {
        o.plan
            .polygons
            .iter()
            .find(|p| p.name.as_deref() == Some(name))
            .expect("named polygon")
    }

    #[test]
    fn default_office_has_rooms_inside_and_outside_the_loop() {
        let o = office();
        // 3 rooms on each long side and 1 on each short side, inside and outside.
        assert_eq!(o.rooms.len(), 16);
        assert_eq!(o.rooms.iter().filter(|r| r.inside_loop).count(), 8);
        assert_eq!(o.plan.polygons.len(), 1 + 2 * 16);
        // Corridor area: 30 × 18 outer minus 26.4 × 14.4 hole.
        let corridor = named(&o, "corridor");
        assert!((corridor.polygon.unsigned_area() - (540.0 - 380.16)).abs() < 1e-9);
        // Outer rooms reach 0.9 + 0.2 + 4 = 5.1 m beyond the centre line.
        let (x0, y0, x1, y1) = o.plan.bounds().expect("non-empty");
        for (got, want) in [(x0, -5.1), (y0, -5.1), (x1, 28.2 + 5.1), (y1, 16.2 + 5.1)] {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
        assert!((o.lap_length() - 88.8).abs() < 1e-9);
        let positions: Vec<f64> = o.rooms.iter().map(|r| r.lap_position).collect();
        assert!(positions.windows(2).all(|w| w[0] <= w[1]));
        assert!(o.plan.polygons.iter().all(|p| p.level == 0 && p.z == 0.0));
    }

    #[test]
    fn rooms_touch_the_corridor_only_through_their_doors() {
        let o = office();
        let corridor = &named(&o, "corridor").polygon;
        for (i, room) in o.rooms.iter().enumerate() {
            let n: usize = room
                .name
                .trim_start_matches("room ")
                .parse()
                .expect("number");
            let area = &named(&o, &room.name).polygon;
            let door = &named(&o, &format!("door {n}")).polygon;
            assert!(
                !area.intersects(corridor),
                "{} touches the corridor",
                room.name
            );
            assert!(
                door.intersects(corridor) && door.intersects(area),
                "door {n}"
            );
            for other in &o.rooms[i + 1..] {
                assert!(
                    !area.intersects(&named(&o, &other.name).polygon),
                    "{} / {}",
                    room.name,
                    other.name
                );
            }
            // Anchors: corridor point on the corridor, door in the door, entry and centre in the room.
            assert!(corridor.contains(&room.corridor));
            assert!(door.contains(&room.door));
            assert!(area.contains(&room.entry) && area.contains(&room.centre));
            assert!(o.plan.is_walkable(room.door.x, room.door.y, Some(0)));
        }
        // The wall between rooms and corridor is not walkable.
        assert!(!o.plan.is_walkable(5.0, -0.9 - 0.1, Some(0)));
        assert!(o.plan.is_walkable(0.0, 0.0, Some(0)));
    }

    #[test]
    fn impossible_layouts_are_rejected() {
        let too_many = OfficeConfig {
            rooms_per_long_side: 8,
            ..Default::default()
        };
        assert!(matches!(
            Office::new(&too_many),
            Err(Error::Config {
                field: "office.rooms_per_long_side",
                ..
            })
        ));
        let small = OfficeConfig {
            loop_height: 10.0,
            ..Default::default()
        };
        assert!(Office::new(&small).is_err());
        let wide_door = OfficeConfig {
            door_width: 5.0,
            ..Default::default()
        };
        assert!(Office::new(&wide_door).is_err());
        let nan = OfficeConfig {
            wall_thickness: f64::NAN,
            ..Default::default()
        };
        assert!(Office::new(&nan).is_err());
        let none = OfficeConfig {
            rooms_per_long_side: 0,
            rooms_per_short_side: 0,
            ..Default::default()
        };
        assert_eq!(
            Office::new(&none)
                .expect("corridor only")
                .plan
                .polygons
                .len(),
            1
        );
    }
}
