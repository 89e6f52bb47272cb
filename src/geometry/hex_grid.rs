//! The regular hexagon grid of FootSLAM's transition map (Robertson et al. 2009, Fig. 7).
//!
//! Pointy-top hexagons of circumradius `r` in the local frame, addressed by axial
//! coordinates `(q, r)` as `hexx::Hex`. Edge `k` (0..6) is the side whose outward normal
//! points at `60°·k` counter-clockwise from east: 0 = E, 1 = NE, 2 = NW, 3 = W, 4 = SW,
//! 5 = SE. Crossing edge `k` of a hexagon enters its neighbour through that neighbour's edge
//! `(k + 3) % 6`. This is the only module that uses `hexx`.

pub use hexx::Hex;
use std::f64::consts::{FRAC_PI_3, PI};

const SQRT3: f64 = 1.732_050_807_568_877_2;

/// Axial offset of the neighbour across edge `k` (see the module docs).
const NEIGHBOUR: [(i32, i32); 6] = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)];

/// One hexagon edge crossed by a straight segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Crossing {
    /// The hexagon left.
    pub from: Hex,
    /// The edge of `from` crossed, 0..6.
    pub edge: u8,
    /// The hexagon entered.
    pub to: Hex,
}

/// A hexagon grid of a given circumradius, with world ↔ hexagon conversions.
///
/// Points to hexagons, neighbours across edges, and the edges a straight step crosses:
///
/// ```
/// use footslam::geometry::{Hex, HexGrid};
///
/// let grid = HexGrid::new(0.5); // hexagons of 0.5 m circumradius
/// let h = grid.hex_at(3.2, 1.1);
/// let (cx, cy) = grid.center(h);
/// assert_eq!(grid.hex_at(cx, cy), h);
/// assert!((cx - 3.2).hypot(cy - 1.1) <= 0.5);
/// // Edge 0 faces east: the neighbour across it lies one hexagon width (√3·r) east.
/// let (ex, ey) = grid.center(HexGrid::neighbour(Hex::ZERO, 0));
/// assert!((ex - 3f64.sqrt() * 0.5).abs() < 1e-12 && ey.abs() < 1e-12);
/// // A 5 m walk east crosses an edge every 0.87 m, each the east edge of the hexagon left.
/// let mut crossings = Vec::new();
/// grid.for_each_crossing((0.0, 0.0), (5.0, 0.0), |c| crossings.push(c));
/// assert_eq!(crossings.len(), 6);
/// assert!(crossings.iter().all(|c| c.edge == 0 && c.to == HexGrid::neighbour(c.from, 0)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HexGrid {
    radius: f64,
    apothem: f64,
    normals: [(f64, f64); 6],
}

impl HexGrid {
    /// A grid of hexagons with circumradius `radius` metres (must be finite and positive).
    #[must_use]
    pub fn new(radius: f64) -> Self {
        debug_assert!(radius.is_finite() && radius > 0.0);
        let normals = std::array::from_fn(|k| {
            let a = FRAC_PI_3 * k as f64;
            (a.cos(), a.sin())
        });
        Self {
            radius,
            apothem: radius * SQRT3 / 2.0,
            normals,
        }
    }

    /// Circumradius, metres.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Area of one hexagon, m².
    #[must_use]
    pub fn cell_area(&self) -> f64 {
        1.5 * SQRT3 * self.radius * self.radius
    }

    /// The hexagon containing the point `(x, y)`.
    #[must_use]
    pub fn hex_at(&self, x: f64, y: f64) -> Hex {
        let q = (SQRT3 / 3.0 * x - y / 3.0) / self.radius;
        let r = (2.0 / 3.0 * y) / self.radius;
        cube_round(q, r)
    }

    /// Centre of hexagon `h` in the local frame.
    #[must_use]
    pub fn center(&self, h: Hex) -> (f64, f64) {
        let (q, r) = (f64::from(h.x), f64::from(h.y));
        (self.radius * SQRT3 * (q + r / 2.0), self.radius * 1.5 * r)
    }

    /// The six corners of `h`, counter-clockwise from the one at −30° (south of edge 0).
    #[must_use]
    pub fn corners(&self, h: Hex) -> [(f64, f64); 6] {
        let (cx, cy) = self.center(h);
        std::array::from_fn(|i| {
            let a = FRAC_PI_3 * i as f64 - PI / 6.0;
            (cx + self.radius * a.cos(), cy + self.radius * a.sin())
        })
    }

    /// The neighbour of `h` across edge `k`.
    #[must_use]
    pub fn neighbour(h: Hex, edge: u8) -> Hex {
        let (dq, dr) = NEIGHBOUR[usize::from(edge % 6)];
        Hex::new(h.x + dq, h.y + dr)
    }

    /// Calls `visit` for every edge crossed, in order, by the straight segment from
    /// `(ax, ay)` to `(bx, by)`. A segment that stays in one hexagon crosses nothing.
    pub fn for_each_crossing(
        &self,
        (ax, ay): (f64, f64),
        (bx, by): (f64, f64),
        mut visit: impl FnMut(Crossing),
    ) {
        let target = self.hex_at(bx, by);
        let mut h = self.hex_at(ax, ay);
        let (dx, dy) = (bx - ax, by - ay);
        // A straight segment crosses at most one edge per hexagon; the guard only protects
        // against rounding at vertices.
        let mut budget = 2 * h.unsigned_distance_to(target) + 4;
        while h != target && budget > 0 {
            budget -= 1;
            let (cx, cy) = self.center(h);
            let (px, py) = (ax - cx, ay - cy);
            let mut best = (f64::INFINITY, 0u8);
            for (k, &(nx, ny)) in self.normals.iter().enumerate() {
                let along = dx * nx + dy * ny;
                if along > 0.0 {
                    let t = (self.apothem - (px * nx + py * ny)) / along;
                    if t < best.0 {
                        best = (t, k as u8);
                    }
                }
            }
            if !best.0.is_finite() {
                break;
            }
            let to = Self::neighbour(h, best.1);
            visit(Crossing {
                from: h,
                edge: best.1,
                to,
            });
            h = to;
        }
    }

    /// FootSLAM's direction correction (Robertson et al. 2009, sec. 3): the exponent that
    /// makes a product of per-edge factors independent of the heading `phi` of a straight
    /// track. A line at heading `phi` crosses `2/(3√3 r) · Σᵢ|cos(phi − 60°·i)|` edges per
    /// metre; the exponent is the heading-average of that sum, `6/π`, over its value at `phi`.
    #[must_use]
    pub fn direction_exponent(phi: f64) -> f64 {
        Self::direction_exponent_of(phi.cos(), phi.sin())
    }

    /// [`Self::direction_exponent`] for a track along `(dx, dy)` (any non-zero length),
    /// without trigonometric calls: `|cos(phi − 60°·i)| = |dx·cos 60°i + dy·sin 60°i| / |d|`.
    #[must_use]
    pub fn direction_exponent_of(dx: f64, dy: f64) -> f64 {
        const C: [(f64, f64); 3] = [(1.0, 0.0), (0.5, SQRT3 / 2.0), (-0.5, SQRT3 / 2.0)];
        let norm = dx.hypot(dy);
        if norm == 0.0 {
            return 1.0;
        }
        let s: f64 = C.iter().map(|&(c, s)| (dx * c + dy * s).abs()).sum();
        (6.0 / PI) * norm / s
    }
}

/// Rounds fractional axial coordinates to the nearest hexagon (cube rounding).
fn cube_round(q: f64, r: f64) -> Hex {
    let s = -q - r;
    let (mut rq, mut rr, rs) = (q.round(), r.round(), s.round());
    let (dq, dr, ds) = ((rq - q).abs(), (rr - r).abs(), (rs - s).abs());
    if dq > dr && dq > ds {
        rq = -rr - rs;
    } else if dr > ds {
        rr = -rq - rs;
    }
    Hex::new(rq as i32, rr as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centres_round_trip_and_neighbours_face_their_edges() {
        let g = HexGrid::new(0.5);
        for q in -3..3 {
            for r in -3..3 {
                let h = Hex::new(q, r);
                let (x, y) = g.center(h);
                assert_eq!(g.hex_at(x, y), h);
                for k in 0..6u8 {
                    let n = HexGrid::neighbour(h, k);
                    let (nx, ny) = g.center(n);
                    let angle = (ny - y).atan2(nx - x);
                    let expect = FRAC_PI_3 * f64::from(k);
                    let diff = crate::geometry::wrap_angle(angle - expect);
                    assert!(diff.abs() < 1e-9, "edge {k}: {angle} vs {expect}");
                    assert!(
                        (((nx - x).powi(2) + (ny - y).powi(2)).sqrt() - 0.5 * SQRT3).abs() < 1e-9
                    );
                }
            }
        }
    }

    #[test]
    fn crossings_of_a_horizontal_segment() {
        let g = HexGrid::new(0.5);
        // From the centre of (0,0) east by 2 hexagon widths: two crossings of edge 0.
        let w = 0.5 * SQRT3;
        let mut seen = Vec::new();
        g.for_each_crossing((0.0, 0.0), (2.0 * w, 0.0), |c| seen.push(c));
        assert_eq!(seen.len(), 2);
        assert!(seen.iter().all(|c| c.edge == 0));
        assert_eq!(seen[1].to, Hex::new(2, 0));
        // Staying inside crosses nothing.
        let mut n = 0;
        g.for_each_crossing((0.0, 0.0), (0.1, 0.1), |_| n += 1);
        assert_eq!(n, 0);
    }

    #[test]
    fn crossings_chain_from_start_to_end_hexagon() {
        let g = HexGrid::new(0.5);
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 10.0 - 5.0
        };
        for _ in 0..1000 {
            let a = (next(), next());
            let b = (next(), next());
            let mut h = g.hex_at(a.0, a.1);
            let mut count = 0u32;
            g.for_each_crossing(a, b, |c| {
                assert_eq!(c.from, h);
                assert_eq!(c.to, HexGrid::neighbour(c.from, c.edge));
                h = c.to;
                count += 1;
            });
            assert_eq!(h, g.hex_at(b.0, b.1));
            assert!(count >= g.hex_at(a.0, a.1).unsigned_distance_to(h));
        }
    }

    #[test]
    fn direction_exponent_averages_to_one() {
        let n = 3600;
        let mean_density: f64 = (0..n)
            .map(|i| {
                let phi = std::f64::consts::TAU * f64::from(i) / f64::from(n);
                1.0 / HexGrid::direction_exponent(phi)
            })
            .sum::<f64>()
            / f64::from(n);
        assert!((mean_density - 1.0).abs() < 1e-3, "{mean_density}");
        // Along an edge normal a track crosses the most edges per metre: exponent < 1.
        assert!(HexGrid::direction_exponent(0.0) < 1.0);
        assert!(HexGrid::direction_exponent(PI / 6.0) > 1.0);
        for phi in [0.0, 0.3, 1.0, 2.5, -2.0] {
            let (a, b) = (
                HexGrid::direction_exponent(phi),
                HexGrid::direction_exponent_of(2.0 * phi.cos(), 2.0 * phi.sin()),
            );
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn measured_crossing_density_matches_the_formula() {
        let g = HexGrid::new(0.5);
        // Averaged over parallel offsets, as a long random track samples them.
        for &phi in &[0.0, 0.2, PI / 6.0, 1.0] {
            let len = 200.0;
            let offsets = 64;
            let mut n = 0u32;
            for o in 0..offsets {
                let d = 3.0 * f64::from(o) / f64::from(offsets);
                let (ox, oy) = (-d * phi.sin(), d * phi.cos());
                g.for_each_crossing(
                    (ox, oy),
                    (ox + len * phi.cos(), oy + len * phi.sin()),
                    |_| n += 1,
                );
            }
            let len = len * f64::from(offsets);
            let s: f64 = (0..3)
                .map(|i| (phi - FRAC_PI_3 * f64::from(i)).cos().abs())
                .sum();
            let expect = len * 2.0 / (3.0 * SQRT3 * 0.5) * s;
            assert!(
                (f64::from(n) - expect).abs() / expect < 0.03,
                "phi {phi}: {n} vs {expect}"
            );
        }
    }
}
