//! KLD-sampling (Fox 2003): how many particles a sample-based belief needs.
//!
//! The state space is split into bins (Woodman & Harle 2008: 1 m × 1 m in position, 10° in
//! heading, and the floor level). If the belief occupies `k` bins, then
//!
//! ```text
//! n_χ(k) = (k − 1) / (2ε) · {1 − 2 / (9(k − 1)) + √(2 / (9(k − 1))) · z_{1−δ}}³      (Fox eq. 13)
//! ```
//!
//! samples keep the Kullback–Leibler divergence between the sample-based maximum-likelihood
//! estimate and the true belief below `ε` with probability `1 − δ`.
//!
//! Fox draws samples one at a time and counts the bins they fall in until `n ≥ n_χ(k)`. A
//! sequential loop does not parallelise, so [`KldBins::sample_size`] solves the same stopping
//! rule in expectation: with `W_b` the belief's mass in bin `b`, `n` draws hit
//! `E[k(n)] = Σ_b 1 − (1 − W_b)ⁿ` distinct bins, and the sample size is the smallest `n` with
//! `n ≥ n_χ(E[k(n)])`. The prior, drawn afresh, uses Fox's sequential rule as written
//! ([`KldBins::mark`]).

use crate::error::Result;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A dense bin array holds at most this many bins; larger spaces use a hash map.
const MAX_DENSE_BINS: usize = 1 << 25;
/// Bisection stops when the bracket's ratio is below `1 + SIZE_TOLERANCE`.
const SIZE_TOLERANCE: f64 = 0.002;

/// KLD-sampling's parameters; every default in one place.
///
/// | field             | default     | meaning                                           |
/// |-------------------|-------------|---------------------------------------------------|
/// | `epsilon`         | 0.035       | bound on the KL divergence `ε`                    |
/// | `delta`           | 0.01        | probability `δ` that the bound is exceeded        |
/// | `bin_size`        | 1.0 m       | bin edge in x and y                               |
/// | `bin_heading`     | 10° (rad)   | bin width in heading                              |
/// | `min_particles`   | 500         | fewest particles                                  |
/// | `max_particles`   | 8,000,000   | most particles (of a prior)                       |
/// | `max_step_particles` | 1,000,000 | most particles after a step: bounds each step's work, however large and open the plan |
///
/// With these values a uniform prior over the 8,725 m² of Woodman & Harle's building needs
/// about 4.5 million particles, the number the paper reports (sec. "Scalability").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct KldConfig {
    /// Bound `ε` on the KL divergence.
    pub epsilon: f64,
    /// Probability `δ` of exceeding the bound.
    pub delta: f64,
    /// Bin edge in x and y, metres.
    pub bin_size: f64,
    /// Bin width in heading, radians.
    pub bin_heading: f64,
    /// Fewest particles.
    pub min_particles: usize,
    /// Most particles (a prior over the plan may draw this many).
    pub max_particles: usize,
    /// Most particles after a step (at most `max_particles`): a belief spread over a large
    /// open plan, which no wall narrows, would otherwise keep the prior's millions at every
    /// step.
    pub max_step_particles: usize,
}

impl KldConfig {
    /// Caps the particles at `n` (`--particles`): the most at the prior, and after a step
    /// where that was higher.
    pub fn cap_particles(&mut self, n: usize) {
        self.max_particles = n;
        self.max_step_particles = self.max_step_particles.min(n);
    }
}

impl Default for KldConfig {
    fn default() -> Self {
        Self {
            epsilon: 0.035,
            delta: 0.01,
            bin_size: 1.0,
            bin_heading: 10f64.to_radians(),
            min_particles: 500,
            max_particles: 8_000_000,
            max_step_particles: 1_000_000,
        }
    }
}

impl KldConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `epsilon` is outside (0, 1), `delta` outside
    /// (0, 0.5), `bin_size` outside [0.05, 100] m, `bin_heading` outside (0, 2π] radians,
    /// `min_particles` is 0 or above `max_particles`, `max_step_particles` outside [1, 2·10⁸], or
    /// `max_particles` above 2·10⁸.
    pub fn validate(&self) -> Result<()> {
        if !(self.epsilon.is_finite() && self.epsilon > 0.0 && self.epsilon < 1.0) {
            return Err(crate::error::Error::config(
                "kld.epsilon",
                self.epsilon.to_string(),
                "must be in (0, 1)",
            ));
        }
        if !(self.delta.is_finite() && self.delta > 0.0 && self.delta < 0.5) {
            return Err(crate::error::Error::config(
                "kld.delta",
                self.delta.to_string(),
                "must be in (0, 0.5)",
            ));
        }
        if !(self.bin_size.is_finite() && (0.05..=100.0).contains(&self.bin_size)) {
            return Err(crate::error::Error::config(
                "kld.bin_size",
                self.bin_size.to_string(),
                "must be in [0.05, 100] metres",
            ));
        }
        if !(self.bin_heading.is_finite() && self.bin_heading > 0.0 && self.bin_heading <= TAU) {
            return Err(crate::error::Error::config(
                "kld.bin_heading",
                self.bin_heading.to_string(),
                "must be in (0, 2π] radians",
            ));
        }
        if self.min_particles == 0 || self.min_particles > self.max_particles {
            return Err(crate::error::Error::config(
                "kld.min_particles",
                self.min_particles.to_string(),
                "must be at least 1 and at most max_particles",
            ));
        }
        if self.max_step_particles == 0 || self.max_step_particles > 200_000_000 {
            return Err(crate::error::Error::config(
                "kld.max_step_particles",
                self.max_step_particles.to_string(),
                "must be in [1, 200000000]",
            ));
        }
        if self.max_particles > 200_000_000 {
            return Err(crate::error::Error::config(
                "kld.max_particles",
                self.max_particles.to_string(),
                "must be at most 200000000",
            ));
        }
        Ok(())
    }

    /// The most particles a step may keep: `max_step_particles`, at most `max_particles`.
    #[must_use]
    pub fn step_cap(&self) -> usize {
        self.max_step_particles.min(self.max_particles)
    }

    /// Fox's `n_χ(k)` (eq. 13) for these `ε` and `δ`, before clamping to the particle limits.
    #[must_use]
    pub fn required(&self, k: f64) -> f64 {
        required_particles(k, self.epsilon, standard_normal_quantile(1.0 - self.delta))
    }
}

/// Fox 2003, eq. (13): samples needed for `k` occupied bins, bound `epsilon` and the
/// upper `1 − δ` quantile `z` of the standard normal distribution.
#[must_use]
pub fn required_particles(k: f64, epsilon: f64, z: f64) -> f64 {
    if k <= 1.0 {
        return 1.0;
    }
    let a = 2.0 / (9.0 * (k - 1.0));
    let c = 1.0 - a + a.sqrt() * z;
    (k - 1.0) / (2.0 * epsilon) * c * c * c
}

/// The standard normal quantile function (Acklam's rational approximation, relative error
/// below 1.2e-9).
#[must_use]
pub fn standard_normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let p = p.clamp(1e-300, 1.0 - 1e-16);
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// Storage of per-bin masses: dense over the space's box when it is small enough.
#[derive(Debug, Clone)]
enum Store {
    Dense { mass: Vec<f64>, touched: Vec<u32> },
    Sparse(FxHashMap<u64, f64>),
}

/// The bins of one building's state space (x, y, heading, level) and the belief's mass in
/// each, reused from step to step without allocating.
#[derive(Debug, Clone)]
pub struct KldBins {
    config: KldConfig,
    z: f64,
    min: [f32; 2],
    /// Reciprocals of the bin size and the heading bin width.
    inv_size: f32,
    inv_heading: f32,
    nx: u64,
    ny: u64,
    nh: u64,
    min_level: i32,
    store: Store,
    /// `ln(1 − W_b)` of every occupied bin (and the count of bins holding all the mass).
    log_miss: Vec<f64>,
    certain: usize,
}

impl KldBins {
    /// Bins covering `bounds` (min x, min y, max x, max y, metres) and levels
    /// `levels.0..=levels.1`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `config` fails [`KldConfig::validate`].
    pub fn new(config: &KldConfig, bounds: [f64; 4], levels: (i32, i32)) -> Result<Self> {
        config.validate()?;
        let s = config.bin_size;
        let nx = (((bounds[2] - bounds[0]) / s).floor().max(0.0) as u64) + 1;
        let ny = (((bounds[3] - bounds[1]) / s).floor().max(0.0) as u64) + 1;
        let nh = ((TAU / config.bin_heading).ceil() as u64).max(1);
        let nl = (i64::from(levels.1) - i64::from(levels.0)).max(0) as u64 + 1;
        let total = nx.saturating_mul(ny).saturating_mul(nh).saturating_mul(nl);
        let store = if total <= MAX_DENSE_BINS as u64 {
            Store::Dense {
                mass: vec![0.0; total as usize],
                touched: Vec::new(),
            }
        } else {
            Store::Sparse(FxHashMap::default())
        };
        Ok(Self {
            config: *config,
            z: standard_normal_quantile(1.0 - config.delta),
            min: [bounds[0] as f32, bounds[1] as f32],
            inv_size: (1.0 / config.bin_size) as f32,
            inv_heading: (1.0 / config.bin_heading) as f32,
            nx,
            ny,
            nh,
            min_level: levels.0,
            store,
            log_miss: Vec::new(),
            certain: 0,
        })
    }

    /// True when bins are indices into a dense array (below 2²⁵ bins), so that a bin fits
    /// in a `u32`.
    #[must_use]
    pub fn dense(&self) -> bool {
        matches!(self.store, Store::Dense { .. })
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &KldConfig {
        &self.config
    }

    /// The bin of a state; positions outside the box fall in its border bins.
    #[inline]
    #[must_use]
    pub fn bin(&self, x: f32, y: f32, heading: f32, level: i32) -> u64 {
        let ix = (((x - self.min[0]) * self.inv_size).max(0.0) as u64).min(self.nx - 1);
        let iy = (((y - self.min[1]) * self.inv_size).max(0.0) as u64).min(self.ny - 1);
        let h = if heading < 0.0 {
            heading + std::f32::consts::TAU
        } else {
            heading
        };
        let ih = ((h.max(0.0) * self.inv_heading) as u64).min(self.nh - 1);
        let il = (i64::from(level) - i64::from(self.min_level)).max(0) as u64;
        ((il * self.ny + iy) * self.nx + ix) * self.nh + ih
    }

    /// Empties every bin.
    pub fn clear(&mut self) {
        match &mut self.store {
            Store::Dense { mass, touched } => {
                for &b in touched.iter() {
                    mass[b as usize] = 0.0;
                }
                touched.clear();
            }
            Store::Sparse(map) => map.clear(),
        }
        self.log_miss.clear();
        self.certain = 0;
    }

    /// Adds `mass` to bin `bin`; returns true when the bin was empty.
    #[inline]
    pub fn add(&mut self, bin: u64, mass: f64) -> bool {
        match &mut self.store {
            Store::Dense { mass: m, touched } => {
                let slot = &mut m[bin as usize];
                let fresh = *slot == 0.0;
                if fresh {
                    touched.push(bin as u32);
                }
                *slot += mass;
                fresh
            }
            Store::Sparse(map) => {
                let slot = map.entry(bin).or_insert(0.0);
                let fresh = *slot == 0.0;
                *slot += mass;
                fresh
            }
        }
    }

    /// Marks bin `bin` as occupied by one more sample (Fox's sequential rule); returns true
    /// when it was empty.
    #[inline]
    pub fn mark(&mut self, bin: u64) -> bool {
        self.add(bin, 1.0)
    }

    /// Number of occupied bins.
    #[must_use]
    pub fn occupied(&self) -> usize {
        match &self.store {
            Store::Dense { touched, .. } => touched.len(),
            Store::Sparse(map) => map.len(),
        }
    }

    /// Fox's stopping rule for `n` samples in `k` occupied bins: true when `n` suffices.
    #[must_use]
    pub fn enough(&self, n: usize, k: usize) -> bool {
        self.enough_given(n, self.required(k))
    }

    /// [`Self::enough`] with `n_χ(k)` given ([`Self::required`]): a sequential draw
    /// computes it again only when `k` grows.
    #[must_use]
    pub fn enough_given(&self, n: usize, required: f64) -> bool {
        n >= self.config.max_particles || self.satisfied_given(n, required)
    }

    /// Whether `n` samples over `k` occupied bins meet the KLD bound (and the minimum),
    /// regardless of the cap.
    #[must_use]
    pub fn satisfied(&self, n: usize, k: usize) -> bool {
        self.satisfied_given(n, self.required(k))
    }

    /// [`Self::satisfied`] with `n_χ(k)` given ([`Self::required`]).
    #[must_use]
    pub fn satisfied_given(&self, n: usize, required: f64) -> bool {
        n >= self.config.min_particles && n as f64 >= required
    }

    /// Fox's `n_χ(k)` (eq. 13) for these bins' `ε` and `δ`.
    #[must_use]
    pub fn required(&self, k: usize) -> f64 {
        required_particles(k as f64, self.config.epsilon, self.z)
    }

    /// The sample size for the belief whose masses were [`add`](Self::add)ed since the last
    /// [`clear`](Self::clear): the smallest `n` in `[min_particles, max_particles]` with
    /// `n ≥ n_χ(E[k(n)])`, `E[k(n)] = Σ_b 1 − (1 − W_b)ⁿ` over normalised masses `W_b`.
    pub fn sample_size(&mut self) -> usize {
        self.sample_size_at_least(self.config.min_particles)
    }

    /// [`sample_size`](Self::sample_size) with the lower limit raised to `min` (capped at
    /// `max_particles`).
    pub fn sample_size_at_least(&mut self, min: usize) -> usize {
        let min = min
            .max(self.config.min_particles)
            .min(self.config.max_particles);
        let total: f64 = match &self.store {
            Store::Dense { mass, touched } => touched.iter().map(|&b| mass[b as usize]).sum(),
            Store::Sparse(map) => map.values().sum(),
        };
        let (lo, hi) = (min as f64, self.config.max_particles as f64);
        if !(total > 0.0 && total.is_finite()) {
            return min;
        }
        self.log_miss.clear();
        self.certain = 0;
        let mut push = |w: f64| {
            let w = w / total;
            if w >= 1.0 - 1e-15 {
                self.certain += 1;
            } else if w > 0.0 {
                self.log_miss.push((-w).ln_1p());
            }
        };
        match &self.store {
            Store::Dense { mass, touched } => touched.iter().for_each(|&b| push(mass[b as usize])),
            Store::Sparse(map) => map.values().for_each(|&w| push(w)),
        }
        let needs_more = |n: f64| n < self.config.required(self.expected_bins(n));
        if !needs_more(lo) {
            return min;
        }
        if needs_more(hi) {
            return self.config.max_particles;
        }
        let (mut a, mut b) = (lo, hi);
        while b > a * (1.0 + SIZE_TOLERANCE) && b - a > 1.0 {
            let m = (a * b).sqrt();
            if needs_more(m) { a = m } else { b = m }
        }
        (b.ceil() as usize).clamp(min, self.config.max_particles)
    }

    /// `E[k(n)]`: the expected number of distinct bins `n` draws from the belief hit.
    fn expected_bins(&self, n: f64) -> f64 {
        self.certain as f64
            + self
                .log_miss
                .iter()
                .map(|&l| 1.0 - (n * l).exp())
                .sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_matches_tables() {
        assert!((standard_normal_quantile(0.99) - 2.326_347_874).abs() < 1e-8);
        assert!((standard_normal_quantile(0.5)).abs() < 1e-12);
        assert!((standard_normal_quantile(0.025) + 1.959_963_985).abs() < 1e-8);
        assert!((standard_normal_quantile(0.999) - 3.090_232_306).abs() < 1e-8);
    }

    #[test]
    fn required_particles_grows_linearly_in_bins() {
        let c = KldConfig::default();
        assert_eq!(c.required(1.0), 1.0);
        let r100 = c.required(100.0);
        let r10k = c.required(10_000.0);
        assert!(r100 > 99.0 / 0.07 && r100 < 3.0 * 99.0 / 0.07, "{r100}");
        assert!((r10k / (9_999.0 / 0.07) - 1.0).abs() < 0.1, "{r10k}");
        // The paper's building: 8725 m² × 36 heading bins needs about 4.5 M particles.
        let paper = c.required(8725.0 * 36.0);
        assert!((4.3e6..4.8e6).contains(&paper), "{paper}");
    }

    #[test]
    fn bins_separate_position_heading_and_level() {
        let bins =
            KldBins::new(&KldConfig::default(), [0.0, 0.0, 10.0, 5.0], (0, 2)).expect("bins");
        let b = bins.bin(1.5, 2.5, 0.05, 1);
        assert_eq!(b, bins.bin(1.9, 2.1, 0.1, 1));
        assert_ne!(b, bins.bin(2.1, 2.5, 0.05, 1));
        assert_ne!(b, bins.bin(1.5, 3.5, 0.05, 1));
        assert_ne!(b, bins.bin(1.5, 2.5, 0.3, 1));
        assert_ne!(b, bins.bin(1.5, 2.5, 0.05, 2));
        // Headings wrap; outside positions clamp to the border.
        assert_eq!(bins.bin(0.0, 0.0, -0.01, 0), bins.bin(0.0, 0.0, 6.27, 0));
        assert_eq!(bins.bin(-5.0, 0.0, 0.0, 0), bins.bin(0.0, 0.0, 0.0, 0));
    }

    #[test]
    fn concentrated_belief_needs_few_particles_spread_belief_many() {
        let config = KldConfig {
            min_particles: 10,
            ..Default::default()
        };
        let mut bins = KldBins::new(&config, [0.0, 0.0, 100.0, 100.0], (0, 0)).expect("bins");
        bins.add(bins.bin(5.0, 5.0, 0.0, 0), 1.0);
        assert_eq!(bins.sample_size(), 10);
        bins.clear();
        assert_eq!(bins.occupied(), 0);
        // 1000 equal bins: E[k(n)] ≈ 1000 once n ≫ 1000, so n ≈ n_χ(1000).
        for i in 0..1000 {
            let b = bins.bin((i % 100) as f32 + 0.5, (i / 100) as f32 + 0.5, 0.0, 0);
            assert!(bins.add(b, 0.001));
        }
        let n = bins.sample_size() as f64;
        let expected = config.required(1000.0);
        assert!((n / expected - 1.0).abs() < 0.02, "{n} vs {expected}");
        // Tiny masses in many extra bins add little: far fewer than n_χ(k) for all bins.
        for i in 0..5000 {
            let b = bins.bin((i % 100) as f32 + 0.5, 50.5 + (i / 100) as f32, 0.0, 0);
            bins.add(b, 1e-9);
        }
        let m = bins.sample_size() as f64;
        assert!(m < 1.1 * n, "{m} vs {n}");
        assert!(m < config.required(6000.0) / 2.0);
    }

    #[test]
    fn sample_size_respects_limits() {
        let config = KldConfig {
            min_particles: 50,
            max_particles: 2000,
            ..Default::default()
        };
        let mut bins = KldBins::new(&config, [0.0, 0.0, 100.0, 100.0], (0, 0)).expect("bins");
        for i in 0..10_000 {
            bins.add(bins.bin((i % 100) as f32, (i / 100) as f32, 0.0, 0), 1.0);
        }
        assert_eq!(bins.sample_size(), 2000);
        bins.clear();
        assert_eq!(bins.sample_size(), 50);
        assert!(bins.enough(2000, 1_000_000));
        assert!(!bins.enough(100, 1_000));
    }

    #[test]
    fn huge_spaces_fall_back_to_a_hash_map() {
        let mut bins =
            KldBins::new(&KldConfig::default(), [0.0, 0.0, 5000.0, 5000.0], (0, 3)).expect("bins");
        assert!(matches!(bins.store, Store::Sparse(_)));
        assert!(bins.add(bins.bin(4999.0, 4999.0, 1.0, 3), 1.0));
        assert!(!bins.add(bins.bin(4999.0, 4999.0, 1.0, 3), 1.0));
        assert_eq!(bins.occupied(), 1);
    }

    #[test]
    fn bad_config_is_rejected() {
        for c in [
            KldConfig {
                epsilon: 0.0,
                ..Default::default()
            },
            KldConfig {
                delta: f64::NAN,
                ..Default::default()
            },
            KldConfig {
                min_particles: 10,
                max_particles: 5,
                ..Default::default()
            },
        ] {
            assert!(c.validate().is_err());
        }
    }
}
