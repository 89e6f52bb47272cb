//! The building's dominant directions as a soft prior on straight walking (heuristic drift
//! elimination, Borenstein, Ojeda & Kwanmuang 2009; inside a particle filter as in
//! Abdulrahim, Hide, Moore & Hill 2011), learned from the walk itself.
//!
//! Most buildings are drawn on a rectangular grid: corridors run along two perpendicular
//! axes, so a walker who goes straight for a while goes along an axis. A heading that drifts
//! turns those stretches off the axes. Each particle therefore learns its own axes from its
//! own straight steps — the resultant of `4φ` over its step directions `φ` (the four axis
//! directions `a + m·π/2` coincide under `φ ↦ 4φ`):
//!
//! `a = ¼ · atan2(Σ ℓ sin 4φ, Σ ℓ cos 4φ)`                                     (1)
//!
//! and weighs each later straight step of length `ℓ` by how close its direction lies to the
//! nearest axis, `δ = φ − a` folded into `[−π/4, π/4)`: a normal about the axis mixed with a
//! uniform share `ε` for straight walking that follows no axis (across a hall, along a
//! slanted wall),
//!
//! `p(δ) = (1 − ε) · N(δ; 0, σ) + ε · 2/π`                                      (2)
//!
//! entered as its ratio to the uniform density (so a particle without axes, or a step far
//! from every axis, is neither rewarded nor punished) and tempered like the compass
//! ([`super::heading_likelihood`], eq. 3): the steps of one stretch share their heading
//! error, so over `L` metres they weigh as one observation,
//!
//! `ln w = min(1, ℓ / L) · ln(p(δ) / (2/π))`.                                 (3)
//!
//! A particle's axes learn only from steps within `inlier_band` of them once they exist, so
//! a diagonal stretch does not pull them round. Particles whose heading drifts off the axes
//! lose weight and the drift the filter keeps is the one that keeps the corridors straight.
//!
//! **When not to apply it** (the floor of MiHDE, Jiménez et al. 2011, without a compass).
//! A building without dominant directions — a round hall, a walk that weaves — would be
//! forced onto axes it does not have. The walk's dead-reckoned steps decide first: find its
//! straight stretches, and for each pair of successive stretches less than `max_turn_gap_s`
//! apart (drift is small over so short a time) that turned by more than 20°, the turn `Δ`.
//! On a rectangular grid the turns are multiples of 90°; elsewhere they are anything. A
//! U-turn counts: walking back along the same line is the commonest way a walk's stretches
//! share their directions (the corridor of a walk that goes there and back is its axis).
//! The prior acts only when
//!
//! `A = mean cos 4Δ ≥ min_alignment`   and   `A · √(2n) ≥ min_significance`       (4)
//!
//! for `n` turns (under turns uniform on the circle `A` has mean 0 and standard deviation
//! `1/√(2n)`, so the second test is a one-sided z-test against "no axes"). Where it fails,
//! the same test on `cos 8Δ` finds buildings whose walls also run at 45° (museums, malls
//! with diagonal halls); the prior then uses eight directions (`8φ` in eq. 1, folds of
//! `π/4`).

use crate::sensor::Step;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, FRAC_PI_8, PI};

/// The smallest change of direction between two stretches that counts as a turn (eq. 4):
/// below it the walker bent, not turned.
const MIN_TURN: f64 = 20.0 * PI / 180.0;

/// Parameters of the axes prior; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AxesConfig {
    /// Use the prior where the walk shows dominant directions (eq. 4). Default false: on
    /// the shared real walks (museum, mall, foot hallways), whose headings drift little,
    /// it changed the answers by a few per cent and more often for the worse
    /// (docs/footslam.md); it is for long walks with drifting gyros in buildings drawn on
    /// a grid. The walk's turns are tested and reported either way.
    pub enabled: bool,
    /// Where the turns show no right-angled axes, test for eight directions (walls also at
    /// 45°, eq. 4 with `cos 8Δ`) and use them. Default true.
    pub diagonals: bool,
    /// `σ` of a straight step's direction about the axis it follows (eq. 2), radians.
    /// Default 5°: people keep to a corridor's line within a few degrees, and a step's
    /// direction wobbles by a few more.
    pub sigma: f64,
    /// `ε`, the share of straight walking that follows no axis (eq. 2). Default 0.3.
    pub outlier_share: f64,
    /// `L`, metres over which a stretch's steps count as one observation (eq. 3).
    /// Default 5 m.
    pub correlation_length: f64,
    /// Half-width of the window of steps (either side) whose dead-reckoned headings must
    /// all lie within `straight_tolerance` for a step to count as straight. Default 3.
    pub straight_window: usize,
    /// The largest spread of dead-reckoned headings within the window of a straight step,
    /// radians. Default 12°.
    pub straight_tolerance: f64,
    /// The shortest straight stretch whose direction enters the turn test (eq. 4), metres.
    /// Default 3 m.
    pub min_stretch_m: f64,
    /// The longest pause between two stretches whose turn enters the test, seconds.
    /// Default 60 s: a phone's or foot IMU's heading drifts by a degree or two a minute.
    pub max_turn_gap_s: f64,
    /// The fewest turns that can show dominant directions. Default 3.
    pub min_turns: usize,
    /// The lowest mean `cos 4Δ` of the turns (eq. 4). Default 0.5.
    pub min_alignment: f64,
    /// The lowest `A·√(2n)` (eq. 4). Default 2 (one-sided 97.7 %).
    pub min_significance: f64,
    /// The resultant of `4φ` (eq. 1), metres, a particle's straight walking must reach
    /// before its axes weigh it. Default 5 m.
    pub min_axis_m: f64,
    /// A particle's axes learn only from straight steps this close to them, radians
    /// (before they exist, from every straight step). Default 15°.
    pub inlier_band: f64,
}

impl Default for AxesConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            diagonals: true,
            sigma: 5.0_f64.to_radians(),
            outlier_share: 0.3,
            correlation_length: 5.0,
            straight_window: 3,
            straight_tolerance: 12.0_f64.to_radians(),
            min_stretch_m: 3.0,
            max_turn_gap_s: 60.0,
            min_turns: 3,
            min_alignment: 0.5,
            min_significance: 2.0,
            min_axis_m: 5.0,
            inlier_band: 15.0_f64.to_radians(),
        }
    }
}

impl AxesConfig {
    /// Checks every field; names the offending one.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) for the first field that is not finite or is out of
    /// its range (e.g. `sigma` outside (0, π/4] radians, `min_alignment` outside [−1, 1],
    /// `straight_window` above 1000 steps), with the range.
    pub fn validate(&self) -> crate::error::Result<()> {
        let fields = [
            (
                "axes.sigma",
                self.sigma,
                1e-4,
                FRAC_PI_4,
                "must be in (0, π/4] radians",
            ),
            (
                "axes.outlier_share",
                self.outlier_share,
                1e-6,
                1.0,
                "must be in (0, 1]",
            ),
            (
                "axes.correlation_length",
                self.correlation_length,
                0.0,
                1e3,
                "must be in [0, 1000] m",
            ),
            (
                "axes.straight_tolerance",
                self.straight_tolerance,
                0.0,
                FRAC_PI_2,
                "must be in [0, π/2] radians",
            ),
            (
                "axes.min_stretch_m",
                self.min_stretch_m,
                0.0,
                1e3,
                "must be in [0, 1000] m",
            ),
            (
                "axes.max_turn_gap_s",
                self.max_turn_gap_s,
                0.0,
                1e5,
                "must be in [0, 100000] s",
            ),
            (
                "axes.min_alignment",
                self.min_alignment,
                -1.0,
                1.0,
                "must be in [-1, 1]",
            ),
            (
                "axes.min_significance",
                self.min_significance,
                -1e3,
                1e3,
                "must be a finite number",
            ),
            (
                "axes.min_axis_m",
                self.min_axis_m,
                0.0,
                1e4,
                "must be in [0, 10000] m",
            ),
            (
                "axes.inlier_band",
                self.inlier_band,
                0.0,
                FRAC_PI_8,
                "must be in [0, π/8] radians",
            ),
        ];
        for (name, v, lo, hi, rule) in fields {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(crate::error::Error::config(name, v, rule));
            }
        }
        if self.straight_window > 1000 {
            return Err(crate::error::Error::config(
                "axes.straight_window",
                self.straight_window,
                "must be at most 1000 steps",
            ));
        }
        Ok(())
    }
}

/// What the walk's dead-reckoned steps say about the building's axes (eq. 4), and which
/// steps are straight.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisEvidence {
    /// Per step of the walk: whether it lies inside a straight stretch.
    straight: Vec<bool>,
    /// Turns between successive straight stretches that entered the test.
    pub turns: usize,
    /// `A`, their mean `cos 4Δ` (0 without turns).
    pub alignment: f64,
    /// Their mean `cos 8Δ` (0 without turns): eq. (4) for a building whose walls also run
    /// at 45° to its axes.
    pub diagonal_alignment: f64,
    /// The building's dominant directions: 4 (two perpendicular axes), 8 (with the
    /// diagonals) or 0 (none found).
    pub directions: u8,
    /// Whether the prior acts (eq. 4 holds and the configuration enables it).
    pub active: bool,
    /// Metres of the walk in straight stretches.
    pub straight_m: f64,
}

impl AxisEvidence {
    /// The evidence of `steps` (one walk, in time order).
    #[must_use]
    pub fn new(steps: &[Step], config: &AxesConfig) -> Self {
        let mut heading = Vec::with_capacity(steps.len());
        let mut h = 0.0;
        for s in steps {
            h += s.dheading;
            heading.push(h);
        }
        let w = config.straight_window;
        let straight: Vec<bool> = (0..steps.len())
            .map(|i| {
                let window = &heading[i.saturating_sub(w)..(i + w + 1).min(steps.len())];
                let (lo, hi) = window
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                        (lo.min(v), hi.max(v))
                    });
                hi - lo <= config.straight_tolerance
            })
            .collect();
        let stretches = stretches(steps, &heading, &straight, config.min_stretch_m);
        let turns: Vec<f64> = stretches
            .windows(2)
            .filter(|p| p[1].t_start - p[0].t_end <= config.max_turn_gap_s)
            .map(|p| crate::geometry::wrap_angle(p[1].heading - p[0].heading))
            .filter(|d| d.abs() >= MIN_TURN)
            .collect();
        let n = turns.len();
        let alignment = if n == 0 {
            0.0
        } else {
            turns.iter().map(|d| (4.0 * d).cos()).sum::<f64>() / n as f64
        };
        let diagonal_alignment = if n == 0 {
            0.0
        } else {
            turns.iter().map(|d| (8.0 * d).cos()).sum::<f64>() / n as f64
        };
        let passes = |a: f64| {
            n >= config.min_turns
                && a >= config.min_alignment
                && a * (2.0 * n as f64).sqrt() >= config.min_significance
        };
        let directions = if passes(alignment) {
            4
        } else if config.diagonals && passes(diagonal_alignment) {
            8
        } else {
            0
        };
        let active = directions > 0 && config.enabled;
        let straight_m = steps
            .iter()
            .zip(&straight)
            .filter(|(_, s)| **s)
            .map(|(s, _)| s.length)
            .sum();
        Self {
            straight,
            turns: n,
            alignment,
            diagonal_alignment,
            directions,
            active,
            straight_m,
        }
    }

    /// Whether eq. (4) holds: the turns show 4 or 8 dominant directions, whether the prior
    /// is enabled or not.
    #[must_use]
    pub fn shows_axes(&self) -> bool {
        self.directions > 0
    }

    /// Whether step `index` (0-based) lies in a straight stretch; false past the walk.
    #[must_use]
    pub fn is_straight(&self, index: usize) -> bool {
        self.straight.get(index).copied().unwrap_or(false)
    }
}

/// One straight stretch: its length-weighted mean dead-reckoned heading and its time span.
struct Stretch {
    heading: f64,
    t_start: f64,
    t_end: f64,
}

/// The maximal runs of straight steps at least `min_m` long.
fn stretches(steps: &[Step], heading: &[f64], straight: &[bool], min_m: f64) -> Vec<Stretch> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < steps.len() {
        if !straight[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i < steps.len() && straight[i] {
            i += 1;
        }
        let run = start..i;
        let length: f64 = steps[run.clone()].iter().map(|s| s.length).sum();
        if length >= min_m && length > 0.0 {
            let weighted: f64 = run.clone().map(|k| steps[k].length * heading[k]).sum();
            out.push(Stretch {
                heading: weighted / length,
                t_start: steps[start].t,
                t_end: steps[i - 1].t,
            });
        }
    }
    out
}

/// Eq. (2)–(3) with their constants, for `m` directions (4, or 8 with the diagonals: then
/// `4φ` becomes `8φ` in eq. 1, the fold's period is `π/4` and the uniform density `4/π`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLikelihood {
    config: AxesConfig,
    /// `m`, the number of directions.
    directions: f64,
    /// `(1 − ε) / (σ √(2π)) / (m/2π)`: the inlier density's peak over the uniform one.
    peak_ratio: f64,
}

impl AxisLikelihood {
    /// The model of a validated configuration for `directions` (4 or 8; anything else is
    /// taken as 4).
    #[must_use]
    pub fn new(config: AxesConfig, directions: u8) -> Self {
        let m = if directions == 8 { 8.0 } else { 4.0 };
        let peak = (1.0 - config.outlier_share) / (config.sigma * (2.0 * PI).sqrt());
        Self {
            config,
            directions: m,
            peak_ratio: peak / (m / (2.0 * PI)),
        }
    }

    /// `ln(p(δ) / (m/2π))` of eq. (2) for `δ` in `[−π/m, π/m)`.
    #[must_use]
    pub fn log_ratio(&self, delta: f64) -> f64 {
        let z = delta / self.config.sigma;
        (self.peak_ratio * (-0.5 * z * z).exp() + self.config.outlier_share).ln()
    }
}

/// One particle's axes: the running resultant of eq. (1), metres. 8 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisState {
    c: f32,
    s: f32,
}

impl AxisState {
    /// The particle's axis angle `a` in `[−π/m, π/m)` for `m` directions once its
    /// resultant reaches `min_axis_m`.
    #[must_use]
    pub fn axis(&self, min_axis_m: f64, directions: f64) -> Option<f64> {
        let (c, s) = (f64::from(self.c), f64::from(self.s));
        (c.hypot(s) >= min_axis_m.max(1e-9)).then(|| s.atan2(c) / directions)
    }

    /// Weighs a straight step from `from` to `to` by eq. (3) against the axes learned so
    /// far, then learns from it (eq. 1). Returns `ln w` (0 before the axes exist).
    pub fn weigh_and_learn(&mut self, model: &AxisLikelihood, dx: f64, dy: f64) -> f64 {
        let length = dx.hypot(dy);
        if length <= 1e-9 {
            return 0.0;
        }
        let phi = dy.atan2(dx);
        let cfg = &model.config;
        let m = model.directions;
        let (log_w, learn) = match self.axis(cfg.min_axis_m, m) {
            Some(a) => {
                let delta = fold(phi - a, 2.0 * PI / m);
                let temper = if cfg.correlation_length > 0.0 {
                    (length / cfg.correlation_length).min(1.0)
                } else {
                    1.0
                };
                (
                    temper * model.log_ratio(delta),
                    delta.abs() <= cfg.inlier_band,
                )
            }
            None => (0.0, true),
        };
        if learn {
            self.c += (length * (m * phi).cos()) as f32;
            self.s += (length * (m * phi).sin()) as f32;
        }
        log_w
    }
}

/// `x` folded into `[−period/2, period/2)`.
fn fold(x: f64, period: f64) -> f64 {
    (x + 0.5 * period).rem_euclid(period) - 0.5 * period
}

#[cfg(test)]
mod tests;
