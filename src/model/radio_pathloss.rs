//! The radio map beyond the survey: a log-distance path-loss model per access point,
//! fitted on a radio map's surveyed cells.
//!
//! Ordinary walks survey a fraction of a floor, and later walks go mostly where nobody
//! surveyed (on the ILC mall floor, 8 % of the held-out walks' scans fall in a surveyed
//! cell). There a Gaussian process ([`super::radio_interpolation`]) reverts to its prior and
//! knows nothing, while the scans still say much: an access point heard at −45 dBm, louder
//! than anywhere the survey heard it, puts the walker nearer to it than any surveyed place.
//! A path-loss model per access point carries that beyond the survey (Seidel & Rappaport
//! 1992's log-distance model; fitted from crowdsourced readings with unknown access point
//! positions as in EZ, Chintalapudi, Iyer & Padmanabhan 2010):
//!
//! * **Model** (eq. 1): the mean RSSI of access point `a` at a place `p` is
//!   `μ_a(p) = A_a + s_a · log10(max(|p − g_a|, d_0))`, with `g_a` the access point's
//!   position, `A_a` its level at 1 m and `s_a = −10 n_a` its slope.
//! * **Fit** (eq. 2): every cell centre within `max_offset_m` of the cell where the access
//!   point is loudest, on that cell's level, surveyed or not, is a candidate `g` (searched
//!   coarse to fine: one per `search_step_m` square, then all near the best); at each,
//!   `A` and `s` are the weighted least-squares line of the cells' mean readings against
//!   `log10 d` (weights: the readings per cell), `s` clamped to
//!   `[−10 n_max, −10 n_min]`; `g_a` is the candidate of least weighted squared residual,
//!   and `σ²_a` that residual (at least `variance_floor`). Access points read in fewer than
//!   `min_cells` cells are left out.
//! * **Detection** (eq. 3): `P_h(μ)`, the chance that a scan hears an access point whose
//!   predicted mean is `μ`, is measured on the survey itself: over every surveyed cell and
//!   modelled access point, the readings over the cell's scans, in `detection_bin_db` bins of
//!   `μ` (Laplace-smoothed, then made non-decreasing in `μ`). It absorbs how often real scans
//!   miss an access point in range (17 % of a cell's loud access points on the ILC floor) and
//!   how far the model errs at range.
//! * **Scan likelihood** at cell `c` (eq. 4), with `σ²_scan` a single scan's spread about
//!   the cell means (`scan_variance`):
//!
//!   ```text
//!   ln p(z | c) = Σ_{a heard} [ln N(r_a; μ_a(c), σ²_a + σ²_scan) + ln P_h(μ_a(c))]
//!               + Σ_{a modelled, not heard} ln(1 − P_h(μ_a(c)))
//!   ```
//!
//! Levels: a cell `k` levels from the access point's is `k · level_m` further (in the
//! distance of eq. 1) and `k · F_a` dB weaker, `F_a` fitted with `A_a` and `s_a` where the
//! access point is read on several levels (clamped to [0, 40] dB), else `level_loss_db`
//! (ITU-R P.1238's order for one concrete floor).

use crate::error::{Error, Result};
use crate::map::RadioMap;
use crate::sensor::WifiScan;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Parameters of [`PathLossMap`]; every default in one place.
///
/// | field              | default  | meaning                                                   |
/// |--------------------|----------|-----------------------------------------------------------|
/// | `min_exponent`     | 1.5      | least path-loss exponent `n` (slope −15 dB a decade)      |
/// | `max_exponent`     | 5        | greatest exponent (slope −50 dB a decade)                 |
/// | `min_cells`        | 4        | fewest cells an access point is read in to be modelled    |
/// | `max_offset_m`     | 60 m     | farthest an access point is placed from its loudest cell  |
/// | `search_step_m`    | 8 m      | the coarse search's square (then every cell near its 3 best) |
/// | `reference_m`      | 1 m      | `d_0`: distances below count as this                      |
/// | `variance_floor`   | 4 dB²    | least residual variance of an access point's fit          |
/// | `scan_variance`    | 9 dB²    | a single scan's spread about the cell means               |
/// | `detection_bin_db` | 2 dB     | bins of the predicted mean for the detection curve        |
/// | `level_m`          | 4 m      | distance added per level between cell and access point    |
/// | `level_loss_db`    | 15 dB    | loss per level where the survey cannot measure it         |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PathLossConfig {
    /// Least path-loss exponent.
    pub min_exponent: f64,
    /// Greatest path-loss exponent.
    pub max_exponent: f64,
    /// Fewest cells an access point must be read in to be modelled.
    pub min_cells: usize,
    /// Farthest an access point is placed from the cell where it is loudest, metres.
    pub max_offset_m: f64,
    /// Side of the coarse search's squares, metres: one candidate each, then every
    /// candidate within 1.5 sides of the best.
    pub search_step_m: f64,
    /// Distances below this count as this, metres.
    pub reference_m: f64,
    /// Least residual variance of an access point's fit, dB².
    pub variance_floor: f64,
    /// A single scan's spread about the cell means, dB².
    pub scan_variance: f64,
    /// Bin width of the predicted mean for the detection curve, dB.
    pub detection_bin_db: f64,
    /// Distance added per level between a cell and an access point, metres.
    pub level_m: f64,
    /// Loss per level between a cell and an access point where the survey does not read the
    /// access point on two levels, dB.
    pub level_loss_db: f64,
}

impl Default for PathLossConfig {
    fn default() -> Self {
        Self {
            min_exponent: 1.5,
            max_exponent: 5.0,
            min_cells: 4,
            max_offset_m: 60.0,
            search_step_m: 8.0,
            reference_m: 1.0,
            variance_floor: 4.0,
            scan_variance: 9.0,
            detection_bin_db: 2.0,
            level_m: 4.0,
            level_loss_db: 15.0,
        }
    }
}

impl PathLossConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] naming the first field out of range: exponents outside [0.5, 10] or
    /// not increasing, `min_cells` outside [3, 10⁴], distances or variances not positive.
    pub fn validate(&self) -> Result<()> {
        use crate::error::check_range;
        check_range("pathloss.min_exponent", self.min_exponent, 0.5..=10.0, "")?;
        check_range(
            "pathloss.max_exponent",
            self.max_exponent,
            self.min_exponent..=10.0,
            "",
        )?;
        check_range("pathloss.min_cells", self.min_cells as f64, 3.0..=1e4, "")?;
        check_range("pathloss.max_offset_m", self.max_offset_m, 1.0..=1e4, "metres")?;
        check_range("pathloss.search_step_m", self.search_step_m, 0.1..=1e3, "metres")?;
        check_range("pathloss.reference_m", self.reference_m, 0.01..=100.0, "metres")?;
        check_range("pathloss.variance_floor", self.variance_floor, 0.01..=1e4, "dB²")?;
        check_range("pathloss.scan_variance", self.scan_variance, 0.0..=1e4, "dB²")?;
        check_range(
            "pathloss.detection_bin_db",
            self.detection_bin_db,
            0.1..=20.0,
            "dB",
        )?;
        check_range("pathloss.level_m", self.level_m, 0.0..=100.0, "metres")?;
        check_range("pathloss.level_loss_db", self.level_loss_db, 0.0..=MAX_LEVEL_LOSS, "dB")
    }
}

/// Coarse candidates refined around (the fit's residual can have several basins).
const REFINED: usize = 3;
/// Greatest loss per level, dB.
const MAX_LEVEL_LOSS: f64 = 40.0;

/// One access point's fitted model (eq. 1).
#[derive(Debug, Clone, Copy, PartialEq)]
struct ApModel {
    /// Position and level.
    x: f64,
    y: f64,
    level: i32,
    /// Level at the reference distance (1 m), dBm.
    a: f64,
    /// dB per decade of distance (negative).
    slope: f64,
    /// Loss per level between the access point and the place, dB.
    level_loss: f64,
    /// Residual variance plus a single scan's, dB².
    variance: f64,
}

/// The detection curve of eq. (3): `ln P_h` and `ln(1 − P_h)` per bin of predicted mean.
#[derive(Debug, Clone, PartialEq)]
struct Detection {
    lowest: f64,
    bin: f64,
    ln_heard: Vec<f64>,
    ln_missed: Vec<f64>,
}

impl Detection {
    const LOWEST_DBM: f64 = -150.0;
    const HIGHEST_DBM: f64 = 10.0;

    fn bin_of(&self, mean: f64) -> usize {
        (((mean - self.lowest) / self.bin).floor().max(0.0) as usize).min(self.ln_heard.len() - 1)
    }
}

/// What a [`PathLossMap`] fit found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PathLossSummary {
    /// Access points modelled.
    pub access_points: usize,
    /// Median fitted path-loss exponent `n`.
    pub median_exponent: f64,
    /// Median residual spread of an access point's cell means about its fit, dB.
    pub median_residual_db: f64,
    /// The detection curve (eq. 3) at a few predicted means: `(dBm, P_h)`.
    pub heard_at: [(f64, f64); 4],
}

/// A path-loss model per access point of a radio map (module docs).
#[derive(Debug, Clone)]
pub struct PathLossMap {
    /// Centre and level of each cell of the map (NaN centre: no area).
    centres: Vec<(f64, f64, i32)>,
    models: Vec<ApModel>,
    columns: FxHashMap<String, usize>,
    detection: Detection,
    /// `Σ_a ln(1 − P_h(μ_a(c)))` over every modelled access point, per cell.
    all_missed: Vec<f64>,
    config: PathLossConfig,
}

/// An access point's readings: `(cell, mean dBm, readings)` per cell that heard it.
type Readings = Vec<(usize, f64, f64)>;

impl PathLossMap {
    /// Fits the model on `map`'s surveyed cells (eqs. 2–3).
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`PathLossConfig::validate`];
    /// [`Error::NotEnough`] when no access point is read in `min_cells` cells.
    pub fn fit(map: &RadioMap, config: &PathLossConfig) -> Result<Self> {
        config.validate()?;
        let centres = map.cell_centres();
        let mut readings: FxHashMap<&str, Readings> = FxHashMap::default();
        for (c, cell) in map.cells.iter().enumerate() {
            if !centres[c].0.is_finite() {
                continue;
            }
            for (bssid, stats) in &cell.radio.aps {
                if let Some(mean) = stats.mean() {
                    let entry = readings.entry(bssid.as_str()).or_default();
                    entry.push((c, mean, f64::from(stats.n)));
                }
            }
        }
        let mut bssids: Vec<&str> = readings
            .iter()
            .filter(|(_, r)| r.len() >= config.min_cells)
            .map(|(b, _)| *b)
            .collect();
        bssids.sort_unstable();
        if bssids.is_empty() {
            return Err(Error::not_enough(
                format!(
                    "no access point of the radio map is read in {} cells or more",
                    config.min_cells
                ),
                "survey more of the building",
            ));
        }
        let models: Vec<ApModel> = bssids
            .par_iter()
            .map(|b| fit_one(&centres, &readings[b], config))
            .collect();
        let columns = bssids
            .iter()
            .enumerate()
            .map(|(i, b)| ((*b).to_owned(), i))
            .collect();
        let mut out = Self {
            centres,
            models,
            columns,
            detection: Detection {
                lowest: Detection::LOWEST_DBM,
                bin: config.detection_bin_db,
                ln_heard: vec![0.0],
                ln_missed: vec![0.0],
            },
            all_missed: Vec::new(),
            config: *config,
        };
        out.detection = out.detection_curve(map, &bssids);
        out.all_missed = (0..out.centres.len())
            .into_par_iter()
            .map(|c| {
                out.models
                    .iter()
                    .map(|m| out.detection.ln_missed[out.detection.bin_of(out.mean_at(m, c))])
                    .sum()
            })
            .collect();
        Ok(out)
    }

    /// Access points modelled.
    #[must_use]
    pub fn access_points(&self) -> usize {
        self.models.len()
    }

    /// How many of the scan's access points are modelled.
    #[must_use]
    pub fn heard(&self, scan: &WifiScan) -> usize {
        scan.readings
            .iter()
            .filter(|r| self.columns.contains_key(&r.bssid))
            .count()
    }

    /// What the fit found, for a run's summary.
    #[must_use]
    pub fn summary(&self) -> PathLossSummary {
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
        };
        let ln_heard = |dbm: f64| self.detection.ln_heard[self.detection.bin_of(dbm)].exp();
        PathLossSummary {
            access_points: self.models.len(),
            median_exponent: median(self.models.iter().map(|m| -m.slope / 10.0).collect()),
            median_residual_db: median(
                self.models
                    .iter()
                    .map(|m| (m.variance - self.config.scan_variance).sqrt())
                    .collect(),
            ),
            heard_at: [-90.0, -80.0, -70.0, -60.0].map(|dbm| (dbm, ln_heard(dbm))),
        }
    }

    /// The predicted mean of access point `m` at cell `c` (eq. 1).
    fn mean_at(&self, m: &ApModel, c: usize) -> f64 {
        let (x, y, level) = self.centres[c];
        let levels = f64::from((level - m.level).abs());
        let d = (x - m.x).hypot(y - m.y).hypot(levels * self.config.level_m);
        m.a + m.slope * d.max(self.config.reference_m).log10() - m.level_loss * levels
    }

    /// Eq. (3) from the survey: the share of scans that heard each modelled access point, by
    /// its predicted mean in the cell.
    fn detection_curve(&self, map: &RadioMap, bssids: &[&str]) -> Detection {
        let bins = ((Detection::HIGHEST_DBM - Detection::LOWEST_DBM) / self.config.detection_bin_db)
            .ceil() as usize;
        let template = Detection {
            lowest: Detection::LOWEST_DBM,
            bin: self.config.detection_bin_db,
            ln_heard: vec![0.0; bins],
            ln_missed: vec![0.0; bins],
        };
        let mut heard = vec![0.0f64; bins];
        let mut scans = vec![0.0f64; bins];
        for (c, cell) in map.cells.iter().enumerate() {
            if cell.radio.scans == 0 || !self.centres[c].0.is_finite() {
                continue;
            }
            let n = f64::from(cell.radio.scans);
            for (m, bssid) in self.models.iter().zip(bssids) {
                let b = template.bin_of(self.mean_at(m, c));
                scans[b] += n;
                heard[b] += cell.radio.aps.get(*bssid).map_or(0.0, |s| f64::from(s.n));
            }
        }
        // The shares, non-decreasing in the predicted mean (pooled adjacent violators over
        // the bins with scans, each weighted by its scans; bins without take their lower
        // neighbour's, the lowest ones the first share), kept off 0 and 1 by one reading.
        let shares = monotone_shares(&heard, &scans);
        let floor = 1.0 / (scans.iter().sum::<f64>() + 2.0);
        let (ln_heard, ln_missed) = shares
            .iter()
            .map(|&p| {
                let p = p.clamp(floor, 1.0 - floor);
                (p.ln(), (1.0 - p).ln())
            })
            .unzip();
        Detection {
            ln_heard,
            ln_missed,
            ..template
        }
    }

    /// `ln p(z | c)` of eq. (4) at every cell (`None` for cells without area), or `None`
    /// when the scan hears no modelled access point.
    #[must_use]
    pub fn log_likelihoods(&self, scan: &WifiScan) -> Option<Vec<Option<f64>>> {
        let heard: Vec<(&ApModel, f64)> = scan
            .readings
            .iter()
            .filter_map(|r| self.columns.get(&r.bssid).map(|&i| (&self.models[i], r.rssi)))
            .collect();
        if heard.is_empty() {
            return None;
        }
        let ln_2pi = (2.0 * std::f64::consts::PI).ln();
        Some(
            (0..self.centres.len())
                .into_par_iter()
                .map(|c| {
                    if !self.centres[c].0.is_finite() {
                        return None;
                    }
                    let mut ll = self.all_missed[c];
                    for &(m, rssi) in &heard {
                        let mean = self.mean_at(m, c);
                        let b = self.detection.bin_of(mean);
                        let e = rssi - mean;
                        ll += -0.5 * (e * e / m.variance + m.variance.ln() + ln_2pi)
                            + self.detection.ln_heard[b]
                            - self.detection.ln_missed[b];
                    }
                    Some(ll)
                })
                .collect(),
        )
    }
}

/// The least-squares non-decreasing fit of `heard[i] / scans[i]` weighted by `scans[i]` (pool
/// adjacent violators), over the bins with scans; a bin without scans takes the share of the
/// nearest bin below that has some (the lowest ones, the first share; all 0 without scans).
fn monotone_shares(heard: &[f64], scans: &[f64]) -> Vec<f64> {
    // Blocks of (share, weight, bins with scans).
    let mut blocks: Vec<(f64, f64, usize)> = Vec::new();
    for (&h, &n) in heard.iter().zip(scans) {
        if n <= 0.0 {
            continue;
        }
        blocks.push((h / n, n, 1));
        while blocks.len() > 1 && blocks[blocks.len() - 2].0 > blocks[blocks.len() - 1].0 {
            let (p2, w2, k2) = blocks.pop().expect("two blocks");
            let (p1, w1, k1) = blocks.pop().expect("two blocks");
            blocks.push(((p1 * w1 + p2 * w2) / (w1 + w2), w1 + w2, k1 + k2));
        }
    }
    let mut fitted = blocks.iter().flat_map(|&(p, _, k)| std::iter::repeat_n(p, k));
    let first = blocks.first().map_or(0.0, |b| b.0);
    let mut last = first;
    scans
        .iter()
        .map(|&n| {
            if n > 0.0 {
                last = fitted.next().unwrap_or(last);
            }
            last
        })
        .collect()
}

/// Eq. (2) for one access point: a coarse search (the first candidate of each
/// `search_step_m` square), then every candidate within 1.5 squares of the [`REFINED`] best
/// coarse ones.
fn fit_one(centres: &[(f64, f64, i32)], readings: &Readings, config: &PathLossConfig) -> ApModel {
    let &(loudest, ..) = readings
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
        .expect("an access point has readings");
    let (lx, ly, level) = centres[loudest];
    let candidates: Vec<usize> = (0..centres.len())
        .filter(|&g| {
            let (gx, gy, glevel) = centres[g];
            glevel == level && gx.is_finite() && (gx - lx).hypot(gy - ly) <= config.max_offset_m
        })
        .collect();
    let mut rows = Vec::with_capacity(readings.len());
    let mut fit_at = |g: usize| {
        let (gx, gy, glevel) = centres[g];
        rows.clear();
        rows.extend(readings.iter().map(|&(c, rssi, w)| {
            let (x, y, l) = centres[c];
            let levels = f64::from((l - glevel).abs());
            let d = (x - gx).hypot(y - gy).hypot(levels * config.level_m);
            Row {
                log_d: d.max(config.reference_m).log10(),
                levels,
                rssi,
                w,
            }
        }));
        let (model, sse) = regress(&rows, config);
        let model = ApModel {
            x: gx,
            y: gy,
            level: glevel,
            ..model
        };
        (sse, model)
    };
    let step = config.search_step_m;
    let mut squares = rustc_hash::FxHashSet::default();
    let mut coarse: Vec<(f64, ApModel)> = candidates
        .iter()
        .filter(|&&g| {
            let (x, y, _) = centres[g];
            squares.insert(((x / step).floor() as i64, (y / step).floor() as i64))
        })
        .map(|&g| fit_at(g))
        .collect();
    coarse.sort_by(|a, b| a.0.total_cmp(&b.0));
    coarse.truncate(REFINED);
    let mut best: Option<(f64, ApModel)> = coarse.first().copied();
    for &g in &candidates {
        let (gx, gy, _) = centres[g];
        if coarse.iter().any(|(_, m)| (gx - m.x).hypot(gy - m.y) <= 1.5 * step) {
            let fit = fit_at(g);
            if best.as_ref().is_none_or(|(b, _)| fit.0 < *b) {
                best = Some(fit);
            }
        }
    }
    best.map_or(
        ApModel {
            x: lx,
            y: ly,
            level,
            a: readings.iter().map(|r| r.1).fold(f64::MIN, f64::max),
            slope: -10.0 * config.min_exponent,
            level_loss: config.level_loss_db,
            variance: config.variance_floor + config.scan_variance,
        },
        |(_, m)| m,
    )
}

/// One cell's reading of an access point, seen from a candidate position.
#[derive(Debug, Clone, Copy)]
struct Row {
    log_d: f64,
    levels: f64,
    rssi: f64,
    w: f64,
}

/// The weighted least-squares fit of `rssi = A + s · log_d − F · levels` (the slope clamped,
/// `F` fitted only where the readings span levels) and its weighted mean squared residual.
/// The returned model's position is left at the origin.
fn regress(rows: &[Row], config: &PathLossConfig) -> (ApModel, f64) {
    let total: f64 = rows.iter().map(|r| r.w).sum();
    let mean = |f: &dyn Fn(&Row) -> f64| rows.iter().map(|r| r.w * f(r)).sum::<f64>() / total;
    let (mx, ml, mr) = (mean(&|r| r.log_d), mean(&|r| r.levels), mean(&|r| r.rssi));
    let sxx = mean(&|r| (r.log_d - mx).powi(2));
    let sll = mean(&|r| (r.levels - ml).powi(2));
    let sxl = mean(&|r| (r.log_d - mx) * (r.levels - ml));
    let sxr = mean(&|r| (r.log_d - mx) * (r.rssi - mr));
    let slr = mean(&|r| (r.levels - ml) * (r.rssi - mr));
    let (lo, hi) = (-10.0 * config.max_exponent, -10.0 * config.min_exponent);
    let det = sxx * sll - sxl * sxl;
    // With readings on several levels, both coefficients (rssi falls with levels: −F);
    // else the slope alone and the configured loss per level.
    let (slope, level_loss) = if sll > 1e-9 && det > 1e-12 {
        let slope = ((sll * sxr - sxl * slr) / det).clamp(lo, hi);
        let fitted = if sll > 0.0 { -(slr - slope * sxl) / sll } else { 0.0 };
        (slope, fitted.clamp(0.0, MAX_LEVEL_LOSS))
    } else if sxx > 0.0 {
        ((sxr / sxx).clamp(lo, hi), config.level_loss_db)
    } else {
        (hi, config.level_loss_db)
    };
    let a = mr - slope * mx + level_loss * ml;
    let sse = mean(&|r| (r.rssi - a - slope * r.log_d + level_loss * r.levels).powi(2));
    let model = ApModel {
        x: 0.0,
        y: 0.0,
        level: 0,
        a,
        slope,
        level_loss,
        variance: sse.max(config.variance_floor) + config.scan_variance,
    };
    (model, sse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::radio_map::{CellRadio, RadioMapCell};
    use geo::{MultiPolygon, Rect};

    /// A 20 × 20 grid of 2 m cells; access points at (5, 5) and (35, 30) with exponent 3,
    /// surveyed only in the grid's western half (x < 20), one scan per cell.
    fn half_surveyed() -> RadioMap {
        let aps = [("west", 5.0, 5.0), ("east", 35.0, 30.0)];
        let mut cells = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                let (x, y) = (2.0 * f64::from(i) + 1.0, 2.0 * f64::from(j) + 1.0);
                let mut radio = CellRadio::default();
                if x < 20.0 {
                    let readings: Vec<(&str, f64)> = aps
                        .iter()
                        .map(|&(b, ax, ay)| {
                            let d = (x - ax).hypot(y - ay).max(1.0);
                            (b, -35.0 - 30.0 * d.log10())
                        })
                        .filter(|&(_, r)| r > -90.0)
                        .collect();
                    radio.add_scan(&WifiScan::from_readings(0.0, &readings));
                }
                let area = Rect::new((x - 1.0, y - 1.0), (x + 1.0, y + 1.0)).to_polygon();
                cells.push(RadioMapCell {
                    id: format!("0-{i}-{j}"),
                    level: 0,
                    area: MultiPolygon(vec![area]),
                    radio,
                });
            }
        }
        RadioMap {
            cells,
            ..Default::default()
        }
    }

    fn likeliest(map: &PathLossMap, scan: &WifiScan) -> (f64, f64) {
        let ll = map.log_likelihoods(scan).expect("modelled");
        let best = ll
            .iter()
            .enumerate()
            .filter_map(|(c, l)| l.map(|l| (c, l)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("a cell")
            .0;
        (map.centres[best].0, map.centres[best].1)
    }

    #[test]
    fn access_points_are_found_beyond_the_survey() {
        let map = PathLossMap::fit(&half_surveyed(), &PathLossConfig::default()).expect("fit");
        assert_eq!(map.access_points(), 2);
        let east = map.models[map.columns["east"]];
        // The eastern access point lies 15 m beyond the surveyed half: found within a cell or two.
        assert!((east.x - 35.0).hypot(east.y - 30.0) < 4.0, "{east:?}");
        assert!((east.slope + 30.0).abs() < 3.0, "{east:?}");
        let west = map.models[map.columns["west"]];
        assert!((west.x - 5.0).hypot(west.y - 5.0) < 2.0, "{west:?}");
    }

    #[test]
    fn a_scan_where_nobody_surveyed_is_placed_there() {
        let map = PathLossMap::fit(&half_surveyed(), &PathLossConfig::default()).expect("fit");
        // A scan at (31, 27), in the unsurveyed half, near the eastern access point.
        let (x, y) = (31.0f64, 27.0f64);
        let rssi = |ax: f64, ay: f64| -35.0 - 30.0 * (x - ax).hypot(y - ay).log10();
        let scan =
            WifiScan::from_readings(0.0, &[("west", rssi(5.0, 5.0)), ("east", rssi(35.0, 30.0))]);
        let (px, py) = likeliest(&map, &scan);
        assert!((px - x).hypot(py - y) < 6.0, "placed at ({px}, {py})");
        // A scan of access points nobody modelled: no likelihood.
        assert!(map.log_likelihoods(&WifiScan::from_readings(0.0, &[("x", -50.0)])).is_none());
    }

    #[test]
    fn detection_shares_are_pooled_where_they_fall() {
        // Bins: empty, 1/10, 5/10, 3/10 (a violation, pooled with the one before: 8/20),
        // empty, 9/10.
        let heard = [0.0, 1.0, 5.0, 3.0, 0.0, 9.0];
        let scans = [0.0, 10.0, 10.0, 10.0, 0.0, 10.0];
        let shares = monotone_shares(&heard, &scans);
        let want = [0.1, 0.1, 0.4, 0.4, 0.4, 0.9];
        for (got, want) in shares.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "{shares:?}");
        }
        assert_eq!(monotone_shares(&[0.0; 3], &[0.0; 3]), vec![0.0; 3]);
    }

    #[test]
    fn a_map_without_enough_readings_is_refused() {
        let mut map = half_surveyed();
        for cell in &mut map.cells[3..] {
            cell.radio = CellRadio::default();
        }
        let err = PathLossMap::fit(&map, &PathLossConfig::default()).unwrap_err();
        assert!(err.to_string().contains("cells or more"), "{err}");
    }
}
