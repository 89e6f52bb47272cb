//! Placing a learned walk against a rough building outline: the most probable shift of the
//! whole path given the GPS bias it may carry and the outline it should rarely cross.
//!
//! Inside the filter the outline is a low Dirichlet prior on the edges that cross it
//! ([`crate::map::edge_prior`]); that steers the shape, but GPS fixes counted as independent
//! pin the path's absolute position far more firmly than a few improbable crossings can
//! move it, although their common bias (metres, slowly varying) moves every fix alike. So,
//! once the path is learned, its absolute place is re-estimated: the path is shifted by
//! `s`, where `s` maximises
//!
//! `ln N(s; 0, σ²I) − c · (crossings of the outline by path + s)`
//!
//! with `σ` the bias spread left after the walks averaged into the frame and
//! `c = ln(α / α_out)`, eq. (6)'s price of an unseen crossing of an outline edge. Because
//! the outline is known only to `margin` metres, a crossing counts only when the path goes
//! from more than `margin` inside to more than `margin` outside, or back (hysteresis): the
//! true path, which enters and leaves through doors, crosses exactly as often as it enters
//! and leaves, wherever within the margin the true walls are, while a path pushed through a
//! wall by a bias adds a crossing pair at every room or corridor that pokes out.
//!
//! Crossings alone cannot tell a path pushed *wholly* outside: a walk that arrives under
//! GPS and then stays in (GPS sees only the entrance) crosses once where it truly enters,
//! and not at all when shifted past the building. What tells is the receiver: it gives a
//! fix a second under open sky, so a stretch of steps with no fix for `OUTAGE` seconds
//! (from the fix before to the fix after) was walked indoors. Time spent by such unseen
//! steps deeper than `margin` outside the outline therefore counts as one crossing pair —
//! out and back in again without GPS seeing it — per `OUTAGE` seconds, so that a path
//! pushed wholly past the building pays for every minute it spends there. The maximum is
//! searched on a square grid of shifts 0.25 m apart within `±3σ` (at most ±10 m); ties go
//! to the smaller shift.

use geo::{Contains, Coord, Polygon};
use rayon::prelude::*;

/// Spacing of the shifts tried, metres.
const SHIFT_STEP: f64 = 0.25;
/// The widest shift tried, metres.
const MAX_SHIFT: f64 = 10.0;
/// A gap between GPS fixes longer than this, seconds, means the walker was indoors (a
/// receiver under open sky gives a fix a second; ten missed in a row is a roof).
pub const OUTAGE: f64 = 10.0;

/// Whether time `t` falls in a GPS outage: a gap longer than [`OUTAGE`] between the fix
/// before it and the fix after it (`fix_times` sorted; before the first fix and after the
/// last the gap is open-ended, so it counts once the nearest fix is more than `OUTAGE`
/// away). Without fixes there is no outage.
#[must_use]
pub fn in_outage(fix_times: &[f64], t: f64) -> bool {
    let i = fix_times.partition_point(|&f| f <= t);
    let before = i.checked_sub(1).map(|j| fix_times[j]);
    let after = fix_times.get(i).copied();
    match (before, after) {
        (Some(b), Some(a)) => a - b > OUTAGE,
        (Some(b), None) => t - b > OUTAGE,
        (None, Some(a)) => a - t > OUTAGE,
        (None, None) => false,
    }
}

/// For each time in `times` (in order): the seconds since the time before it (0 for the
/// first) when it falls in a GPS outage ([`in_outage`]), and 0 otherwise.
#[must_use]
pub fn unseen_seconds(times: &[f64], fix_times: &[f64]) -> Vec<f64> {
    times
        .iter()
        .enumerate()
        .map(|(k, &t)| match k.checked_sub(1) {
            Some(j) if in_outage(fix_times, t) => (t - times[j]).max(0.0),
            _ => 0.0,
        })
        .collect()
}

/// An outline known to `margin` metres: which side of it a point lies on, with the
/// margin as no man's land.
#[derive(Debug, Clone)]
pub struct OutlineZone {
    outline: Polygon<f64>,
    ring: Vec<(f64, f64)>,
    margin: f64,
}

impl OutlineZone {
    /// The zone of `outline` known to `margin` metres.
    #[must_use]
    pub fn new(outline: &Polygon<f64>, margin: f64) -> Self {
        Self {
            outline: outline.clone(),
            ring: outline.exterior().coords().map(|c| (c.x, c.y)).collect(),
            margin,
        }
    }

    /// True when `(x, y)` lies more than the margin outside the outline.
    #[must_use]
    pub fn is_far_outside(&self, x: f64, y: f64) -> bool {
        self.side((x, y)) == -1
    }

    /// +1 deeper than the margin inside, −1 deeper than the margin outside, 0 in between.
    fn side(&self, p: (f64, f64)) -> i8 {
        let d = self
            .ring
            .windows(2)
            .map(|w| segment_distance(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min);
        if d <= self.margin {
            0
        } else if self.outline.contains(&Coord { x: p.0, y: p.1 }) {
            1
        } else {
            -1
        }
    }
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let u = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - u * dx).hypot(p.1 - a.1 - u * dy)
}

/// Crossings of the outline `zone` by `path` moved by `s`, with the zone's margin as
/// hysteresis, plus a pair for every [`OUTAGE`] seconds that points GPS did not see
/// (`unseen`, seconds a point, [`unseen_seconds`]; missing entries count as seen) spend
/// deeper than the margin outside.
fn crossings(path: &[(f64, f64)], unseen: &[f64], zone: &OutlineZone, s: (f64, f64)) -> f64 {
    let mut last = 0i8;
    let mut n = 0u32;
    let mut outside = 0.0;
    for (i, &(x, y)) in path.iter().enumerate() {
        let now = zone.side((x + s.0, y + s.1));
        if now != 0 {
            if last != 0 && now != last {
                n += 1;
            }
            last = now;
        }
        if now == -1 {
            outside += unseen.get(i).copied().unwrap_or(0.0);
        }
    }
    f64::from(n) + 2.0 * outside / OUTAGE
}

/// The most probable shift of `path` (positions in walking order, with `unseen` the
/// seconds each was walked in a GPS outage, [`unseen_seconds`]) given the outline `zone`,
/// the cost `cost` of a crossing and a Gaussian bias prior of spread `sigma` per axis;
/// `(0, 0)` when `sigma` is 0 or the path is too short.
#[must_use]
pub fn fit_outline_shift(
    path: &[(f64, f64)],
    unseen: &[f64],
    zone: &OutlineZone,
    cost: f64,
    sigma: f64,
) -> (f64, f64) {
    if sigma.is_nan() || sigma <= 0.0 || path.len() < 2 {
        return (0.0, 0.0);
    }
    let reach = (3.0 * sigma).min(MAX_SHIFT);
    let k = (reach / SHIFT_STEP).floor() as i32;
    let shifts: Vec<(f64, f64)> = (-k..=k)
        .flat_map(|i| (-k..=k).map(move |j| (f64::from(i) * SHIFT_STEP, f64::from(j) * SHIFT_STEP)))
        .collect();
    let scores: Vec<f64> = shifts
        .par_iter()
        .map(|&s| {
            let n = crossings(path, unseen, zone, s);
            -cost * n - (s.0 * s.0 + s.1 * s.1) / (2.0 * sigma * sigma)
        })
        .collect();
    // The first maximum in a fixed order (by score, then by the smaller shift).
    let mut best = (f64::NEG_INFINITY, f64::INFINITY, (0.0, 0.0));
    for (&s, &v) in shifts.iter().zip(&scores) {
        let r = s.0 * s.0 + s.1 * s.1;
        if v > best.0 + 1e-12 || ((v - best.0).abs() <= 1e-12 && r < best.1) {
            best = (v, r, s);
        }
    }
    best.2
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Rect;

    fn walk() -> Vec<(f64, f64)> {
        walk_through(true)
    }

    /// From the yard through a door at (10, -2), laps of a loop 2–3 m inside the walls of
    /// a 24 m × 24 m building, and (`out`) out again.
    fn walk_through(out: bool) -> Vec<(f64, f64)> {
        let mut corners: Vec<(f64, f64)> = vec![(10.0, -8.0), (10.0, 1.0)];
        for _ in 0..3 {
            corners.extend([
                (19.0, 1.0),
                (19.0, 19.0),
                (1.0, 19.0),
                (1.0, 1.0),
                (10.0, 1.0),
            ]);
        }
        if out {
            corners.push((10.0, -8.0));
        }
        let corners = corners;
        // A point every half metre.
        let mut path = Vec::new();
        for w in corners.windows(2) {
            let n = ((w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) / 0.5).ceil() as usize;
            for i in 0..n {
                let u = i as f64 / n as f64;
                path.push((
                    w[0].0 + u * (w[1].0 - w[0].0),
                    w[0].1 + u * (w[1].1 - w[0].1),
                ));
            }
        }
        path
    }

    #[test]
    fn a_path_pushed_through_a_wall_is_pulled_back_inside() {
        let outline = Rect::new((-2.0, -2.0), (22.0, 22.0)).to_polygon();
        let zone = OutlineZone::new(&outline, 0.5);
        let cost = (0.8f64 / 0.05).ln();
        let path = walk();
        assert_eq!(crossings(&path, &[], &zone, (0.0, 0.0)), 2.0);
        // Seen 5 m too far south-east (a GPS bias): pulled back to within the margin.
        let biased: Vec<(f64, f64)> = path.iter().map(|&(x, y)| (x + 5.0, y - 5.0)).collect();
        assert_eq!(crossings(&biased, &[], &zone, (0.0, 0.0)), 6.0);
        let (sx, sy) = fit_outline_shift(&biased, &[], &zone, cost, 3.0);
        assert!((-6.0..=-1.5).contains(&sx), "{sx}");
        assert!((1.5..=6.0).contains(&sy), "{sy}");
        assert_eq!(crossings(&biased, &[], &zone, (sx, sy)), 2.0);
        // The true path needs no shift.
        assert_eq!(fit_outline_shift(&path, &[], &zone, cost, 3.0), (0.0, 0.0));
        // An outline off by a metre (within the margin) does not move the true path.
        let off = Rect::new((-2.0, -1.0), (23.0, 22.0)).to_polygon();
        assert_eq!(
            fit_outline_shift(&path, &[], &OutlineZone::new(&off, 1.5), cost, 3.0),
            (0.0, 0.0)
        );
    }

    #[test]
    fn a_walk_that_stays_in_is_not_pushed_past_the_building() {
        let outline = Rect::new((-2.0, -2.0), (22.0, 22.0)).to_polygon();
        let zone = OutlineZone::new(&outline, 0.5);
        let cost = (0.8f64 / 0.05).ln();
        // GPS sees the walker until the door, then never again: a fix a second to y = −2.
        let path = walk_through(false);
        let times: Vec<f64> = (0..path.len()).map(|i| i as f64 * 0.5).collect();
        let fixes: Vec<f64> = times
            .iter()
            .zip(&path)
            .filter(|(_, p)| p.1 < -2.0)
            .map(|(&t, _)| t)
            .step_by(2)
            .collect();
        let unseen = unseen_seconds(&times, &fixes);
        assert!(unseen[1] == 0.0 && unseen[path.len() - 1] == 0.5);
        // Seen 9 m too far north (a GPS bias at the entrance).
        let biased: Vec<(f64, f64)> = path.iter().map(|&(x, y)| (x, y + 9.0)).collect();
        // The true place: one crossing (in through the door), nothing outside unseen.
        assert_eq!(crossings(&path, &unseen, &zone, (0.0, 0.0)), 1.0);
        let (sx, sy) = fit_outline_shift(&biased, &unseen, &zone, cost, 4.0);
        assert!(sx.abs() <= 1.5, "{sx}");
        // Back inside: the loop runs 2–3 m inside the walls, so any shift that puts it
        // within the outline (and its margin) explains the walk; the prior takes the least.
        assert!((-10.5..=-5.0).contains(&sy), "{sy}");
        assert_eq!(crossings(&biased, &unseen, &zone, (sx, sy)), 1.0);
        // Seen 14 m too far north, beyond the ±10 m searched: without knowing where GPS
        // was blind, moving further past the building looks best; knowing, it comes back.
        let far: Vec<(f64, f64)> = path.iter().map(|&(x, y)| (x, y + 14.0)).collect();
        let blind = fit_outline_shift(&far, &[], &zone, cost, 4.0);
        let (_, sy) = fit_outline_shift(&far, &unseen, &zone, cost, 4.0);
        assert!(blind.1 >= 0.0, "{blind:?}");
        assert!(sy <= -8.0, "{sy}");
        // The true path stays where it is.
        assert_eq!(
            fit_outline_shift(&path, &unseen, &zone, cost, 4.0),
            (0.0, 0.0)
        );
    }

    #[test]
    fn outages_are_the_long_gaps_between_fixes() {
        let fixes = [0.0, 1.0, 2.0, 20.0, 21.0];
        let times = [-15.0, -5.0, 1.5, 5.0, 18.0, 21.5, 30.0, 40.0];
        assert_eq!(
            unseen_seconds(&times, &fixes),
            [0.0, 0.0, 0.0, 3.5, 13.0, 0.0, 0.0, 10.0]
        );
        assert_eq!(unseen_seconds(&times, &[]), [0.0; 8]);
        let zone = OutlineZone::new(&Rect::new((0.0, 0.0), (10.0, 10.0)).to_polygon(), 1.0);
        assert!(zone.is_far_outside(-1.5, 5.0) && zone.is_far_outside(5.0, 12.0));
        assert!(!zone.is_far_outside(-0.5, 5.0) && !zone.is_far_outside(5.0, 5.0));
    }
}
