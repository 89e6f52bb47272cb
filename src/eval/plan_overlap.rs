//! How well a learned walkable plan matches the true one: precision (the share of the
//! learned walkable area that is truly walkable) and recall of visited space (the share of
//! the truly walkable area the walks passed near that the learned plan covers), by area.
//!
//! Both are measured on a square grid (`resolution` metres): a square counts where its
//! centre lies. "Visited space" is the true walkable area within `reach` metres of a true
//! position of the walks — what the walks could reveal — on the surface the walker stood
//! on or one touching it (a door, the next tread), so that reach does not pass through a
//! wall into a room nobody entered; such rooms are not held against the plan. Plans of several floors are compared level by level (a learned level
//! against the true level it stands for) and the areas summed.

use crate::error::{Error, Result, check_range};
use crate::geometry::RigidTransform;
use crate::map::FloorPlan;
use geo::{BoundingRect, Intersects, Point};
use std::collections::HashSet;
use std::ops::Bound::{Excluded, Unbounded};

/// Precision and recall of a learned plan, by area.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PlanOverlap {
    /// Learned walkable area that is truly walkable, over the learned walkable area.
    pub precision: f64,
    /// Visited true walkable area that the learned plan covers, over the visited area.
    pub recall: f64,
    /// Learned walkable area, m².
    pub learned_m2: f64,
    /// Visited true walkable area, m².
    pub visited_m2: f64,
}

/// [`PlanOverlap`] of `learned` (moved into the truth's frame by `transform` when given, e.g.
/// a track's rigid alignment) against `truth`, with `visited` the walks' true positions
/// `(x, y, level)`. Learned level `l` stands for true level `l + level_offset` (a learned
/// plan's level 0 is the walks' first floor).
///
/// # Errors
///
/// [`Error::Config`] when `resolution` or `reach` is not a positive number; [`Error::NotEnough`]
/// when both plans are empty, or no square of the learned plan is walkable or none of the truth's
/// is visited.
pub fn plan_overlap(
    learned: &FloorPlan,
    truth: &FloorPlan,
    visited: &[(f64, f64, i32)],
    level_offset: i32,
    transform: Option<&RigidTransform>,
    reach: f64,
    resolution: f64,
) -> Result<PlanOverlap> {
    check_range(
        "plan overlap resolution",
        resolution,
        (Excluded(0.0), Unbounded),
        "m",
    )?;
    check_range("plan overlap reach", reach, (Excluded(0.0), Unbounded), "m")?;
    // The learned plan in the truth's frame: test squares of the truth's frame against the
    // learned polygons by the inverse transform.
    let inverse = transform.map(RigidTransform::inverse);
    let in_learned = |x: f64, y: f64, level: i32| {
        let (lx, ly) = inverse.as_ref().map_or((x, y), |t| t.apply((x, y)));
        learned.is_walkable(lx, ly, Some(level - level_offset))
    };
    let mut levels = truth.levels();
    levels.extend(learned.levels().iter().map(|l| l + level_offset));
    levels.sort_unstable();
    levels.dedup();
    // Squares within `reach` of a visited position, on the surface it stood on or one
    // touching it (a door, the next tread): reach does not pass through walls.
    let nearby = touching_surfaces(truth);
    let cell = |v: f64| (v / resolution).floor() as i64;
    let k = (reach / resolution).ceil() as i64;
    let mut near: HashSet<(i32, i64, i64)> = HashSet::new();
    for &(x, y, level) in visited {
        let here = Point::new(x, y);
        let standing: Vec<usize> = truth
            .polygons
            .iter()
            .enumerate()
            .filter(|(_, p)| p.level == level && p.polygon.intersects(&here))
            .map(|(i, _)| i)
            .collect();
        let mut allowed: Vec<usize> = standing
            .iter()
            .flat_map(|&i| std::iter::once(i).chain(nearby[i].iter().copied()))
            .collect();
        allowed.sort_unstable();
        allowed.dedup();
        let (cx, cy) = (cell(x), cell(y));
        for i in -k..=k {
            for j in -k..=k {
                let (sx, sy) = (
                    (cx + i) as f64 * resolution + resolution / 2.0,
                    (cy + j) as f64 * resolution + resolution / 2.0,
                );
                if (sx - x).hypot(sy - y) <= reach
                    && allowed
                        .iter()
                        .any(|&a| truth.polygons[a].polygon.intersects(&Point::new(sx, sy)))
                {
                    near.insert((level, cx + i, cy + j));
                }
            }
        }
    }
    // Bounds: the truth's plan and the learned one (moved), with the visited squares.
    let mut corners: Vec<(f64, f64)> = Vec::new();
    for (plan, moved) in [(truth, false), (learned, true)] {
        if let Some((x0, y0, x1, y1)) = plan.bounds() {
            for p in [(x0, y0), (x0, y1), (x1, y0), (x1, y1)] {
                corners.push(match (moved, transform) {
                    (true, Some(t)) => t.apply(p),
                    _ => p,
                });
            }
        }
    }
    let (mut lo, mut hi) = (
        (f64::INFINITY, f64::INFINITY),
        (f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for (x, y) in corners {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    if !(lo.0.is_finite() && hi.0.is_finite()) {
        return Err(Error::not_enough("plan overlap of empty plans", ""));
    }
    let (mut learned_n, mut hit_n, mut visited_n, mut covered_n) = (0u64, 0u64, 0u64, 0u64);
    for &level in &levels {
        for cx in cell(lo.0)..=cell(hi.0) {
            for cy in cell(lo.1)..=cell(hi.1) {
                let (x, y) = (
                    cx as f64 * resolution + resolution / 2.0,
                    cy as f64 * resolution + resolution / 2.0,
                );
                let l = in_learned(x, y, level);
                let t = truth.is_walkable(x, y, Some(level));
                learned_n += u64::from(l);
                hit_n += u64::from(l && t);
                if t && near.contains(&(level, cx, cy)) {
                    visited_n += 1;
                    covered_n += u64::from(l);
                }
            }
        }
    }
    if learned_n == 0 || visited_n == 0 {
        return Err(Error::not_enough(
            format!("plan overlap: {learned_n} learned and {visited_n} visited squares"),
            "",
        ));
    }
    let area = resolution * resolution;
    Ok(PlanOverlap {
        precision: hit_n as f64 / learned_n as f64,
        recall: covered_n as f64 / visited_n as f64,
        learned_m2: learned_n as f64 * area,
        visited_m2: visited_n as f64 * area,
    })
}

/// For each surface of `plan`, the other surfaces of its level that touch or overlap it.
fn touching_surfaces(plan: &FloorPlan) -> Vec<Vec<usize>> {
    let boxes: Vec<Option<geo::Rect<f64>>> = plan
        .polygons
        .iter()
        .map(|p| p.polygon.bounding_rect())
        .collect();
    (0..plan.polygons.len())
        .map(|i| {
            (0..plan.polygons.len())
                .filter(|&j| {
                    let (a, b) = (&plan.polygons[i], &plan.polygons[j]);
                    j != i
                        && a.level == b.level
                        && matches!((boxes[i], boxes[j]), (Some(p), Some(q)) if p.intersects(&q))
                        && a.polygon.intersects(&b.polygon)
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::FloorPolygon;
    use geo::Rect;

    fn plan(x0: f64, y0: f64, x1: f64, y1: f64) -> FloorPlan {
        FloorPlan {
            polygons: vec![FloorPolygon {
                polygon: Rect::new((x0, y0), (x1, y1)).to_polygon(),
                level: 0,
                z: 0.0,
                name: None,
                room: None,
            }],
            barriers: vec![],
        }
    }

    #[test]
    fn precision_and_recall_by_area() {
        // A 10 m × 2 m corridor walked along its middle; the learned plan covers its west
        // 8 m and pokes 1 m out of its south side.
        let truth = plan(0.0, 0.0, 10.0, 2.0);
        let learned = plan(0.0, -1.0, 8.0, 2.0);
        let walk: Vec<(f64, f64, i32)> = (0..=100).map(|i| (0.1 * f64::from(i), 1.0, 0)).collect();
        let o = plan_overlap(&learned, &truth, &walk, 0, None, 5.0, 0.05).expect("overlap");
        assert!((o.precision - 16.0 / 24.0).abs() < 0.01, "{o:?}");
        assert!((o.recall - 0.8).abs() < 0.01, "{o:?}");
        // Moved by a transform: the same learned plan 1 m west of its place, put back.
        let shifted = plan(-1.0, -1.0, 7.0, 2.0);
        let t = RigidTransform {
            angle: 0.0,
            tx: 1.0,
            ty: 0.0,
        };
        let m = plan_overlap(&shifted, &truth, &walk, 0, Some(&t), 5.0, 0.05).expect("overlap");
        assert!((m.precision - o.precision).abs() < 0.01 && (m.recall - o.recall).abs() < 0.01);
        assert!(plan_overlap(&learned, &truth, &[], 0, None, 5.0, 0.05).is_err());
    }

    #[test]
    fn floors_are_compared_level_by_level() {
        // Two floors of the same corridor in plan; the learned plan has the ground floor
        // right and puts the upper floor 5 m east. Learned level 0 is true level 1 here.
        let mut truth = plan(0.0, 0.0, 10.0, 2.0);
        let mut upper = truth.polygons[0].clone();
        upper.level = 2;
        truth.polygons.push(upper);
        truth.polygons[0].level = 1;
        let mut learned = plan(0.0, 0.0, 10.0, 2.0);
        let mut up = plan(5.0, 0.0, 15.0, 2.0).polygons[0].clone();
        up.level = 1;
        learned.polygons.push(up);
        let walk: Vec<(f64, f64, i32)> = (0..=100)
            .flat_map(|i| [(0.1 * f64::from(i), 1.0, 1), (0.1 * f64::from(i), 1.0, 2)])
            .collect();
        let o = plan_overlap(&learned, &truth, &walk, 1, None, 5.0, 0.05).expect("overlap");
        // Ground floor: all right; upper: half of it right. Levels ignored would say 1.0.
        assert!((o.precision - 0.75).abs() < 0.01, "{o:?}");
        assert!((o.recall - 0.75).abs() < 0.01, "{o:?}");
    }

    #[test]
    fn reach_does_not_pass_through_walls() {
        // A corridor 0 ≤ y ≤ 2 and, beyond a 0.2 m wall, a room 2.2 ≤ y ≤ 6 nobody entered;
        // the walk runs along y = 1.8. The learned plan is the corridor alone.
        let mut truth = plan(0.0, 0.0, 10.0, 2.0);
        truth
            .polygons
            .push(plan(0.0, 2.2, 10.0, 6.0).polygons[0].clone());
        let learned = plan(0.0, 0.0, 10.0, 2.0);
        let walk: Vec<(f64, f64, i32)> = (0..=100).map(|i| (0.1 * f64::from(i), 1.8, 0)).collect();
        let o = plan_overlap(&learned, &truth, &walk, 0, None, 1.0, 0.05).expect("overlap");
        assert!(o.recall > 0.99, "{o:?}");
        // The corridor within 1 m of the walk (0.8 ≤ y ≤ 2), none of the room.
        assert!((o.visited_m2 - 10.0 * 1.2).abs() < 0.3, "{o:?}");
        // A door joining them: the walker in the doorway sees into the room.
        let mut with_door = truth.clone();
        with_door
            .polygons
            .push(plan(4.5, 2.0, 5.5, 2.2).polygons[0].clone());
        let through: Vec<(f64, f64, i32)> =
            (0..=40).map(|i| (5.0, 0.1 * f64::from(i), 0)).collect();
        let o = plan_overlap(&learned, &with_door, &through, 0, None, 1.0, 0.05).expect("overlap");
        assert!(o.recall < 0.9, "the room beyond the door is visited: {o:?}");
    }
}
