//! WiFi scans as evidence of revisits inside FootSLAM: every scan is compared with the
//! walker's earlier scans, and a particle is weighted by how well the distance between its
//! position now and its own position at each earlier scan agrees with how alike the two
//! scans are (WiSLAM's idea, Bruno & Robertson, IPIN 2011, in scan-to-scan form).
//!
//! **Why scan to scan, not a radio map per particle.** WiSLAM keeps per particle and per
//! hexagon the RSSI statistics of every access point. On ordinary walks a place is heard a
//! few times at most, so a per-particle radio map is, in effect, the particle's earlier
//! scans placed where that particle put them, at the cost of tens of access points per
//! hexagon per particle. Keeping only the particle's position at each earlier scan (8 bytes
//! a scan, shared by descendants, [`crate::filter::footslam`]) holds the same information;
//! the radio map is then a kernel map over the scans, and the likelihood of a new scan
//! reduces to pair terms.
//!
//! **The model.** For scans `k` and `j` let `D_kj` be their RSSI dissimilarity (eq. 1): the
//! root mean square RSSI difference over the access points either heard, a reading missing
//! from one scan counted at `floor_rssi`. `D` grows with the distance `d` between the places
//! they were taken. Its conditional density is modelled per distance as a normal with a
//! uniform outlier floor,
//!
//! `p(D | d) = (1 − η) · N(D; μ(d), σ(d)) + η / D_max`                      (2)
//!
//! and a particle at distance `d_kj` from its own position at scan `j` is weighted by
//!
//! `ln w_k = n_k^(−γ) · Σ_j [ln p(D_kj | d_kj) − ln p(D_kj | d_far)]`       (3)
//!
//! over the `n_k` earlier scans `j` that are informative (the bracket moves by more than
//! [`INFORMATIVE`] over distance) and at least `min_gap_s` older (closer ones are the steps'
//! business). The bracket rewards a particle that is near where similar scans were heard and
//! penalises one that folds onto a place that sounded different; the tempering `n_k^(−γ)`
//! stands for the pairs not being independent (scans heard at one place agree with one
//! another).
//!
//! **Calibrated on the walk itself.** `μ(d)` and `σ(d)` (median and scaled MAD per distance
//! bin, [`PairLikelihood::calibrate`]) come from the walk's own scan pairs less than
//! `calibration_window_s` apart, whose distance dead reckoning knows well over so short a
//! time. No constant belongs to a building: stale readings, body shadowing, device
//! sensitivity and the access points' density all enter through the measured spread.

use crate::geometry::Pose2;
use crate::sensor::step::step_at_time;
use crate::sensor::{Step, WifiScan};
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// A pair whose log ratio (eq. 3's bracket) moves less than this over distance is left out.
pub const INFORMATIVE: f64 = 0.05;
/// Distance resolution of the pair tables, metres.
pub(super) const D_STEP: f64 = 0.25;
/// Distance beyond which a pair tells nothing more (the last table entry), metres.
const D_FAR: f64 = 24.0;
/// Entries per table row.
pub(super) const ROW: usize = (D_FAR / D_STEP) as usize + 1;
/// Dissimilarity resolution of the pair tables, dB.
pub(super) const DB_STEP: f64 = 0.25;
/// The largest dissimilarity tabulated, dB (larger ones read the last row).
const DB_MAX: f64 = 80.0;
/// Upper edges of the calibration's distance bins, metres.
const BIN_EDGES: [f64; 7] = [2.0, 4.0, 7.0, 11.0, 16.0, 24.0, f64::INFINITY];
/// Calibration pairs a distance bin needs to stand on its own.
const MIN_BIN_PAIRS: usize = 10;
/// The lags tried for a scan's latency, seconds apart.
const LATENCY_STEP: f64 = 0.25;
/// The smallest spread a bin may have, dB.
const MIN_SIGMA: f64 = 1.0;

/// Settings of the scan-pair model; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ScanPairConfig {
    /// Weight particles by the walk's WiFi scans (when it has them). Default true.
    pub enabled: bool,
    /// In a FeetSLAM batch's later passes, weigh each scan also against the other walks'
    /// scans placed where their previous pass put them ([`super::scan_references`]).
    /// Default false: on the 106 walks of ILC F1 it moved the waypoint errors by less than
    /// 2 % (docs/footslam.md). Only `learn` of a whole batch in one process applies it;
    /// a batch run walk by walk (`--shard`, the Python batch runner) does not.
    pub cross_walk: bool,
    /// The most similar of the other walks' scans a scan is weighed against. Default 32.
    pub references_per_scan: usize,
    /// Earlier scans closer in time than this are left to the steps, seconds. Default 15.
    pub min_gap_s: f64,
    /// Scan pairs at most this far apart in time calibrate the model (their distance from
    /// dead reckoning), seconds. Default 60.
    pub calibration_window_s: f64,
    /// What an access point missing from one scan of a pair reads as, dBm. Default −100.
    pub floor_rssi: f64,
    /// `η` of eq. (2): pairs that disagree with the model (a door shut, a crowd). Default 0.05.
    pub outlier_share: f64,
    /// `γ` of eq. (3), how far the pairs of one scan are taken as dependent: 0 counts each in
    /// full, 1 averages them. Default 1: on the museum routes of docs/footslam.md, 0.5
    /// let the scans bend the paths (p95 up to 1.4 m worse than without them), 1 did not.
    pub pair_tempering: f64,
    /// Calibration pairs needed to use the scans at all. Default 30.
    pub min_calibration_pairs: usize,
    /// The longest latency (eq. 4) searched, seconds; 0 takes the time stamps as they are.
    /// Default 4.
    pub latency_max_s: f64,
}

impl Default for ScanPairConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            cross_walk: false,
            references_per_scan: 32,
            min_gap_s: 15.0,
            calibration_window_s: 60.0,
            floor_rssi: -100.0,
            outlier_share: 0.05,
            pair_tempering: 1.0,
            min_calibration_pairs: 30,
            latency_max_s: 4.0,
        }
    }
}

impl ScanPairConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) for the first field that is not finite or is out of
    /// its range (e.g. `floor_rssi` outside [−150, −30] dBm, `latency_max_s` outside [0, 30] s),
    /// with the range.
    pub fn validate(&self) -> crate::error::Result<()> {
        use crate::error::check_range;
        check_range("wifi.min_gap_s", self.min_gap_s, 0.0..=3600.0, "s")?;
        check_range(
            "wifi.calibration_window_s",
            self.calibration_window_s,
            1.0..=3600.0,
            "s",
        )?;
        check_range("wifi.floor_rssi", self.floor_rssi, -150.0..=-30.0, "dBm")?;
        check_range("wifi.outlier_share", self.outlier_share, 1e-6..=0.9, "")?;
        check_range("wifi.pair_tempering", self.pair_tempering, 0.0..=1.0, "")?;
        check_range(
            "wifi.references_per_scan",
            self.references_per_scan as f64,
            0.0..=10_000.0,
            "",
        )?;
        check_range("wifi.latency_max_s", self.latency_max_s, 0.0..=30.0, "s")
    }
}

/// A scan as its access points' ids (sorted) and RSSI.
#[derive(Debug, Clone)]
pub(super) struct CompactScan {
    readings: Vec<(u32, f32)>,
}

impl CompactScan {
    pub(super) fn new(scan: &WifiScan, ids: &mut FxHashMap<String, u32>, floor: f64) -> Self {
        let mut readings: Vec<(u32, f32)> = scan
            .readings
            .iter()
            .filter(|r| r.rssi > floor)
            .map(|r| {
                let next = ids.len() as u32;
                (*ids.entry(r.bssid.clone()).or_insert(next), r.rssi as f32)
            })
            .collect();
        readings.sort_unstable_by_key(|r| r.0);
        readings.dedup_by_key(|r| r.0);
        Self { readings }
    }
}

/// Eq. (1): the RMS RSSI difference of two scans over the access points either heard, a
/// missing reading taken as `floor`; `None` when neither heard any.
pub(super) fn dissimilarity(a: &CompactScan, b: &CompactScan, floor: f64) -> Option<f64> {
    let (a, b) = (&a.readings, &b.readings);
    let floor = floor as f32;
    let (mut i, mut j, mut sum, mut n) = (0, 0, 0.0f64, 0u32);
    while i < a.len() || j < b.len() {
        let diff = match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x.0 == y.0 => {
                i += 1;
                j += 1;
                x.1 - y.1
            }
            (Some(x), Some(y)) if x.0 < y.0 => {
                i += 1;
                x.1 - floor
            }
            (Some(x), None) => {
                i += 1;
                x.1 - floor
            }
            (_, Some(y)) => {
                j += 1;
                y.1 - floor
            }
            (None, None) => unreachable!(),
        };
        sum += f64::from(diff * diff);
        n += 1;
    }
    (n > 0).then(|| (sum / f64::from(n)).sqrt())
}

/// Eq. (2): the density of a pair's dissimilarity given the distance between its places,
/// per distance bin, calibrated on the walk.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairLikelihood {
    /// Each bin's median distance, metres.
    pub distance: Vec<f64>,
    /// Each bin's median dissimilarity `μ`, dB.
    pub mu: Vec<f64>,
    /// Each bin's spread `σ` (scaled median absolute deviation), dB.
    pub sigma: Vec<f64>,
    /// Calibration pairs in each distance bin (all seven, populated or not; `distance`, `mu`
    /// and `sigma` list the populated ones and, first, one extrapolated to near places).
    pub pairs: Vec<usize>,
    /// `η`.
    pub outlier_share: f64,
}

impl PairLikelihood {
    /// Fits eq. (2) to `(distance, dissimilarity)` pairs: the median and scaled MAD of `D`
    /// in each distance bin, bins with too few pairs interpolated from their neighbours (or
    /// extrapolated, the nearest bin's `μ` and `σ` beyond the last), `μ` made non-decreasing
    /// with distance. `None` with fewer than two populated bins.
    ///
    /// # Panics
    ///
    /// Never: the one `expect` unwraps a bin just found fitted.
    pub fn calibrate(pairs: &[(f64, f64)], outlier_share: f64) -> Option<Self> {
        let mut bins: Vec<Vec<(f64, f64)>> = vec![Vec::new(); BIN_EDGES.len()];
        for &(d, big_d) in pairs {
            let b = BIN_EDGES.iter().position(|&e| d < e).unwrap_or(0);
            bins[b].push((d, big_d));
        }
        let fitted: Vec<Option<(f64, f64, f64)>> = bins
            .iter_mut()
            .map(|bin| {
                (bin.len() >= MIN_BIN_PAIRS).then(|| {
                    let d = median(bin.iter().map(|p| p.0).collect());
                    let values: Vec<f64> = bin.iter().map(|p| p.1).collect();
                    let mu = median(values.clone());
                    let mad = median(values.iter().map(|v| (v - mu).abs()).collect());
                    (d, mu, (1.4826 * mad).max(MIN_SIGMA))
                })
            })
            .collect();
        let known: Vec<usize> = (0..fitted.len()).filter(|&b| fitted[b].is_some()).collect();
        if known.len() < 2 {
            return None;
        }
        let (mut distance, mut mu, mut sigma) = (Vec::new(), Vec::new(), Vec::new());
        for &b in &known {
            let (d, m, s) = fitted[b].expect("known bins are fitted");
            distance.push(d);
            mu.push(m);
            sigma.push(s);
        }
        // Near places first: a walk that never came back within 2 m leaves the first bin
        // empty; extend the trend of the next two, never below half their μ.
        if known[0] != 0 && distance[0] > BIN_EDGES[0] {
            let slope = (mu[1] - mu[0]) / (distance[1] - distance[0]).max(1e-6);
            let d0 = BIN_EDGES[0] / 2.0;
            let m0 = (mu[0] - slope.max(0.0) * (distance[0] - d0)).max(0.5 * mu[0]);
            distance.insert(0, d0);
            mu.insert(0, m0);
            sigma.insert(0, sigma[0]);
        }
        for i in 1..mu.len() {
            mu[i] = mu[i].max(mu[i - 1]);
        }
        let pairs = bins.iter().map(Vec::len).collect();
        Some(Self {
            distance,
            mu,
            sigma,
            pairs,
            outlier_share,
        })
    }

    /// `(μ(d), σ(d))`, linear between bins, the end bins' values beyond.
    fn at(&self, d: f64) -> (f64, f64) {
        let x = &self.distance;
        let i = x.partition_point(|&c| c <= d);
        if i == 0 {
            return (self.mu[0], self.sigma[0]);
        }
        if i == x.len() {
            return (self.mu[i - 1], self.sigma[i - 1]);
        }
        let f = (d - x[i - 1]) / (x[i] - x[i - 1]);
        (
            self.mu[i - 1] + f * (self.mu[i] - self.mu[i - 1]),
            self.sigma[i - 1] + f * (self.sigma[i] - self.sigma[i - 1]),
        )
    }

    /// Eq. (2): `ln p(D | d)`.
    #[must_use]
    pub fn log_density(&self, big_d: f64, d: f64) -> f64 {
        let (mu, sigma) = self.at(d);
        let z = (big_d - mu) / sigma;
        let normal = (-0.5 * z * z).exp() / (sigma * (std::f64::consts::TAU).sqrt());
        ((1.0 - self.outlier_share) * normal + self.outlier_share / DB_MAX).ln()
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_unstable_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// One informative earlier scan of a scan: its index and its table row.
#[derive(Debug, Clone, Copy)]
struct Pair {
    earlier: u32,
    row: u16,
}

/// Why a walk's scans could not be used.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ScanPairsUnused {
    /// The configuration switches them off.
    Disabled,
    /// Fewer scans than two.
    TooFewScans(usize),
    /// Too few calibration pairs (or too few distance bins) to fit eq. (2).
    TooFewPairs(usize),
}

impl std::fmt::Display for ScanPairsUnused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Disabled => write!(f, "switched off (wifi.enabled = false)"),
            Self::TooFewScans(n) => write!(f, "{n} scans: at least 2 are needed"),
            Self::TooFewPairs(n) => write!(
                f,
                "{n} scan pairs close enough in time to calibrate the model: too few (or \
                 all at one distance)"
            ),
        }
    }
}

/// A walk's scans ready for the filter: eq. (3)'s informative pairs and their tables.
#[derive(Debug, Clone)]
pub struct ScanEvidence {
    times: Vec<f64>,
    /// Scan `k`'s pairs are `pairs[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<u32>,
    pairs: Vec<Pair>,
    /// Eq. (3)'s tempering per scan.
    temper: Vec<f32>,
    /// Row `r` (a dissimilarity of `r · DB_STEP`) at distance `i · D_STEP`: eq. (3)'s bracket.
    table: Vec<f32>,
    /// The calibrated eq. (2).
    pub likelihood: PairLikelihood,
    /// Calibration pairs used.
    pub calibration_pairs: usize,
    /// How long before its time stamp a scan was heard, seconds (eq. 4).
    pub latency_s: f64,
}

impl ScanEvidence {
    /// The evidence of `scans` (in time order) for a walk of `steps`: eq. (2) calibrated on
    /// pairs less than `calibration_window_s` apart placed by dead reckoning, then each
    /// scan's informative earlier scans.
    ///
    /// # Errors
    ///
    /// Why the scans cannot be used: [`ScanPairsUnused::Disabled`] when `config.enabled` is false,
    /// [`ScanPairsUnused::TooFewScans`] with fewer than two scans, [`ScanPairsUnused::TooFewPairs`]
    /// when fewer than `min_calibration_pairs` pairs of scans (not both empty) lie within
    /// `calibration_window_s`, or when no latency spreads them over two distance bins of ten pairs.
    pub fn new(
        scans: &[WifiScan],
        steps: &[Step],
        config: &ScanPairConfig,
    ) -> Result<Self, ScanPairsUnused> {
        if !config.enabled {
            return Err(ScanPairsUnused::Disabled);
        }
        if scans.len() < 2 {
            return Err(ScanPairsUnused::TooFewScans(scans.len()));
        }
        let mut ids = FxHashMap::default();
        let compact: Vec<CompactScan> = scans
            .iter()
            .map(|s| CompactScan::new(s, &mut ids, config.floor_rssi))
            .collect();
        let times: Vec<f64> = scans.iter().map(|s| s.t).collect();
        // Pairs close in time, whose distance dead reckoning knows.
        let mut near = Vec::new();
        for k in 0..scans.len() {
            for j in (0..k).rev() {
                if times[k] - times[j] > config.calibration_window_s {
                    break;
                }
                if let Some(big_d) = dissimilarity(&compact[k], &compact[j], config.floor_rssi) {
                    near.push((k, j, big_d));
                }
            }
        }
        if near.len() < config.min_calibration_pairs {
            return Err(ScanPairsUnused::TooFewPairs(near.len()));
        }
        let (latency_s, likelihood) = calibrate_latency(&near, &times, steps, config)
            .ok_or(ScanPairsUnused::TooFewPairs(near.len()))?;
        let calibration_pairs = near.len();
        let times: Vec<f64> = times.iter().map(|t| t - latency_s).collect();
        let (table, informative) = tabulate(&likelihood);
        let (mut offsets, mut pairs, mut temper) = (vec![0u32], Vec::new(), Vec::new());
        for k in 0..scans.len() {
            let start = pairs.len();
            for j in 0..k {
                if times[k] - times[j] < config.min_gap_s {
                    break;
                }
                let Some(big_d) = dissimilarity(&compact[k], &compact[j], config.floor_rssi) else {
                    continue;
                };
                let row = ((big_d / DB_STEP).round() as usize).min(informative.len() - 1);
                if informative[row] {
                    pairs.push(Pair {
                        earlier: j as u32,
                        row: row as u16,
                    });
                }
            }
            let n = (pairs.len() - start).max(1) as f64;
            temper.push(n.powf(-config.pair_tempering) as f32);
            offsets.push(pairs.len() as u32);
        }
        Ok(Self {
            times,
            offsets,
            pairs,
            temper,
            table,
            likelihood,
            calibration_pairs,
            latency_s,
        })
    }

    /// The scans' times, in order.
    #[must_use]
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Informative pairs over all scans.
    #[must_use]
    pub fn pairs(&self) -> usize {
        self.pairs.len()
    }

    /// Eq. (3) for scan `k` taken at `at`, the particle's positions at the earlier scans
    /// given by `earlier(j)`; pairs for which `same_place_possible(j)` is false (another
    /// floor) are left out.
    pub fn log_factor(
        &self,
        k: usize,
        at: (f32, f32),
        earlier: impl Fn(usize) -> (f32, f32),
        same_place_possible: impl Fn(usize) -> bool,
    ) -> f64 {
        let range = self.offsets[k] as usize..self.offsets[k + 1] as usize;
        let mut sum = 0.0f32;
        for pair in &self.pairs[range] {
            let j = pair.earlier as usize;
            if !same_place_possible(j) {
                continue;
            }
            let (x, y) = earlier(j);
            let d = (at.0 - x).hypot(at.1 - y);
            let i = ((d * (1.0 / D_STEP as f32)) as usize).min(ROW - 1);
            sum += self.table[usize::from(pair.row) * ROW + i];
        }
        f64::from(sum * self.temper[k])
    }
}

/// Eq. (4): a scan's latency — how long before its time stamp the receiver heard it (a
/// scan sweeps the channels for a second or more, and phones deliver cached results) — and
/// eq. (2) calibrated with it: of the lags `0, Δ, …, latency_max_s`, the one under which the
/// near pairs' dissimilarities are most probable given their dead-reckoned distances. A
/// walker heading out and back would otherwise place each leg's scans a latency's walk
/// apart. `None` when no lag gives a model.
fn calibrate_latency(
    near: &[(usize, usize, f64)],
    times: &[f64],
    steps: &[Step],
    config: &ScanPairConfig,
) -> Option<(f64, PairLikelihood)> {
    let lags = (config.latency_max_s / LATENCY_STEP).floor() as usize;
    let mut best: Option<(f64, f64, PairLikelihood)> = None;
    for i in 0..=lags {
        let lag = i as f64 * LATENCY_STEP;
        let heard: Vec<f64> = times.iter().map(|t| t - lag).collect();
        let places = dead_reckoned_at(steps, &heard);
        let pairs: Vec<(f64, f64)> = near
            .iter()
            .map(|&(k, j, big_d)| {
                let d = (places[k].0 - places[j].0).hypot(places[k].1 - places[j].1);
                (d, big_d)
            })
            .collect();
        let Some(model) = PairLikelihood::calibrate(&pairs, config.outlier_share) else {
            continue;
        };
        let score: f64 = pairs
            .iter()
            .map(|&(d, big_d)| model.log_density(big_d, d))
            .sum();
        if best.as_ref().is_none_or(|b| score > b.1 + 1e-9) {
            best = Some((lag, score, model));
        }
    }
    best.map(|(lag, _, model)| (lag, model))
}

/// Eq. (3)'s bracket for every tabulated dissimilarity and distance, and whether each row
/// is informative.
pub(super) fn tabulate(likelihood: &PairLikelihood) -> (Vec<f32>, Vec<bool>) {
    let rows = (DB_MAX / DB_STEP) as usize + 1;
    let mut table = vec![0.0f32; rows * ROW];
    let mut informative = vec![false; rows];
    for r in 0..rows {
        let big_d = r as f64 * DB_STEP;
        let far = likelihood.log_density(big_d, D_FAR);
        let row = &mut table[r * ROW..(r + 1) * ROW];
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for (i, v) in row.iter_mut().enumerate() {
            let x = likelihood.log_density(big_d, i as f64 * D_STEP) - far;
            lo = lo.min(x);
            hi = hi.max(x);
            *v = x as f32;
        }
        informative[r] = hi - lo > INFORMATIVE;
    }
    (table, informative)
}

/// The dead-reckoned position at each of `times` (in order), from the origin heading east,
/// interpolated within the step it falls in (before the first step: the start; after the
/// last: its end).
fn dead_reckoned_at(steps: &[Step], times: &[f64]) -> Vec<(f64, f64)> {
    let mut pose = Pose2::default();
    let poses: Vec<Pose2> = steps
        .iter()
        .map(|s| {
            pose = pose.step(s.length, s.dheading);
            pose
        })
        .collect();
    times
        .iter()
        .map(|&t| {
            let (k, along) = step_at_time(steps, t);
            let before = k.checked_sub(1).map_or(Pose2::default(), |j| poses[j]);
            match poses.get(k) {
                Some(next) => (
                    before.x + along * (next.x - before.x),
                    before.y + along * (next.y - before.y),
                ),
                None => (before.x, before.y),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests;
