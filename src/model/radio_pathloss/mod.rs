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
//! * **Device offset** (eq. 5): phones read a few dB apart (the ILC walks ±3.5 dB about the
//!   survey's scans within 3 m), and one offset `δ` moves every reading of a scan. With
//!   `δ ~ N(0, τ²)` (`device_offset_db`) integrated out, the heard readings' residuals
//!   `e_a = r_a − μ_a(c)` with weights `w_a = 1 / σ²_a` add
//!
//!   ```text
//!   ½ (Σ_a w_a e_a)² / (Σ_a w_a + 1/τ²)
//!   ```
//!
//!   to eq. (4) (the Gaussian's Sherman–Morrison form; `−½ ln(1 + τ² Σ w_a)` is the same at
//!   every cell and left out): a scan is placed by its readings' differences more than by
//!   their level.
//!
//! Levels: a cell `k` levels from the access point's is `k · level_m` further (in the
//! distance of eq. 1) and `k · F_a` dB weaker, `F_a` fitted with `A_a` and `s_a` where the
//! access point is read on several levels (clamped to [0, 40] dB), else `level_loss_db`
//! (ITU-R P.1238's order for one concrete floor).

mod fit;

use crate::error::{Error, Result};
use crate::map::RadioMap;
use crate::sensor::WifiScan;
use fit::{fit_one, monotone_shares};
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
/// | `device_offset_db` | 4 dB     | `τ`: spread of a scan's device offset (0: none)            |
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
    /// `τ` of eq. (5): spread of a scan's device offset, dB (0: none).
    pub device_offset_db: f64,
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
            device_offset_db: 4.0,
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
        check_range(
            "pathloss.max_offset_m",
            self.max_offset_m,
            1.0..=1e4,
            "metres",
        )?;
        check_range(
            "pathloss.search_step_m",
            self.search_step_m,
            0.1..=1e3,
            "metres",
        )?;
        check_range(
            "pathloss.reference_m",
            self.reference_m,
            0.01..=100.0,
            "metres",
        )?;
        check_range(
            "pathloss.variance_floor",
            self.variance_floor,
            0.01..=1e4,
            "dB²",
        )?;
        check_range(
            "pathloss.scan_variance",
            self.scan_variance,
            0.0..=1e4,
            "dB²",
        )?;
        check_range(
            "pathloss.detection_bin_db",
            self.detection_bin_db,
            0.1..=20.0,
            "dB",
        )?;
        check_range("pathloss.level_m", self.level_m, 0.0..=100.0, "metres")?;
        check_range(
            "pathloss.level_loss_db",
            self.level_loss_db,
            0.0..=MAX_LEVEL_LOSS,
            "dB",
        )?;
        check_range(
            "pathloss.device_offset_db",
            self.device_offset_db,
            0.0..=30.0,
            "dB",
        )
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

    /// The bin of a predicted mean (below the lowest bin: the lowest; `as` truncates what
    /// `max` keeps non-negative, so no `floor`).
    fn bin_of(&self, mean: f64) -> usize {
        (((mean - self.lowest) / self.bin).max(0.0) as usize).min(self.ln_heard.len() - 1)
    }
}

/// Most `(access point, cell)` means a [`PathLossMap`] tabulates (4 bytes each: 128 MB);
/// beyond, a scan's heard access points are evaluated per cell as it is weighed.
const MAX_TABLE: usize = 1 << 25;

/// Cells per parallel task of a scan's likelihood.
const CHUNK: usize = 512;

/// The distance of a horizontal offset `(dx, dy)` and a vertical one `dz` (the same bits as
/// `dx.hypot(dy).hypot(dz)`, without the second `hypot` on one level).
fn distance(dx: f64, dy: f64, dz: f64) -> f64 {
    let h = dx.hypot(dy);
    if dz == 0.0 { h } else { h.hypot(dz) }
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
    /// `μ_a(c)` of eq. (1), row by access point, where the models × cells fit
    /// [`MAX_TABLE`].
    means: Option<Vec<f32>>,
    /// `Σ_a ln(1 − P_h(μ_a(c)))` over every modelled access point, per cell.
    all_missed: Vec<f64>,
    /// `ln P_h − ln(1 − P_h)` per bin of the detection curve: a heard access point's term
    /// over a missed one's.
    heard_gain: Vec<f64>,
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
            means: None,
            all_missed: Vec::new(),
            heard_gain: Vec::new(),
            config: *config,
        };
        let cells = out.centres.len();
        if out.models.len() * cells <= MAX_TABLE {
            let mut table = vec![0.0f32; out.models.len() * cells];
            table
                .par_chunks_mut(cells.max(1))
                .zip(&out.models)
                .for_each(|(row, m)| {
                    for (c, mean) in row.iter_mut().enumerate() {
                        *mean = out.mean_at(m, c);
                    }
                });
            out.means = Some(table);
        }
        out.detection = out.detection_curve(map, &bssids);
        out.heard_gain = (out.detection.ln_heard.iter())
            .zip(&out.detection.ln_missed)
            .map(|(h, m)| h - m)
            .collect();
        out.all_missed = (0..cells)
            .into_par_iter()
            .map(|c| {
                (0..out.models.len())
                    .map(|a| out.detection.ln_missed[out.detection.bin_of(out.mean(a, c))])
                    .sum()
            })
            .collect();
        Ok(out)
    }

    /// Centre and level of each cell of the map the model was fitted on (NaN centre: no
    /// area).
    #[must_use]
    pub fn centres(&self) -> &[(f64, f64, i32)] {
        &self.centres
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
    fn mean_at(&self, m: &ApModel, c: usize) -> f32 {
        let (x, y, level) = self.centres[c];
        let levels = f64::from((level - m.level).abs());
        let d = distance(x - m.x, y - m.y, levels * self.config.level_m);
        (m.a + m.slope * d.max(self.config.reference_m).log10() - m.level_loss * levels) as f32
    }

    /// `μ_a(c)` of the `a`-th model, from the table where there is one.
    fn mean(&self, a: usize, c: usize) -> f64 {
        f64::from(match &self.means {
            Some(table) => table[a * self.centres.len() + c],
            None => self.mean_at(&self.models[a], c),
        })
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
            for (a, bssid) in bssids.iter().enumerate() {
                let b = template.bin_of(self.mean(a, c));
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
        // Each heard access point's model, reading, 1 / σ² and the terms that are the same
        // at every cell.
        let ln_2pi = (2.0 * std::f64::consts::PI).ln();
        let heard: Vec<(usize, f64, f64, f64)> = scan
            .readings
            .iter()
            .filter_map(|r| {
                let a = *self.columns.get(&r.bssid)?;
                let variance = self.models[a].variance;
                Some((a, r.rssi, variance.recip(), -0.5 * (variance.ln() + ln_2pi)))
            })
            .collect();
        if heard.is_empty() {
            return None;
        }
        let mut ll = self.all_missed.clone();
        let tau2 = self.config.device_offset_db.powi(2);
        let shrink = if tau2 > 0.0 {
            let total: f64 = heard.iter().map(|h| h.2).sum();
            0.5 / (total + tau2.recip())
        } else {
            0.0
        };
        // Access point by access point over a chunk of cells, the table's rows read in
        // order; each cell adds its terms in the scan's order.
        ll.par_chunks_mut(CHUNK).enumerate().for_each(|(i, chunk)| {
            let first = i * CHUNK;
            // Scratch for the means where there is no table, and eq. (5)'s sums.
            let mut row = vec![0.0f32; if self.means.is_some() { 0 } else { chunk.len() }];
            let mut pulled = vec![0.0f64; if shrink > 0.0 { chunk.len() } else { 0 }];
            for &(a, rssi, precision, constant) in &heard {
                let means = match &self.means {
                    Some(table) => &table[a * self.centres.len() + first..][..chunk.len()],
                    None => {
                        for (k, mean) in row.iter_mut().enumerate() {
                            *mean = self.mean_at(&self.models[a], first + k);
                        }
                        &row
                    }
                };
                for (k, (l, &mean)) in chunk.iter_mut().zip(means).enumerate() {
                    let mean = f64::from(mean);
                    let e = rssi - mean;
                    *l += constant - 0.5 * e * e * precision
                        + self.heard_gain[self.detection.bin_of(mean)];
                    if let Some(p) = pulled.get_mut(k) {
                        *p += precision * e;
                    }
                }
            }
            for (l, p) in chunk.iter_mut().zip(&pulled) {
                *l += shrink * p * p;
            }
        });
        Some(
            ll.into_iter()
                .zip(&self.centres)
                .map(|(l, centre)| centre.0.is_finite().then_some(l))
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests;
