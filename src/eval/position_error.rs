//! Position error of an estimated track against the ground truth.
//!
//! Each track point is compared with the truth at the same time, linearly interpolated
//! between the two truth samples around it. Track points outside the truth's time span are
//! skipped (and counted). With [`Alignment::Rigid`] the track is first moved by the rigid
//! transform that best fits it to the matched truth (least squares), which measures the
//! shape of a track learned without absolute anchors.
//!
//! Percentiles use the nearest-rank method: of `n` errors sorted ascending, the `P`-th
//! percentile is the one of rank `⌈P·n/100⌉` (1-based), an actual error, never interpolated.

use crate::error::{Error, Result};
use crate::geometry::{RigidTransform, nearest_rank};
use crate::io::TimedPoint;
use serde::{Deserialize, Serialize, Serializer};

/// How the track is placed on the truth before measuring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Alignment {
    /// As estimated: absolute errors.
    #[default]
    None,
    /// After the best rotation and translation of the track onto the truth.
    Rigid,
}

/// Summary of the position errors, metres.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorReport {
    /// Track points compared.
    pub n: usize,
    /// Track points skipped because they lie outside the truth's time span.
    pub skipped: usize,
    /// Median error (nearest rank).
    pub p50: f64,
    /// 75th percentile (nearest rank).
    pub p75: f64,
    /// 90th percentile (nearest rank).
    pub p90: f64,
    /// 95th percentile (nearest rank).
    pub p95: f64,
    /// Largest error.
    pub max: f64,
    /// Mean error.
    pub mean: f64,
    /// Root mean square error.
    pub rmse: f64,
    /// The transform applied to the track (track frame → truth frame) with
    /// [`Alignment::Rigid`]; `None` without alignment.
    #[serde(serialize_with = "serialize_transform")]
    pub transform: Option<RigidTransform>,
}

/// The fewest matched points a rigid alignment is measured on: two points leave one degree
/// of freedom of four, fewer none.
pub const MIN_RIGID_POINTS: usize = 3;

/// The least spread (RMS distance from their centre) of the truth's matched points a rigid
/// alignment is measured on, metres: a truth that stays in one place fixes no rotation, and
/// the alignment would fit any track onto it.
pub const MIN_RIGID_SPREAD_M: f64 = 0.5;

/// The RMS distance of `points` from their centre, metres.
fn rms_spread(points: &[(f64, f64)]) -> f64 {
    let n = points.len().max(1) as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(sx, sy), &(x, y)| (sx + x / n, sy + y / n));
    (points
        .iter()
        .map(|&(x, y)| (x - mx).powi(2) + (y - my).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

/// Errors of `track` against `truth` (both in time order, local metres).
///
/// # Errors
///
/// - [`Error::NotEnough`] when either series is empty, or a rigid alignment would rest on fewer
///   than [`MIN_RIGID_POINTS`] matched points or on a truth that spreads less than
///   [`MIN_RIGID_SPREAD_M`].
/// - [`Error::InvalidData`] naming a point that is not finite or not strictly after the one before
///   it.
/// - [`Error::Mismatch`] when no track point lies within the truth's time span (another clock?).
pub fn position_errors(
    truth: &[TimedPoint],
    track: &[TimedPoint],
    alignment: Alignment,
) -> Result<ErrorReport> {
    check_series(truth, "truth")?;
    check_series(track, "track")?;
    let (estimated, reference): (Vec<_>, Vec<_>) = track
        .iter()
        .filter_map(|p| interpolate_at(truth, p.t).map(|q| ((p.x, p.y), q)))
        .unzip();
    let n = estimated.len();
    if n == 0 {
        let (t0, t1) = (truth[0].t, truth[truth.len() - 1].t);
        return Err(Error::mismatch(
            format!(
                "none of the {} track points lies within the truth's time span [{t0}, {t1}] s",
                track.len()
            ),
            "are they on the same clock?",
        ));
    }
    if alignment == Alignment::Rigid && n < MIN_RIGID_POINTS {
        return Err(Error::not_enough(
            format!(
                "a rigid alignment needs at least {MIN_RIGID_POINTS} track points within the \
                 truth's time span, got {n}: it would fit them exactly and report no error"
            ),
            "use no alignment",
        ));
    }
    let spread = rms_spread(&reference);
    if alignment == Alignment::Rigid && spread < MIN_RIGID_SPREAD_M {
        return Err(Error::not_enough(
            format!(
                "a rigid alignment measures a track's shape, but the truth's {n} points \
                 matched in time lie within {spread:.2} m (RMS) of one place: any track \
                 would fit it"
            ),
            "use no alignment, or a truth of a walk that moves",
        ));
    }
    let transform = match alignment {
        Alignment::None => None,
        Alignment::Rigid => RigidTransform::fit(&estimated, &reference),
    };
    let mut errors: Vec<f64> = estimated
        .iter()
        .zip(&reference)
        .map(|(&p, &(tx, ty))| {
            let (x, y) = transform.map_or(p, |t| t.apply(p));
            (x - tx).hypot(y - ty)
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    let count = n as f64;
    Ok(ErrorReport {
        n,
        skipped: track.len() - n,
        p50: nearest_rank(&errors, 50),
        p75: nearest_rank(&errors, 75),
        p90: nearest_rank(&errors, 90),
        p95: nearest_rank(&errors, 95),
        max: errors[n - 1],
        mean: errors.iter().sum::<f64>() / count,
        rmse: (errors.iter().map(|e| e * e).sum::<f64>() / count).sqrt(),
        transform,
    })
}

/// The position of a series (time order) at time `t`, linearly interpolated; `None` outside
/// its time span.
#[must_use]
pub fn interpolate_at(truth: &[TimedPoint], t: f64) -> Option<(f64, f64)> {
    let i = truth.partition_point(|p| p.t < t);
    let b = truth.get(i)?;
    if b.t == t {
        return Some((b.x, b.y));
    }
    let a = truth.get(i.checked_sub(1)?)?;
    let f = (t - a.t) / (b.t - a.t);
    Some((a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)))
}

fn check_series(points: &[TimedPoint], name: &str) -> Result<()> {
    if points.is_empty() {
        return Err(Error::not_enough(format!("the {name} has no points"), ""));
    }
    if let Some(i) = points
        .iter()
        .position(|p| !(p.t.is_finite() && p.x.is_finite() && p.y.is_finite()))
    {
        return Err(Error::invalid(format!("{name} point {i}"), "is not finite"));
    }
    if let Some(i) = points.windows(2).position(|w| w[1].t <= w[0].t) {
        return Err(Error::invalid(
            format!("{name} point {}", i + 1),
            format!(
                "at {} s follows {} s: times must be strictly increasing",
                points[i + 1].t,
                points[i].t
            ),
        ));
    }
    Ok(())
}

/// Writes a transform as `{"angle": rad, "tx": m, "ty": m}` (or `null`).
fn serialize_transform<S: Serializer>(t: &Option<RigidTransform>, s: S) -> Result<S::Ok, S::Error> {
    #[derive(Serialize)]
    struct Wire {
        angle: f64,
        tx: f64,
        ty: f64,
    }
    t.map(|t| Wire {
        angle: t.angle,
        tx: t.tx,
        ty: t.ty,
    })
    .serialize(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tp(t: f64, x: f64, y: f64) -> TimedPoint {
        TimedPoint { t, x, y }
    }

    #[test]
    fn interpolates_truth_and_skips_points_outside_its_span() {
        let truth = [tp(0.0, 0.0, 0.0), tp(10.0, 10.0, 0.0), tp(20.0, 10.0, 10.0)];
        // Errors 1 (t = 5, truth (5, 0)), 0 (t = 10), 2 (t = 15, truth (10, 5)).
        let track = [
            tp(-1.0, 0.0, 0.0),
            tp(5.0, 5.0, 1.0),
            tp(10.0, 10.0, 0.0),
            tp(15.0, 12.0, 5.0),
            tp(21.0, 0.0, 0.0),
        ];
        let r = position_errors(&truth, &track, Alignment::None).expect("report");
        assert_eq!((r.n, r.skipped), (3, 2));
        assert_eq!((r.p50, r.p75, r.p95, r.max), (1.0, 2.0, 2.0, 2.0));
        assert!((r.mean - 1.0).abs() < 1e-12);
        assert!((r.rmse - (5.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!(r.transform.is_none());
    }

    #[test]
    fn rigid_alignment_removes_a_rotation_and_shift() {
        let truth: Vec<_> = (0..20)
            .map(|i| tp(f64::from(i), f64::from(i), (f64::from(i) * 0.3).sin()))
            .collect();
        let moved = RigidTransform {
            angle: 0.4,
            tx: 3.0,
            ty: -1.0,
        };
        let track: Vec<_> = truth
            .iter()
            .map(|p| {
                let (x, y) = moved.apply((p.x, p.y));
                tp(p.t, x, y)
            })
            .collect();
        let plain = position_errors(&truth, &track, Alignment::None).expect("report");
        assert!(plain.p50 > 1.0);
        let r = position_errors(&truth, &track, Alignment::Rigid).expect("report");
        assert!(r.max < 1e-9, "{r:?}");
        let t = r.transform.expect("transform");
        assert!((t.angle + 0.4).abs() < 1e-9);
        let json = serde_json::to_value(&r).expect("json");
        assert!((json["transform"]["angle"].as_f64().expect("angle") + 0.4).abs() < 1e-9);
    }

    #[test]
    fn refuses_unusable_input() {
        let truth = [tp(0.0, 0.0, 0.0), tp(1.0, 1.0, 0.0)];
        let late = [tp(5.0, 0.0, 0.0)];
        let err = position_errors(&truth, &late, Alignment::None).expect_err("no overlap");
        assert!(
            err.to_string().contains("none of the 1 track points"),
            "{err}"
        );
        assert!(position_errors(&[], &late, Alignment::None).is_err());
        let unordered = [tp(1.0, 0.0, 0.0), tp(0.5, 0.0, 0.0)];
        let err = position_errors(&truth, &unordered, Alignment::None).expect_err("unordered");
        assert!(
            err.to_string()
                .contains("track point 1: at 0.5 s follows 1 s: times must be strictly increasing"),
            "{err}"
        );
        assert!(matches!(err, Error::InvalidData { .. }));
        // A truth that stays in one place fits any track rigidly: refused, not 0 m.
        let still: Vec<_> = (0..10).map(|i| tp(f64::from(i), 1.0, 2.0)).collect();
        let err = position_errors(&still, &still, Alignment::Rigid).expect_err("degenerate");
        assert!(err.to_string().contains("within 0.00 m"), "{err}");
        assert!(position_errors(&still, &still, Alignment::None).is_ok());
    }
}
