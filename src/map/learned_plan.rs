//! A learned hexagon map as a walkable floor plan: the walkable area the walks revealed,
//! in the same polygon contract as a drawn plan ([`FloorPlan`]), so that `track` and
//! `survey` run on buildings that have no plan.
//!
//! A hexagon is walkable when the walks passed through it at least `min_visits` times
//! ([`super::HexCell::visits`]). The walkable hexagons are dissolved into polygons (geo's
//! boolean union) and grown by `grow` (geo's buffer: the body's half-width beside the
//! feet); holes smaller than `hole_area` — a pillar, a desk, a hexagon the walks
//! happened to skip — are filled; pieces smaller than `min_area` (one or two stray
//! hexagons, a step that jumped) are dropped; and each polygon is simplified with
//! Visvalingam–Whyatt preserving topology, so the hexagons' zigzag becomes a wall without
//! two rings ever crossing. A map of several floors (FootSLAM's stacked per-level maps)
//! gives one plan level per floor, at the floor's height; a one-floor map gives one level,
//! `level` at height `z`.

use super::floor_plan::{FloorPlan, FloorPolygon};
use super::hex_transitions::HexMapSnapshot;
use crate::error::{Error, Result};
use crate::geometry::HexGrid;
use geo::{Area, Buffer, LineString, MultiPolygon, Polygon, SimplifyVwPreserve, unary_union};
use serde::{Deserialize, Serialize};

/// Settings of [`walkable_plan`]; every default in one place.
///
/// | field        | default | meaning                                                    |
/// |--------------|---------|------------------------------------------------------------|
/// | `min_visits` | 1       | passes through a hexagon that make it walkable             |
/// | `grow`       | 0.25 m  | the walkable hexagons' outline moved out by this much      |
/// | `hole_area`  | 4 m²    | holes smaller than this are filled                         |
/// | `min_area`   | 2 m²    | walkable pieces smaller than this are dropped              |
/// | `simplify`   | 1.5     | Visvalingam–Whyatt tolerance, in hexagon notches (below)   |
/// | `level`      | 0       | the plan level of the map's level 0 (the walk's first floor) |
/// | `z`          | 0 m     | that level's floor height (other floors: plus their height) |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlanConfig {
    /// Passes through a hexagon that make it walkable. Default 1.
    pub min_visits: u32,
    /// The dissolved hexagons' outline is moved out by this much, metres: the hexagons hold
    /// where the feet went, and a walker (and a tracker's particles) needs the body's
    /// half-width either side. Default 0.25.
    pub grow: f64,
    /// Holes smaller than this are filled, m². Default 4.
    pub hole_area: f64,
    /// Walkable pieces smaller than this are dropped, m². Default 2.
    pub min_area: f64,
    /// Visvalingam–Whyatt tolerance: corners whose triangle with their neighbours is
    /// smaller than this many hexagon notches go (a notch is the triangle of three
    /// successive corners of a hexagon, `(√3/4)·r²`: 0.11 m² for 0.5 m hexagons). 0 keeps
    /// every corner. Default 1.5: the zigzag goes, real corners stay.
    pub simplify: f64,
    /// The plan level of the map's level 0 (the walk's first floor); the map's level `l`
    /// becomes plan level `level + l`. Default 0.
    pub level: i32,
    /// The floor height of the map's level 0, metres; the map's other levels are at this
    /// plus their height. Default 0.
    pub z: f64,
}

impl Default for PlanConfig {
    fn default() -> Self {
        Self {
            min_visits: 1,
            grow: 0.25,
            hole_area: 4.0,
            min_area: 2.0,
            simplify: 1.5,
            level: 0,
            z: 0.0,
        }
    }
}

impl PlanConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] for the first field out of its range: `min_visits` outside [1, 10⁶],
    /// `grow` outside [0, 10] m, `hole_area` or `min_area` outside [0, 10⁶] m², `simplify` outside
    /// [0, 100], `z` outside [−1000, 10 000] m, `level` beyond ±1000.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("plan.min_visits", f64::from(self.min_visits), 1.0..=1e6, "")?;
        crate::error::check_range("plan.grow", self.grow, 0.0..=10.0, "m")?;
        crate::error::check_range("plan.hole_area", self.hole_area, 0.0..=1e6, "m²")?;
        crate::error::check_range("plan.min_area", self.min_area, 0.0..=1e6, "m²")?;
        crate::error::check_range("plan.simplify", self.simplify, 0.0..=100.0, "notches")?;
        crate::error::check_range("plan.z", self.z, -1000.0..=10000.0, "m")?;
        if self.level.abs() > 1000 {
            return Err(crate::error::Error::config(
                "plan.level",
                self.level.to_string(),
                "must be in [-1000, 1000]",
            ));
        }
        Ok(())
    }
}

/// A walkable plan and how it was made.
///
/// The walkable plan of a loop of corridors, walked twice:
///
/// ```
/// use footslam::geometry::Pose2;
/// use footslam::map::{PlanConfig, map_of_path, walkable_plan};
///
/// // Twice round a 12 m × 6 m block, a step every metre, a left turn at each corner.
/// let (mut pose, mut path) = (Pose2::default(), Vec::new());
/// for _ in 0..2 {
///     for metres in [12, 6, 12, 6] {
///         for _ in 0..metres {
///             pose = pose.step(1.0, 0.0);
///             path.push(pose);
///         }
///         pose.heading += std::f64::consts::FRAC_PI_2;
///     }
/// }
/// let map = map_of_path(Pose2::default(), &path, &vec![0; path.len()], 0.5, 0.8);
///
/// let learned = walkable_plan(&map, &PlanConfig::default())?;
/// assert_eq!(learned.plan.levels(), [0]);
/// assert!(learned.plan.is_walkable(6.0, 0.0, Some(0))); // the corridors
/// assert!(learned.plan.is_walkable(12.0, 3.0, Some(0)));
/// assert!(!learned.plan.is_walkable(6.0, 3.0, Some(0))); // the block, never walked
/// assert!(learned.area_m2 > 30.0 && learned.area_m2 < 72.0);
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LearnedPlan {
    /// The plan: one polygon per walkable piece, per level.
    pub plan: FloorPlan,
    /// Hexagons with at least `min_visits` passes.
    pub hexagons: usize,
    /// Hexagons of the map with fewer.
    pub hexagons_left_out: usize,
    /// Holes filled.
    pub holes_filled: usize,
    /// Pieces dropped as too small.
    pub pieces_dropped: usize,
    /// Walkable area of the plan, m².
    pub area_m2: f64,
}

/// The walkable plan of `map` (see the module documentation), one plan level per level of
/// the map (`config.level` plus the map's level, at `config.z` plus its height).
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`PlanConfig::validate`]; [`Error::NotEnough`] when no
/// hexagon has `min_visits` visits, or when every walkable piece is smaller than `min_area`.
pub fn walkable_plan(map: &HexMapSnapshot, config: &PlanConfig) -> Result<LearnedPlan> {
    config.validate()?;
    let walkable = map
        .cells
        .iter()
        .filter(|c| c.visits() >= config.min_visits)
        .count();
    if walkable == 0 {
        return Err(Error::not_enough(
            format!(
                "no hexagon of the map has {} or more visits ({} hexagons, at most {} visits)",
                config.min_visits,
                map.cells.len(),
                map.cells.iter().map(|c| c.visits()).max().unwrap_or(0)
            ),
            "lower --min-visits",
        ));
    }
    let (mut holes_filled, mut pieces_dropped) = (0, 0);
    let mut surfaces = Vec::new();
    for level in map.cell_levels() {
        let pieces = level_pieces(map, level, config, &mut holes_filled, &mut pieces_dropped);
        let (number, z) = (config.level + level, config.z + map.level_height(level));
        surfaces.extend(
            pieces
                .into_iter()
                .enumerate()
                .map(|(i, polygon)| FloorPolygon {
                    polygon,
                    level: number,
                    z,
                    name: Some(format!("walkable {}", i + 1)),
                    room: None,
                }),
        );
    }
    if surfaces.is_empty() {
        return Err(Error::not_enough(
            format!(
                "every walkable piece of the map is smaller than {} m²",
                config.min_area
            ),
            "lower plan.min_area",
        ));
    }
    let area_m2 = surfaces.iter().map(|s| s.polygon.unsigned_area()).sum();
    Ok(LearnedPlan {
        plan: FloorPlan {
            polygons: surfaces,
            barriers: Vec::new(),
        },
        hexagons: walkable,
        hexagons_left_out: map.cells.len() - walkable,
        holes_filled,
        pieces_dropped,
        area_m2,
    })
}

/// The walkable pieces of one level of `map`, largest first (so that a level's first
/// polygon is its main floor), counting the holes filled and pieces dropped.
fn level_pieces(
    map: &HexMapSnapshot,
    level: i32,
    config: &PlanConfig,
    holes_filled: &mut usize,
    pieces_dropped: &mut usize,
) -> Vec<Polygon<f64>> {
    let grid = HexGrid::new(map.radius);
    let hexagons: Vec<Polygon<f64>> = map
        .cells
        .iter()
        .filter(|c| c.level == level && c.visits() >= config.min_visits)
        .map(|c| {
            let mut ring: Vec<(f64, f64)> = grid.corners(c.hex).to_vec();
            ring.push(ring[0]);
            Polygon::new(LineString::from(ring), vec![])
        })
        .collect();
    if hexagons.is_empty() {
        return Vec::new();
    }
    let mut union: MultiPolygon<f64> = unary_union(&hexagons);
    if config.grow > 0.0 {
        union = union.buffer(config.grow);
    }
    let notch = 3f64.sqrt() / 4.0 * map.radius * map.radius;
    let mut polygons = Vec::new();
    for piece in union {
        let (exterior, interiors) = piece.into_inner();
        let kept: Vec<LineString<f64>> = interiors
            .into_iter()
            .filter(|hole| {
                let small = Polygon::new(hole.clone(), vec![]).unsigned_area() < config.hole_area;
                *holes_filled += usize::from(small);
                !small
            })
            .collect();
        let filled = Polygon::new(exterior, kept);
        if filled.unsigned_area() < config.min_area {
            *pieces_dropped += 1;
            continue;
        }
        polygons.push(if config.simplify > 0.0 {
            filled.simplify_vw_preserve(config.simplify * notch)
        } else {
            filled
        });
    }
    polygons.sort_by(|a, b| b.unsigned_area().total_cmp(&a.unsigned_area()));
    polygons
}

/// `plan` grown by `margin` metres on every side, for tracking on a learned plan: its edges
/// are where the walks that made it stopped, not walls, and a new walker steps past them
/// (into the far side of a room the walks only crossed). The surfaces of each level are
/// dissolved and buffered, named `walkable N` per level, largest first. Only for plans with
/// one height per level (learned plans).
///
/// # Errors
///
/// [`Error::Config`] when `margin` is outside [0, 5] m; [`Error::InvalidData`] naming a level whose
/// surfaces lie at several heights (stairs, a stepped floor), which growing would merge.
pub fn grow_plan(plan: &FloorPlan, margin: f64) -> Result<FloorPlan> {
    crate::error::check_range("plan margin", margin, 0.0..=5.0, "m")?;
    if margin == 0.0 {
        return Ok(plan.clone());
    }
    let levels = plan.levels();
    let mut grown = FloorPlan {
        polygons: Vec::new(),
        barriers: plan.barriers.clone(),
    };
    for level in levels {
        let surfaces: Vec<&FloorPolygon> =
            plan.polygons.iter().filter(|p| p.level == level).collect();
        let z = surfaces[0].z;
        if let Some(other) = surfaces.iter().find(|p| (p.z - z).abs() > 1e-6) {
            return Err(Error::invalid(
                format!("level {level}"),
                format!(
                    "has surfaces at heights {z} m and {} m: only a plan with one height per \
                     level (a learned plan) can be grown",
                    other.z
                ),
            ));
        }
        let polygons: Vec<Polygon<f64>> = surfaces.iter().map(|p| p.polygon.clone()).collect();
        let mut pieces: Vec<Polygon<f64>> = unary_union(&polygons).buffer(margin).0;
        pieces.sort_by(|a, b| b.unsigned_area().total_cmp(&a.unsigned_area()));
        grown.polygons.extend(
            pieces
                .into_iter()
                .enumerate()
                .map(|(i, polygon)| FloorPolygon {
                    polygon,
                    level,
                    z,
                    name: Some(format!("walkable {}", i + 1)),
                    room: None,
                }),
        );
    }
    Ok(grown)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Hex;
    use crate::map::HexCell;

    /// Every hexagon of a grid of `radius` whose centre lies in `inside`, each passed `visits`
    /// times.
    fn map_of(radius: f64, inside: impl Fn(f64, f64) -> bool, visits: u32) -> HexMapSnapshot {
        let grid = HexGrid::new(radius);
        let mut cells = Vec::new();
        for q in -80..80 {
            for r in -80..80 {
                let hex = Hex::new(q, r);
                let (x, y) = grid.center(hex);
                if inside(x, y) {
                    cells.push(HexCell {
                        hex,
                        counts: [visits, visits, 0, 0, 0, 0],
                        level: 0,
                    });
                }
            }
        }
        HexMapSnapshot {
            radius,
            alpha: 0.8,
            cells,
            levels: Vec::new(),
        }
    }

    #[test]
    fn a_ring_corridor_becomes_one_polygon_with_its_courtyard_kept() {
        // A 3 m wide corridor round an 8 m × 4 m courtyard, a pillar-sized gap in it, and a
        // stray hexagon far away.
        let corridor = |x: f64, y: f64| {
            let outer = (0.0..14.0).contains(&x) && (0.0..10.0).contains(&y);
            let court = (3.0..11.0).contains(&x) && (3.0..7.0).contains(&y);
            let pillar = (x - 7.0).hypot(y - 1.5) < 0.7;
            let stray = (x - 30.0).hypot(y - 30.0) < 0.5;
            (outer && !court && !pillar) || stray
        };
        let map = map_of(0.5, corridor, 1);
        let learned = walkable_plan(&map, &PlanConfig::default()).expect("plan");
        assert_eq!(learned.plan.polygons.len(), 1, "{learned:?}");
        assert_eq!(learned.pieces_dropped, 1);
        assert!(learned.holes_filled >= 1, "the pillar's hole");
        let p = &learned.plan.polygons[0].polygon;
        assert_eq!(p.interiors().len(), 1, "the courtyard stays a hole");
        // Area close to the corridor's 108 m² grown by 0.25 m along its 72 m of walls
        // (18 m²); hexagon edges cut it within a cell.
        assert!(
            (118.0..140.0).contains(&learned.area_m2),
            "{}",
            learned.area_m2
        );
        assert!(learned.plan.is_walkable(7.0, 1.5, Some(0)), "pillar filled");
        assert!(learned.plan.is_walkable(1.0, 5.0, Some(0)));
        assert!(!learned.plan.is_walkable(7.0, 5.0, Some(0)), "courtyard");
        assert!(
            !learned.plan.is_walkable(30.0, 30.0, Some(0)),
            "stray dropped"
        );
        // Simplified: far fewer corners than the hexagons' zigzag.
        let zigzag = walkable_plan(
            &map,
            &PlanConfig {
                simplify: 0.0,
                ..Default::default()
            },
        )
        .expect("plan");
        let corners = |l: &LearnedPlan| l.plan.polygons[0].polygon.exterior().0.len();
        assert!(corners(&learned) * 2 < corners(&zigzag));
    }

    #[test]
    fn visits_below_the_threshold_are_left_out_and_nothing_left_is_an_error() {
        let map = map_of(
            0.5,
            |x, y| (0.0..6.0).contains(&x) && (0.0..3.0).contains(&y),
            1,
        );
        let config = PlanConfig {
            min_visits: 2,
            ..Default::default()
        };
        let e = walkable_plan(&map, &config).expect_err("nothing walkable");
        assert!(e.to_string().contains("--min-visits"), "{e}");
        let bad = PlanConfig {
            hole_area: f64::NAN,
            ..Default::default()
        };
        assert!(walkable_plan(&map, &bad).is_err());
    }

    #[test]
    fn growing_a_plan_widens_each_level_and_refuses_a_level_of_several_heights() {
        let map = map_of(
            0.5,
            |x, y| (0.0..10.0).contains(&x) && (0.0..2.0).contains(&y),
            2,
        );
        let learned = walkable_plan(&map, &PlanConfig::default()).expect("plan");
        let grown = grow_plan(&learned.plan, 0.25).expect("grown");
        let area = |p: &FloorPlan| {
            p.polygons
                .iter()
                .map(|f| f.polygon.unsigned_area())
                .sum::<f64>()
        };
        let perimeter = 2.0 * (10.0 + 2.0);
        let gained = area(&grown) - area(&learned.plan);
        assert!(
            (gained - 0.25 * perimeter).abs() < 0.3 * 0.25 * perimeter,
            "{gained} m² gained"
        );
        assert_eq!(grow_plan(&learned.plan, 0.0).expect("same"), learned.plan);
        assert!(grow_plan(&learned.plan, f64::NAN).is_err());
        let mut stairs = learned.plan.clone();
        let mut tread = stairs.polygons[0].clone();
        tread.z = 0.2;
        stairs.polygons.push(tread);
        let e = grow_plan(&stairs, 0.25).expect_err("two heights");
        assert!(e.to_string().contains("one height per level"), "{e}");
    }
}
