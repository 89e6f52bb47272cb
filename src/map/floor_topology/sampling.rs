//! Points drawn uniformly over the walkable area: every surface triangulated (ear clipping),
//! a triangle drawn by its area, a point drawn uniformly inside it.

use geo::{Area, TriangulateEarcut};
use rand::RngExt;

/// Guide buckets per triangle (see [`Triangles::find`]).
const BUCKETS_PER_TRIANGLE: usize = 4;

/// The triangles of all surfaces with their cumulative areas.
#[derive(Debug, Clone, Default)]
pub(super) struct Triangles {
    triangles: Vec<(u32, [[f64; 2]; 3])>,
    cumulative: Vec<f64>,
    /// For each of as many equal stretches of the total area, the first triangle whose
    /// cumulative area exceeds the stretch's start (a guide table: the draw's triangle is
    /// found from there in a step or two instead of by bisection).
    guide: Vec<u32>,
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
        let buckets = BUCKETS_PER_TRIANGLE * triangles.triangles.len();
        triangles.guide = (0..buckets)
            .map(|b| {
                let start = Self::bucket_start(b, buckets, total);
                triangles.cumulative.partition_point(|&c| c <= start) as u32
            })
            .collect();
        triangles
    }

    /// Where guide bucket `b` of `buckets` over `total` starts.
    #[inline]
    fn bucket_start(b: usize, buckets: usize, total: f64) -> f64 {
        b as f64 * total / buckets as f64
    }

    /// The first triangle whose cumulative area exceeds `u` (its index, or the count when
    /// none does): the bisection's answer, found from the guide bucket of `u` by stepping
    /// forward. Exact: every triangle before the bucket's entry ends at or before the
    /// bucket's start, hence at or before `u`.
    #[inline]
    fn find(&self, u: f64, total: f64) -> usize {
        let buckets = self.guide.len();
        let b = (u / total * buckets as f64) as usize;
        if b < buckets && u >= Self::bucket_start(b, buckets, total) {
            let mut i = self.guide[b] as usize;
            while i < self.cumulative.len() && self.cumulative[i] <= u {
                i += 1;
            }
            return i;
        }
        self.cumulative.partition_point(|&c| c <= u)
    }

    /// A point drawn uniformly over the whole walkable area (holes excluded) and its surface.
    pub(super) fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> (u32, [f64; 2]) {
        let total = self.cumulative.last().copied().unwrap_or(0.0);
        let u = rng.random::<f64>() * total;
        let i = self
            .find(u, total)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_guide_finds_what_bisection_finds() {
        // Triangles of very different areas (stair treads beside a hall).
        let polygons: Vec<geo::Polygon<f64>> = [0.05, 40.0, 0.3, 0.3, 7.0, 0.01, 1.0]
            .iter()
            .enumerate()
            .map(|(k, &a)| {
                let x = 10.0 * k as f64;
                geo::Rect::new((x, 0.0), (x + a, 1.0)).to_polygon()
            })
            .collect();
        let t = Triangles::new(&polygons);
        let total = *t.cumulative.last().expect("area");
        let mut edges: Vec<f64> = t.cumulative.clone();
        edges.extend(t.cumulative.iter().map(|c| c.next_down()));
        edges.extend((0..t.guide.len()).map(|b| Triangles::bucket_start(b, t.guide.len(), total)));
        let sweep = (0..20_000).map(|i| (f64::from(i) * 0.618_033_988_749_895).fract() * total);
        for u in edges
            .into_iter()
            .chain(sweep)
            .filter(|&u| (0.0..total).contains(&u))
        {
            let bisection = t.cumulative.partition_point(|&c| c <= u);
            assert_eq!(t.find(u, total), bisection, "{u:e}");
        }
    }
}
