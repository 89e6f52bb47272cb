//! A walker's route: a polyline through waypoints with rounded corners, walked by arc length.
//!
//! Each interior corner is replaced by a quadratic Bézier curve from a point `r` before the
//! corner to a point `r` after it. The curve lies in the triangle of those two points and the
//! corner, so a route whose waypoints and such triangles lie on the floor stays on the floor.

use geo::Coord;

/// Curve points per rounded corner.
const CURVE_POINTS: usize = 12;
/// A corner's rounding may use at most this fraction of each adjacent segment.
const MAX_SEGMENT_FRACTION: f64 = 0.45;
/// Points closer than this are merged, metres.
const MERGE_DISTANCE: f64 = 1e-9;

/// A dense polyline with its cumulative arc lengths.
#[derive(Debug, Clone, PartialEq)]
pub struct Route {
    points: Vec<Coord<f64>>,
    cumulative: Vec<f64>,
}

fn norm(c: Coord<f64>) -> f64 {
    c.x.hypot(c.y)
}

impl Route {
    /// The route through `waypoints` with each interior corner rounded with radius
    /// `min(radius, 0.45 × either adjacent segment's length)`.
    #[must_use]
    pub fn rounded(waypoints: &[Coord<f64>], radius: f64) -> Self {
        let mut corners: Vec<Coord<f64>> = Vec::with_capacity(waypoints.len());
        for &w in waypoints {
            if corners.last().is_none_or(|&l| norm(w - l) > MERGE_DISTANCE) {
                corners.push(w);
            }
        }
        let mut points = Vec::with_capacity(corners.len() * CURVE_POINTS);
        for (i, &v) in corners.iter().enumerate() {
            let (Some(&p), Some(&n)) = (
                i.checked_sub(1).and_then(|j| corners.get(j)),
                corners.get(i + 1),
            ) else {
                push_distinct(&mut points, v);
                continue;
            };
            let (d1, d2) = (norm(v - p), norm(n - v));
            let r = radius
                .max(0.0)
                .min(MAX_SEGMENT_FRACTION * d1)
                .min(MAX_SEGMENT_FRACTION * d2);
            if r <= MERGE_DISTANCE {
                push_distinct(&mut points, v);
                continue;
            }
            let a = v + (p - v) * (r / d1);
            let b = v + (n - v) * (r / d2);
            push_distinct(&mut points, a);
            for j in 1..=CURVE_POINTS {
                let u = j as f64 / CURVE_POINTS as f64;
                let q = a * ((1.0 - u) * (1.0 - u)) + v * (2.0 * u * (1.0 - u)) + b * (u * u);
                push_distinct(&mut points, q);
            }
        }
        let mut cumulative = Vec::with_capacity(points.len());
        let mut total = 0.0;
        for (i, &q) in points.iter().enumerate() {
            if let Some(&previous) = i.checked_sub(1).and_then(|j| points.get(j)) {
                total += norm(q - previous);
            }
            cumulative.push(total);
        }
        Self { points, cumulative }
    }

    /// Total length, metres.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// The polyline's points.
    #[must_use]
    pub fn points(&self) -> &[Coord<f64>] {
        &self.points
    }

    /// The point at arc length `s` (clamped to the route) and the unit direction of travel
    /// there (east for a route of fewer than two points).
    #[must_use]
    pub fn at(&self, s: f64) -> (Coord<f64>, Coord<f64>) {
        let east = Coord { x: 1.0, y: 0.0 };
        let Some(&first) = self.points.first() else {
            return (Coord { x: 0.0, y: 0.0 }, east);
        };
        if self.points.len() < 2 {
            return (first, east);
        }
        let s = s.clamp(0.0, self.length());
        // The segment [i - 1, i] holding s.
        let i = self
            .cumulative
            .partition_point(|&c| c < s)
            .clamp(1, self.points.len() - 1);
        let (p, q) = (self.points[i - 1], self.points[i]);
        let len = self.cumulative[i] - self.cumulative[i - 1];
        let u = if len > 0.0 {
            ((s - self.cumulative[i - 1]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let direction = if len > 0.0 { (q - p) / len } else { east };
        (p + (q - p) * u, direction)
    }
}

fn push_distinct(points: &mut Vec<Coord<f64>>, q: Coord<f64>) {
    if points.last().is_none_or(|&l| norm(q - l) > MERGE_DISTANCE) {
        points.push(q);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(x: f64, y: f64) -> Coord<f64> {
        Coord { x, y }
    }

    #[test]
    fn straight_routes_are_walked_exactly() {
        let r = Route::rounded(&[c(0.0, 0.0), c(2.0, 0.0), c(2.0, 0.0), c(4.0, 0.0)], 0.5);
        assert!((r.length() - 4.0).abs() < 1e-12);
        let (p, d) = r.at(1.5);
        assert!((p.x - 1.5).abs() < 1e-12 && p.y.abs() < 1e-12);
        assert!((d.x - 1.0).abs() < 1e-12);
        assert_eq!(r.at(10.0).0, c(4.0, 0.0));
    }

    #[test]
    fn corners_are_rounded_within_the_corner_triangle() {
        let r = Route::rounded(&[c(0.0, 0.0), c(4.0, 0.0), c(4.0, 4.0)], 0.5);
        // The rounded corner is shorter than the sharp one but no shorter than the chord.
        assert!(r.length() < 8.0 && r.length() > 7.0 + 0.5f64.hypot(0.5));
        for q in r.points() {
            let in_first = q.y.abs() < 1e-12 && q.x <= 3.5 + 1e-12;
            let in_last = (q.x - 4.0).abs() < 1e-12 && q.y >= 0.5 - 1e-12;
            let in_triangle =
                q.x >= 3.5 - 1e-12 && q.y <= 0.5 + 1e-12 && q.y >= -1e-12 && q.x <= 4.0 + 1e-12;
            assert!(in_first || in_last || in_triangle, "{q:?}");
        }
        // A short leg limits the radius to 45 % of it.
        let r = Route::rounded(&[c(0.0, 0.0), c(1.0, 0.0), c(1.0, 0.2)], 0.5);
        assert!(r.points().iter().all(|q| q.x <= 1.0 + 1e-12 && q.x >= 0.0));
        assert!(
            r.points()
                .iter()
                .any(|q| (q.x - 0.91).abs() < 1e-12 && q.y.abs() < 1e-12)
        );
    }

    #[test]
    fn u_turns_stay_on_the_segment() {
        let r = Route::rounded(&[c(0.0, 0.0), c(2.0, 0.0), c(0.0, 0.0)], 0.5);
        assert!(r.points().iter().all(|q| q.y.abs() < 1e-12 && q.x <= 2.0));
    }
}
