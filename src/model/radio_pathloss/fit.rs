//! Eqs. (2) and (3) of the path-loss model: each access point's position, level and slope,
//! and the detection curve's monotone shares.

use super::{ApModel, MAX_LEVEL_LOSS, PathLossConfig, REFINED, Readings, distance};

/// The least-squares non-decreasing fit of `heard[i] / scans[i]` weighted by `scans[i]` (pool
/// adjacent violators), over the bins with scans; a bin without scans takes the share of the
/// nearest bin below that has some (the lowest ones, the first share; all 0 without scans).
pub(super) fn monotone_shares(heard: &[f64], scans: &[f64]) -> Vec<f64> {
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
    let mut fitted = blocks
        .iter()
        .flat_map(|&(p, _, k)| std::iter::repeat_n(p, k));
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
pub(super) fn fit_one(
    centres: &[(f64, f64, i32)],
    readings: &Readings,
    config: &PathLossConfig,
) -> ApModel {
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
            let d = distance(x - gx, y - gy, levels * config.level_m);
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
        if coarse
            .iter()
            .any(|(_, m)| (gx - m.x).hypot(gy - m.y) <= 1.5 * step)
        {
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
    // Weighted means, then the centred second moments in one pass.
    let (mut total, mut mx, mut ml, mut mr) = (0.0, 0.0, 0.0, 0.0);
    for r in rows {
        total += r.w;
        mx += r.w * r.log_d;
        ml += r.w * r.levels;
        mr += r.w * r.rssi;
    }
    (mx, ml, mr) = (mx / total, ml / total, mr / total);
    let (mut sxx, mut sll, mut sxl, mut sxr, mut slr) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for r in rows {
        let (x, l, y) = (r.log_d - mx, r.levels - ml, r.rssi - mr);
        sxx += r.w * x * x;
        sll += r.w * l * l;
        sxl += r.w * x * l;
        sxr += r.w * x * y;
        slr += r.w * l * y;
    }
    let (sxx, sll, sxl, sxr, slr) = (
        sxx / total,
        sll / total,
        sxl / total,
        sxr / total,
        slr / total,
    );
    let (lo, hi) = (-10.0 * config.max_exponent, -10.0 * config.min_exponent);
    let det = sxx * sll - sxl * sxl;
    // With readings on several levels, both coefficients (rssi falls with levels: −F);
    // else the slope alone and the configured loss per level.
    let (slope, level_loss) = if sll > 1e-9 && det > 1e-12 {
        let slope = ((sll * sxr - sxl * slr) / det).clamp(lo, hi);
        let fitted = if sll > 0.0 {
            -(slr - slope * sxl) / sll
        } else {
            0.0
        };
        (slope, fitted.clamp(0.0, MAX_LEVEL_LOSS))
    } else if sxx > 0.0 {
        ((sxr / sxx).clamp(lo, hi), config.level_loss_db)
    } else {
        (hi, config.level_loss_db)
    };
    let a = mr - slope * mx + level_loss * ml;
    let sse = rows
        .iter()
        .map(|r| r.w * (r.rssi - a - slope * r.log_d + level_loss * r.levels).powi(2))
        .sum::<f64>()
        / total;
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
