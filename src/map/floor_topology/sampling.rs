//! Points drawn uniformly over the walkable area: every surface triangulated (ear clipping),
//! a triangle drawn by its area, a point drawn uniformly inside it.

use geo::{Area, TriangulateEarcut};
use rand::RngExt;

/// The triangles of all surfaces with their cumulative areas.
#[derive(Debug, Clone, Default)]
pub(super) struct Triangles {
    triangles: Vec<(u32, [[f64; 2]; 3])>,
    cumulative: Vec<f64>,
}

impl Triangles {
    /// Triangulates every surface (ear clipping) for uniform sampling.
    pub(super) fn new(polygons: &[geo::Polygon<f64>]) -> Self {
        let mut triangles = Self::default();
        let mut total = 0.0;
        for (s, poly) in polygons.iter().enumerate() {
            for t in poly.earcut_triangles_iter() {
                let area = t.unsigned_area();
                if area <= 0.0 {
                    continue;
                }
                total += area;
                triangles
                    .triangles
                    .push((s as u32, [t.v1(), t.v2(), t.v3()].map(|c| [c.x, c.y])));
                triangles.cumulative.push(total);
            }
        }
        triangles
    }

    /// A point drawn uniformly over the whole walkable area (holes excluded) and its surface.
    pub(super) fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> (u32, [f64; 2]) {
        let total = self.cumulative.last().copied().unwrap_or(0.0);
        let u = rng.random::<f64>() * total;
        let i = self
            .cumulative
            .partition_point(|&c| c <= u)
            .min(self.triangles.len().saturating_sub(1));
        let Some(&(surface, [a, b, c])) = self.triangles.get(i) else {
            return (0, [0.0, 0.0]);
        };
        let (mut r1, mut r2) = (rng.random::<f64>(), rng.random::<f64>());
        if r1 + r2 > 1.0 {
            (r1, r2) = (1.0 - r1, 1.0 - r2);
        }
        let p = [
            a[0] + r1 * (b[0] - a[0]) + r2 * (c[0] - a[0]),
            a[1] + r1 * (b[1] - a[1]) + r2 * (c[1] - a[1]),
        ];
        (surface, p)
    }
}
