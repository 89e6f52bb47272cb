//! The walk's start from its first GPS fixes: position at the first fix, heading from how
//! the first metres of dead reckoning must be turned to follow the fixes.
//!
//! The fixes share a slowly varying bias, so their differences are far more accurate than
//! the fixes themselves: the heading offset `θ` that turns the dead-reckoned displacements
//! `dᵢ` (from the walk's start, heading 0) onto the fixes' displacements `gᵢ` (from the
//! first fix) is the least-squares rotation `θ = atan2(Σ dᵢ × gᵢ, Σ dᵢ · gᵢ)`, over the
//! fixes until the walker is `HEADING_BASELINE` metres from the start. Its spread is the
//! angle a fix's accuracy subtends at that distance, `σ_θ = 2σ / |d|` (at least 3°): loose
//! on purpose, since drift and a turning walker bend the first metres.

use crate::geometry::Pose2;
use crate::model::GpsObservation;
use crate::sensor::Step;

/// Dead-reckoned distance from the start over which the heading is fitted, metres.
pub const HEADING_BASELINE: f64 = 25.0;
/// The shortest baseline that gives a heading, metres.
const MIN_BASELINE: f64 = 10.0;
/// The smallest heading spread returned, radians (3°).
const MIN_HEADING_SIGMA: f64 = 0.052_359_877_6;

/// `(θ, σ_θ)`: the start heading (radians from east) and its spread, or `None` when the
/// fixes before the walker is `MIN_BASELINE` (10 m) from the start are too few (fewer than
/// three) or the walker never gets that far while fixes come in.
#[must_use]
pub fn heading_from_fixes(fixes: &[GpsObservation], steps: &[Step]) -> Option<(f64, f64)> {
    let first = fixes.first()?;
    // Dead reckoning from (0, 0) heading 0, with the time of each step's end.
    let mut pose = Pose2::default();
    let mut track = vec![(first.t.min(steps.first()?.t), pose)];
    for s in steps {
        pose = pose.step(s.length, s.dheading);
        track.push((s.t, pose));
        if pose.x.hypot(pose.y) > HEADING_BASELINE {
            break;
        }
    }
    let at = |t: f64| -> Option<(f64, f64)> {
        let i = track.partition_point(|(tt, _)| *tt < t);
        let (t1, p1) = *track.get(i)?;
        let (t0, p0) = if i == 0 { (t1, p1) } else { track[i - 1] };
        let u = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        Some((p0.x + u * (p1.x - p0.x), p0.y + u * (p1.y - p0.y)))
    };
    let origin = at(first.t)?;
    let (mut cross, mut dot, mut n, mut reach, mut sigma) = (0.0, 0.0, 0, 0.0_f64, 0.0_f64);
    for f in fixes {
        let Some((x, y)) = at(f.t) else { break };
        let d = (x - origin.0, y - origin.1);
        let g = (f.x - first.x, f.y - first.y);
        // Skip fixes far off the dead-reckoned distance (outliers).
        let (dl, gl) = (d.0.hypot(d.1), g.0.hypot(g.1));
        if (gl - dl).abs() > 3.0 * f.sigma + 0.3 * dl {
            continue;
        }
        cross += d.0 * g.1 - d.1 * g.0;
        dot += d.0 * g.0 + d.1 * g.1;
        n += 1;
        reach = reach.max(dl);
        sigma = sigma.max(f.sigma);
    }
    if n < 3 || reach < MIN_BASELINE {
        return None;
    }
    let theta = cross.atan2(dot);
    Some((theta, (2.0 * sigma / reach).max(MIN_HEADING_SIGMA)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_the_heading_of_a_walk_with_a_turn() {
        // Walk 20 steps, turn left 90°, 20 more; the true start heading is 30°.
        let heading = 30f64.to_radians();
        let mut steps = Vec::new();
        for i in 0..40 {
            steps.push(Step {
                t: 0.5 * f64::from(i + 1),
                length: 0.7,
                dheading: if i == 20 {
                    std::f64::consts::FRAC_PI_2
                } else {
                    0.0
                },
                dz: 0.0,
                heading: None,
            });
        }
        let truth = {
            let mut p = Pose2::new(5.0, -3.0, heading);
            let mut out = vec![(0.0, p)];
            for s in &steps {
                p = p.step(s.length, s.dheading);
                out.push((s.t, p));
            }
            out
        };
        // One fix a second with a 4 m bias and a few decimetres of noise.
        let fixes: Vec<GpsObservation> = (0..20)
            .map(|k| {
                let (_, p) = truth[2 * k];
                let wobble = 0.3 * ((k * 7) as f64).sin();
                GpsObservation {
                    t: k as f64,
                    x: p.x + 4.0 + wobble,
                    y: p.y - 1.0 - wobble,
                    sigma: 3.0,
                }
            })
            .collect();
        let (theta, sigma) = heading_from_fixes(&fixes, &steps).expect("heading");
        assert!(
            (theta - heading).abs() < 2f64.to_radians(),
            "{}",
            theta.to_degrees()
        );
        assert!((MIN_HEADING_SIGMA..0.4).contains(&sigma), "{sigma}");
        // Too few fixes, or standing still: no heading.
        assert!(heading_from_fixes(&fixes[..2], &steps).is_none());
        assert!(heading_from_fixes(&fixes, &steps[..5]).is_none());
    }
}
