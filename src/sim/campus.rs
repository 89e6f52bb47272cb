//! The office of [`super::office`] in its grounds: a yard around the building, a lobby from
//! the corridor to a front door in the outer wall — the outdoor–indoor–outdoor setting of
//! Robertson et al. 2009, sec. 4.1 (walks that start and end outdoors under GPS).
//!
//! The lobby is a passage as wide as the corridor, running from the south side of the
//! corridor loop straight out to the building's south wall, in the widest gap between the
//! outer rooms of that side. The front door fills the outer wall (`wall_thickness` deep)
//! between the lobby and the yard. The yard is a band `yard_width` wide all round the
//! building's outer walls. The building's true outline is the rectangle of its outer walls;
//! the outline a user would have is that rectangle with every side moved by up to
//! `outline_error` (the plan is "known only to a few metres").

use super::office::Office;
use super::office_config::OfficeConfig;
use crate::error::{Error, Result};
use crate::map::{FloorPlan, FloorPolygon};
use geo::{Coord, Polygon, Rect};
use rand::RngExt;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Dimensions of the grounds; every default in one place (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CampusConfig {
    /// Width of the yard around the building. Default 15 m.
    pub yard_width: f64,
    /// Width of the lobby from the corridor to the front door. Default 1.8 m.
    pub lobby_width: f64,
    /// Width of the front door. Default 1.2 m.
    pub door_width: f64,
    /// Largest shift of each side of the outline given to the learner. Default 1.5 m.
    pub outline_error: f64,
}

impl Default for CampusConfig {
    fn default() -> Self {
        Self {
            yard_width: 15.0,
            lobby_width: 1.8,
            door_width: 1.2,
            outline_error: 1.5,
        }
    }
}

impl CampusConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `yard_width` is outside [5, 500] m, `lobby_width` outside
    /// [0.8, 10] m, `door_width` outside [0.6, 10] m or wider than the lobby, or `outline_error`
    /// outside [0, 10] m.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("campus.yard_width", self.yard_width, 5.0..=500.0, "m")?;
        crate::error::check_range("campus.lobby_width", self.lobby_width, 0.8..=10.0, "m")?;
        crate::error::check_range("campus.door_width", self.door_width, 0.6..=10.0, "m")?;
        crate::error::check_range("campus.outline_error", self.outline_error, 0.0..=10.0, "m")?;
        if self.door_width > self.lobby_width {
            return Err(crate::error::Error::config(
                "campus.door_width",
                self.door_width.to_string(),
                "must not exceed lobby_width",
            ));
        }
        Ok(())
    }
}

/// The office with its lobby, front door and yard.
#[derive(Debug, Clone, PartialEq)]
pub struct Campus {
    /// The office (its rooms and tour anchors).
    pub office: Office,
    /// Every walkable surface: the office's, `"lobby"`, `"front door"` and `"yard"`.
    pub plan: FloorPlan,
    /// The building's outer walls, true to the centimetre.
    pub outline: Rect<f64>,
    /// The lobby's axis (x) where it meets the corridor's centre line (y = 0).
    pub lobby: Coord<f64>,
    /// The middle of the front door.
    pub door: Coord<f64>,
    /// The yard's outer edge.
    pub grounds: Rect<f64>,
}

impl Campus {
    /// Builds the campus around the office of `office`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`CampusConfig::validate`], `office` fails
    /// [`Office::new`], or no gap between the south side's outer rooms is wide enough for the
    /// lobby.
    pub fn new(office: &OfficeConfig, config: &CampusConfig) -> Result<Self> {
        config.validate()?;
        let office = Office::new(office)?;
        let t = office.config.wall_thickness;
        let c = office.config.corridor_width;
        let (x0, y0, x1, y1) = office
            .plan
            .bounds()
            .ok_or_else(|| Error::Simulation("the office has no surfaces".into()))?;
        let (a, _) = office.config.centre_line_size();
        let x = lobby_axis(
            &office,
            x0.max(-c / 2.0),
            x1.min(a + c / 2.0),
            config.lobby_width + 2.0 * t,
        )
        .ok_or(crate::error::Error::config(
            "campus.lobby_width",
            config.lobby_width.to_string(),
            "no gap between the south side's outer rooms is wide enough for the lobby",
        ))?;
        let (hl, hd) = (config.lobby_width / 2.0, config.door_width / 2.0);
        let outline = Rect::new((x0 - t, y0 - t), (x1 + t, y1 + t));
        let w = config.yard_width;
        let grounds = Rect::new((x0 - t - w, y0 - t - w), (x1 + t + w, y1 + t + w));
        let mut plan = office.plan.clone();
        let surface = |polygon: Polygon<f64>, name: &str| FloorPolygon {
            polygon,
            level: 0,
            z: 0.0,
            name: Some(name.into()),
            room: None,
        };
        plan.polygons.push(surface(
            Rect::new((x - hl, y0), (x + hl, -c / 2.0)).to_polygon(),
            "lobby",
        ));
        plan.polygons.push(surface(
            Rect::new((x - hd, y0 - t), (x + hd, y0)).to_polygon(),
            "front door",
        ));
        plan.polygons.push(surface(
            Polygon::new(
                grounds.to_polygon().exterior().clone(),
                vec![outline.to_polygon().exterior().clone()],
            ),
            "yard",
        ));
        Ok(Self {
            office,
            plan,
            outline,
            lobby: Coord { x, y: 0.0 },
            door: Coord { x, y: y0 - t / 2.0 },
            grounds,
        })
    }

    /// True outdoors (in the yard or beyond).
    #[must_use]
    pub fn is_outdoors(&self, x: f64, y: f64) -> bool {
        let (lo, hi) = (self.outline.min(), self.outline.max());
        !(x > lo.x && x < hi.x && y > lo.y && y < hi.y)
    }

    /// The outline a user would have: the outer walls with each side moved by a uniform
    /// draw in `±error`.
    pub fn rough_outline(&self, error: f64, rng: &mut Pcg64Mcg) -> Polygon<f64> {
        let mut d = || {
            if error > 0.0 {
                rng.random_range(-error..=error)
            } else {
                0.0
            }
        };
        let (lo, hi) = (self.outline.min(), self.outline.max());
        Rect::new((lo.x + d(), lo.y + d()), (hi.x + d(), hi.y + d())).to_polygon()
    }
}

/// The x of the lobby's axis: the middle of the widest gap at least `needed` wide between the
/// outer rooms on the corridor's south side, within `[lo, hi]` (the corridor's extent).
fn lobby_axis(office: &Office, lo: f64, hi: f64, needed: f64) -> Option<f64> {
    let c = office.config.corridor_width;
    let mut taken: Vec<(f64, f64)> = office
        .rooms
        .iter()
        .filter(|r| !r.inside_loop && r.area.max().y <= -c / 2.0)
        .map(|r| (r.area.min().x, r.area.max().x))
        .collect();
    taken.sort_by(|p, q| p.0.total_cmp(&q.0));
    // Keep clear of the corridor's corners (the lobby must open onto the straight part).
    let (mut start, end) = (lo + c, hi - c);
    let mut best: Option<(f64, f64)> = None;
    for (a, b) in taken.into_iter().chain(std::iter::once((end, end))) {
        let gap = (start, a.min(end));
        if gap.1 - gap.0 >= needed && best.is_none_or(|g| gap.1 - gap.0 > g.1 - g.0 + 1e-9) {
            best = Some(gap);
        }
        start = start.max(b);
    }
    best.map(|(a, b)| (a + b) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Intersects;

    #[test]
    fn lobby_door_and_yard_connect_the_corridor_to_the_outside() {
        let campus =
            Campus::new(&OfficeConfig::default(), &CampusConfig::default()).expect("campus");
        let named = |n: &str| {
            campus
                .plan
                .polygons
                .iter()
                .find(|p| p.name.as_deref() == Some(n))
                .map(|p| p.polygon.clone())
                .expect(n)
        };
        let (lobby, door, yard) = (named("lobby"), named("front door"), named("yard"));
        assert!(lobby.intersects(&named("corridor")));
        assert!(door.intersects(&lobby) && door.intersects(&yard));
        assert!(!yard.intersects(&named("corridor")));
        // The default office's south outer rooms span 2.1–6.1, 12.1–16.1, 22.1–26.1 m: the
        // widest gaps are 6.1–12.1 and 16.1–22.1; the first is taken.
        assert!((campus.lobby.x - 9.1).abs() < 1e-9, "{:?}", campus.lobby);
        for p in [campus.lobby, campus.door] {
            assert!(campus.plan.is_walkable(p.x, p.y, Some(0)));
        }
        assert!(campus.is_outdoors(campus.door.x, campus.door.y - 1.0));
        assert!(!campus.is_outdoors(campus.lobby.x, campus.lobby.y));
        // No room touches the lobby.
        for r in &campus.office.rooms {
            assert!(!r.area.to_polygon().intersects(&lobby), "{}", r.name);
        }
    }

    #[test]
    fn rough_outline_stays_within_the_error() {
        use rand::SeedableRng;
        let campus =
            Campus::new(&OfficeConfig::default(), &CampusConfig::default()).expect("campus");
        let mut rng = Pcg64Mcg::seed_from_u64(3);
        let rough = campus.rough_outline(1.5, &mut rng);
        for (p, q) in rough
            .exterior()
            .coords()
            .zip(campus.outline.to_polygon().exterior().coords())
        {
            assert!((p.x - q.x).abs() <= 1.5 && (p.y - q.y).abs() <= 1.5);
        }
        assert!(
            Campus::new(
                &OfficeConfig::default(),
                &CampusConfig {
                    lobby_width: 8.0,
                    ..Default::default()
                }
            )
            .is_err()
        );
    }
}
