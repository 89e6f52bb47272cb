//! Clusters of particles by mean shift (Woodman & Harle 2008, sec. "Environmental symmetry":
//! a multimodal belief is a set of distinct particle clusters, each a possible location).
//!
//! Mean shift with a flat kernel: a mode moves to the weighted mean of the particles within
//! `radius` horizontally, less than `max_dz` vertically and heading within `max_dheading` of
//! the mode's (circular) mean heading, until it stops moving. Heading is part of the kernel
//! because a hypothesis is a pose, not a place: in a building with rotational symmetry two
//! groups walking towards each other along one corridor pass within the 7 m radius while
//! being distinct hypotheses (a pedestrian's particles all turn at the same step, so one
//! hypothesis keeps a tight heading spread). Seeds are the weighted means of occupied bins of
//! half the radius and of `max_dheading` in heading (bin seeding), modes closer than the
//! kernel are merged, keeping the densest, and every particle joins its nearest mode within
//! reach. Knows nothing of maps: particles are points with a height, a level, a heading and a
//! weight.

use crate::error::Result;
use crate::geometry::angle::wrap_angle;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Iterations of one mode's mean shift at most.
const MAX_ITERATIONS: usize = 100;
/// A mode that moves less than this has converged, metres.
const CONVERGED: f64 = 1e-3;

/// Clustering's parameters; every default in one place.
///
/// | field          | default | meaning                                                     |
/// |----------------|---------|-------------------------------------------------------------|
/// | `radius`       | 7 m     | flat kernel's horizontal radius (the paper's value)         |
/// | `max_dz`       | 1 m     | particles less than this apart vertically share a kernel    |
/// | `max_dheading` | 45°     | particles less than this apart in heading share a kernel (π = ignore heading) |
/// | `min_weight`   | 0.01    | clusters holding less of the weight are not counted         |
/// | `max_spread`   | 2 m     | a lone cluster wider than this (RMS radius) is not yet a fix |
/// | `max_particles`| 10,000  | beliefs with more particles are not clustered               |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClusterConfig {
    /// Horizontal kernel radius, metres.
    pub radius: f64,
    /// Vertical kernel half-height, metres.
    pub max_dz: f64,
    /// Heading kernel half-width, radians (π: headings never separate clusters).
    pub max_dheading: f64,
    /// Clusters below this share of the total weight are stragglers, not counted.
    pub min_weight: f64,
    /// A single cluster localises the walker only when its particles' RMS horizontal
    /// distance from its mean is at most this, metres: a blob stretched along a corridor
    /// (e.g. a WiFi prior region one kernel wide) is one cluster but not yet a position.
    pub max_spread: f64,
    /// Clustering runs only when there are at most this many particles.
    pub max_particles: usize,
}

impl Default for ClusterConfig {
    fn default() -> Self {
        Self {
            radius: 7.0,
            max_dz: 1.0,
            max_dheading: std::f64::consts::FRAC_PI_4,
            min_weight: 0.01,
            max_spread: 2.0,
            max_particles: 10_000,
        }
    }
}

impl ClusterConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `radius` or `max_spread` is outside
    /// [0.1, 1000] m, `max_dz` outside [0.01, 100] m, `max_dheading` outside [0.05, π] radians,
    /// `min_weight` outside [0, 0.5), or `max_particles` above 10 000 000.
    pub fn validate(&self) -> Result<()> {
        if !(self.radius.is_finite() && (0.1..=1000.0).contains(&self.radius)) {
            return Err(crate::error::Error::config(
                "cluster.radius",
                self.radius.to_string(),
                "must be in [0.1, 1000] metres",
            ));
        }
        if !(self.max_dz.is_finite() && (0.01..=100.0).contains(&self.max_dz)) {
            return Err(crate::error::Error::config(
                "cluster.max_dz",
                self.max_dz.to_string(),
                "must be in [0.01, 100] metres",
            ));
        }
        if !(self.max_dheading.is_finite()
            && (0.05..=std::f64::consts::PI).contains(&self.max_dheading))
        {
            return Err(crate::error::Error::config(
                "cluster.max_dheading",
                self.max_dheading.to_string(),
                "must be in [0.05, π] radians",
            ));
        }
        if !(self.min_weight.is_finite() && (0.0..0.5).contains(&self.min_weight)) {
            return Err(crate::error::Error::config(
                "cluster.min_weight",
                self.min_weight.to_string(),
                "must be in [0, 0.5)",
            ));
        }
        if !(self.max_spread.is_finite() && (0.1..=1000.0).contains(&self.max_spread)) {
            return Err(crate::error::Error::config(
                "cluster.max_spread",
                self.max_spread.to_string(),
                "must be in [0.1, 1000] metres",
            ));
        }
        if self.max_particles > 10_000_000 {
            return Err(crate::error::Error::config(
                "cluster.max_particles",
                self.max_particles.to_string(),
                "must be at most 10000000",
            ));
        }
        Ok(())
    }
}

/// A weighted point to cluster.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterPoint {
    /// East, metres.
    pub x: f32,
    /// North, metres.
    pub y: f32,
    /// Height, metres.
    pub z: f32,
    /// Floor level.
    pub level: i32,
    /// Heading, radians.
    pub heading: f32,
    /// Weight (non-negative).
    pub weight: f32,
}

/// One cluster: the weighted mean of its particles.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cluster {
    /// Weighted mean east, metres.
    pub x: f64,
    /// Weighted mean north, metres.
    pub y: f64,
    /// Weighted mean height, metres.
    pub z: f64,
    /// The level holding most of the cluster's weight.
    pub level: i32,
    /// Weighted circular mean heading, radians in (−π, π].
    pub heading: f64,
    /// Weighted RMS horizontal distance of its particles from the mean, metres.
    pub spread: f64,
    /// Share of the total weight, in [0, 1].
    pub weight: f64,
    /// Number of particles.
    pub particles: usize,
}

/// Clusters of `points`, heaviest first, with every cluster's share of the weight; clusters
/// lighter than `config.min_weight` are dropped from the list (their particles still count in
/// the total). Empty when the points carry no weight. A filter that clusters every step keeps
/// a [`MeanShift`] instead, whose buffers live from call to call.
#[must_use]
pub fn mean_shift(points: &[ClusterPoint], config: &ClusterConfig) -> Vec<Cluster> {
    MeanShift::default().cluster(points, config)
}

/// Mean shift's working memory (each point's heading as a unit vector, the points sorted by
/// cell, the seeds), kept between calls so that clustering every step allocates nothing of
/// the belief's size.
#[derive(Debug, Clone, Default)]
pub struct MeanShift {
    unit: Vec<Unit>,
    grid: Grid,
    seed_keys: Vec<(SeedBin, u32)>,
    seed_packed: Vec<u64>,
    shifts: Shifts,
}

impl MeanShift {
    /// [`mean_shift`] of `points`, reusing this workspace's buffers.
    pub fn cluster(&mut self, points: &[ClusterPoint], config: &ClusterConfig) -> Vec<Cluster> {
        let total: f64 = points.iter().map(|p| f64::from(p.weight)).sum();
        if !(total > 0.0 && total.is_finite()) {
            return Vec::new();
        }
        let r = config.radius;
        // Each point's heading as a unit vector, once: mean shift visits a point many times.
        self.unit.clear();
        self.unit.extend(points.iter().map(Unit::of));
        let unit = &self.unit;
        self.grid.build(points, unit, r);
        let seeds = seeds(
            points,
            unit,
            r / 2.0,
            config.max_dheading,
            &mut self.seed_keys,
            &mut self.seed_packed,
        );
        let modes = merge_modes(self.shifts.shift_all(seeds, &self.grid, config), config);
        let mut sums = vec![Sums::default(); modes.len()];
        let weighted = points.iter().zip(unit).filter(|(p, _)| p.weight > 0.0);
        if let [_] = modes[..] {
            // One mode is every particle's nearest (a localised belief's usual case).
            weighted.for_each(|(p, u)| sums[0].add(p, u));
        } else {
            let index = ModeIndex::new(&modes, r);
            for (p, u) in weighted {
                if let Some(i) = index.nearest(p, &modes, config) {
                    sums[i].add(p, u);
                }
            }
        }
        let mut clusters: Vec<Cluster> = sums
            .into_iter()
            .filter(|s| s.m.w > 0.0)
            .map(|s| s.cluster(total))
            .filter(|c| c.weight >= config.min_weight)
            .collect();
        clusters.sort_by(|a, b| b.weight.total_cmp(&a.weight));
        clusters
    }
}

/// A mode's position and the weight inside its kernel.
#[derive(Debug, Clone, Copy)]
struct Mode {
    x: f64,
    y: f64,
    z: f64,
    heading: f64,
    density: f64,
}

/// Absolute difference of two headings, radians in [0, π].
#[inline]
fn heading_gap(a: f64, b: f64) -> f64 {
    wrap_angle(a - b).abs()
}

/// Weighted sums of position and heading: a mode's kernel.
#[derive(Debug, Clone, Copy, Default)]
struct Moments {
    w: f64,
    x: f64,
    y: f64,
    z: f64,
    cos: f64,
    sin: f64,
}

/// A point's heading as `(cos, sin)`.
#[derive(Debug, Clone, Copy)]
struct Unit(f64, f64);

impl Unit {
    fn of(p: &ClusterPoint) -> Self {
        let h = f64::from(p.heading);
        Self(h.cos(), h.sin())
    }
}

impl Moments {
    fn add(&mut self, p: &ClusterPoint, u: &Unit) {
        let w = f64::from(p.weight);
        self.w += w;
        self.x += w * f64::from(p.x);
        self.y += w * f64::from(p.y);
        self.z += w * f64::from(p.z);
        self.cos += w * u.0;
        self.sin += w * u.1;
    }

    /// [`Self::add`] of a point as the grid holds it (the same sums, bit for bit).
    #[inline]
    fn add_member(&mut self, p: &Member) {
        self.w += p.w;
        self.x += p.w * p.x;
        self.y += p.w * p.y;
        self.z += p.w * p.z;
        self.cos += p.w * p.cos;
        self.sin += p.w * p.sin;
    }

    /// The weighted mean, its circular mean heading and the weight as density.
    fn mode(&self) -> Mode {
        Mode {
            x: self.x / self.w,
            y: self.y / self.w,
            z: self.z / self.w,
            heading: self.sin.atan2(self.cos),
            density: self.w,
        }
    }
}

/// Weighted sums of a cluster's particles.
#[derive(Debug, Clone, Default)]
struct Sums {
    m: Moments,
    /// Weighted sum of `x² + y²`.
    r2: f64,
    n: usize,
    levels: Vec<(i32, f64)>,
}

impl Sums {
    fn add(&mut self, p: &ClusterPoint, u: &Unit) {
        let w = f64::from(p.weight);
        self.m.add(p, u);
        self.r2 += w * (f64::from(p.x).powi(2) + f64::from(p.y).powi(2));
        self.n += 1;
        match self.levels.iter_mut().find(|(l, _)| *l == p.level) {
            Some((_, lw)) => *lw += w,
            None => self.levels.push((p.level, w)),
        }
    }

    fn cluster(&self, total: f64) -> Cluster {
        let level = self
            .levels
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
            .map_or(0, |l| l.0);
        let Mode {
            x,
            y,
            z,
            heading,
            density: w,
        } = self.m.mode();
        Cluster {
            x,
            y,
            z,
            level,
            heading,
            spread: (self.r2 / w - x.powi(2) - y.powi(2)).max(0.0).sqrt(),
            weight: w / total,
            particles: self.n,
        }
    }
}

/// A weighted point as the kernel reads it: in `f64`, its heading's unit vector beside it.
#[derive(Debug, Clone, Copy)]
struct Member {
    x: f64,
    y: f64,
    z: f64,
    heading: f64,
    w: f64,
    cos: f64,
    sin: f64,
}

/// The weighted particles binned horizontally by the kernel radius, for neighbour queries:
/// sorted by cell, column by column (x, then y), each cell's particles in their order, so
/// that the 3 × 3 cells around a place are three runs, visited in the order of the cells
/// `(x − 1, y − 1), (x − 1, y), …, (x + 1, y + 1)`.
#[derive(Debug, Clone, Default)]
struct Grid {
    cell: f64,
    /// The occupied cells, sorted.
    keys: Vec<(i64, i64)>,
    /// Where each cell's members start in `members` (one more entry than `keys`).
    starts: Vec<u32>,
    members: Vec<Member>,
    /// Scratch: `(cell, point index)` of every weighted point.
    order: Vec<([i64; 2], u32)>,
    /// Scratch of the sorting.
    packed: Vec<u64>,
}

impl Grid {
    fn build(&mut self, points: &[ClusterPoint], unit: &[Unit], cell: f64) {
        self.cell = cell;
        self.order.clear();
        self.order.extend(
            points
                .iter()
                .enumerate()
                .filter(|(_, p)| p.weight > 0.0)
                .map(|(i, p)| {
                    let (kx, ky) = Self::key(f64::from(p.x), f64::from(p.y), cell);
                    ([kx, ky], i as u32)
                }),
        );
        // Keys are unique (the index is part of them): the sorted order is in point order.
        sort_keys(&mut self.order, &mut self.packed);
        self.keys.clear();
        self.starts.clear();
        self.members.clear();
        for &([kx, ky], i) in &self.order {
            let key = (kx, ky);
            if self.keys.last() != Some(&key) {
                self.keys.push(key);
                self.starts.push(self.members.len() as u32);
            }
            let (p, u) = (&points[i as usize], unit[i as usize]);
            self.members.push(Member {
                x: f64::from(p.x),
                y: f64::from(p.y),
                z: f64::from(p.z),
                heading: f64::from(p.heading),
                w: f64::from(p.weight),
                cos: u.0,
                sin: u.1,
            });
        }
        self.starts.push(self.members.len() as u32);
    }

    fn key(x: f64, y: f64, cell: f64) -> (i64, i64) {
        ((x / cell).floor() as i64, (y / cell).floor() as i64)
    }

    /// The members of the cells `(x, y0..=y1)`.
    fn column(&self, x: i64, y0: i64, y1: i64) -> &[Member] {
        let a = self.keys.partition_point(|&k| k < (x, y0));
        let b = a + self.keys[a..].partition_point(|&k| k <= (x, y1));
        &self.members[self.starts[a] as usize..self.starts[b] as usize]
    }
}

/// A seeding bin: cell x, cell y, metre of height, heading sector.
type SeedBin = [i64; 4];

/// Bin seeding: the weighted mean of the particles of each occupied bin of edge `cell`
/// (per metre of height, per `sector` of heading), in bin order; each bin's particles are
/// summed in their order. `keys` and `packed` are scratch.
fn seeds(
    points: &[ClusterPoint],
    unit: &[Unit],
    cell: f64,
    sector: f64,
    keys: &mut Vec<(SeedBin, u32)>,
    packed: &mut Vec<u64>,
) -> Vec<Mode> {
    keys.clear();
    keys.extend(
        points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.weight > 0.0)
            .map(|(i, p)| {
                let (kx, ky) = Grid::key(f64::from(p.x), f64::from(p.y), cell);
                let kz = f64::from(p.z).floor() as i64;
                let kh = ((f64::from(p.heading) + std::f64::consts::PI) / sector).floor() as i64;
                ([kx, ky, kz, kh], i as u32)
            }),
    );
    sort_keys(keys, packed);
    let mut modes = Vec::new();
    for run in keys.chunk_by(|a, b| a.0 == b.0) {
        let mut m = Moments::default();
        for &(_, i) in run {
            m.add(&points[i as usize], &unit[i as usize]);
        }
        modes.push(m.mode());
    }
    modes
}

/// Modes closer than the kernel to a denser mode are that mode. The kept modes are binned
/// by the kernel radius, so each mode is compared with those of the 3 × 3 cells around it
/// only (a belief spread over a large open plan has as many modes as points).
fn merge_modes(mut modes: Vec<Mode>, config: &ClusterConfig) -> Vec<Mode> {
    modes.sort_by(|a, b| b.density.total_cmp(&a.density));
    let mut kept: Vec<Mode> = Vec::new();
    let mut cells: FxHashMap<(i64, i64), Vec<u32>> = FxHashMap::default();
    for m in modes {
        let (cx, cy) = Grid::key(m.x, m.y, config.radius);
        let near = (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                cells.get(&(cx + dx, cy + dy)).is_some_and(|v| {
                    v.iter().any(|&k| {
                        let k = &kept[k as usize];
                        (k.x - m.x).hypot(k.y - m.y) < config.radius
                            && (k.z - m.z).abs() < config.max_dz
                            && heading_gap(k.heading, m.heading) < config.max_dheading
                    })
                })
            })
        });
        if !near {
            cells.entry((cx, cy)).or_default().push(kept.len() as u32);
            kept.push(m);
        }
    }
    kept
}

/// The modes binned horizontally, for each particle's nearest mode.
struct ModeIndex {
    cell: f64,
    cells: FxHashMap<(i64, i64), Vec<u32>>,
    /// The cells' key range, `(min x, min y, max x, max y)`.
    extent: (i64, i64, i64, i64),
}

impl ModeIndex {
    fn new(modes: &[Mode], cell: f64) -> Self {
        let mut cells: FxHashMap<(i64, i64), Vec<u32>> = FxHashMap::default();
        let mut extent = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
        for (i, m) in modes.iter().enumerate() {
            let (cx, cy) = Grid::key(m.x, m.y, cell);
            extent = (
                extent.0.min(cx),
                extent.1.min(cy),
                extent.2.max(cx),
                extent.3.max(cy),
            );
            cells.entry((cx, cy)).or_default().push(i as u32);
        }
        Self {
            cell,
            cells,
            extent,
        }
    }

    /// The mode nearest `p` horizontally, one at another height (≥ `max_dz`) or heading
    /// (beyond `max_dheading`) counting as far away; the lowest index among equals. Searched
    /// ring by ring of cells outwards until no unseen mode can be nearer: the same answer as
    /// comparing every mode.
    fn nearest(&self, p: &ClusterPoint, modes: &[Mode], config: &ClusterConfig) -> Option<usize> {
        let (px, py) = (f64::from(p.x), f64::from(p.y));
        let (cx, cy) = Grid::key(px, py, self.cell);
        let distance = |m: &Mode| {
            let dz = (f64::from(p.z) - m.z).abs();
            let dh = heading_gap(f64::from(p.heading), m.heading);
            let mut penalty = if dz < config.max_dz { 0.0 } else { 1e6 * dz };
            if dh > config.max_dheading {
                penalty += 1e3 * dh;
            }
            (px - m.x).hypot(py - m.y) + penalty
        };
        // Rings beyond this one hold no mode.
        let (x0, y0, x1, y1) = self.extent;
        let last_ring = [cx - x0, x1 - cx, cy - y0, y1 - cy]
            .into_iter()
            .max()
            .unwrap_or(0)
            .max(0);
        let mut best: Option<(f64, usize)> = None;
        for ring in 0..=last_ring {
            // Every mode outside the rings searched so far is at least this far away.
            if let Some((d, _)) = best
                && d < (ring - 1).max(0) as f64 * self.cell
            {
                break;
            }
            let mut visit = |key: (i64, i64)| {
                for &i in self.cells.get(&key).map_or(&[][..], Vec::as_slice) {
                    let d = distance(&modes[i as usize]);
                    let i = i as usize;
                    if best.is_none_or(|(bd, bi)| d.total_cmp(&bd).then(i.cmp(&bi)).is_lt()) {
                        best = Some((d, i));
                    }
                }
            };
            if ring == 0 {
                visit((cx, cy));
                continue;
            }
            for k in -ring..=ring {
                visit((cx + k, cy - ring));
                visit((cx + k, cy + ring));
            }
            for k in -ring + 1..ring {
                visit((cx - ring, cy + k));
                visit((cx + ring, cy + k));
            }
        }
        best.map(|(_, i)| i)
    }
}

#[path = "cluster_shift.rs"]
mod shift;
use shift::Shifts;

#[path = "cluster_sort.rs"]
mod sort;
use sort::sort_keys;

#[cfg(test)]
#[path = "cluster_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "cluster_index_tests.rs"]
mod index_tests;
