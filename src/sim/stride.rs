//! Strides along a route: random stride lengths at a jittered step rate, with a small, smooth
//! sideways wander — the gait shared by every simulated walker.

use super::route::Route;
use crate::error::Result;
use geo::Coord;
use rand_pcg::Pcg64Mcg;

/// Correlation of the sideways wander from one step to the next.
const WANDER_CORRELATION: f64 = 0.7;
/// A final stride shorter than this is not taken, metres.
const MIN_FINAL_STRIDE: f64 = 0.25;

/// How a walker strides (from its walk configuration).
#[derive(Debug, Clone, Copy)]
pub(super) struct Gait {
    /// Steps per second.
    pub frequency: f64,
    /// Relative jitter (1σ) of a step's period.
    pub period_jitter: f64,
    /// Mean stride, metres (strides stay within ±50 % of it).
    pub length_mean: f64,
    /// Stride spread (1σ), metres.
    pub length_sigma: f64,
    /// Stationary spread (1σ) of the sideways wander, metres.
    pub wander_sigma: f64,
}

impl Gait {
    /// Checks every field against its documented range (named as in the walk
    /// configurations).
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("walk.step_frequency", self.frequency, 0.2..=5.0, "Hz")?;
        crate::error::check_range("walk.step_period_jitter", self.period_jitter, 0.0..=0.3, "")?;
        crate::error::check_range("walk.step_length_mean", self.length_mean, 0.2..=2.0, "m")?;
        crate::error::check_range("walk.step_length_sigma", self.length_sigma, 0.0..=0.3, "m")?;
        crate::error::check_range("walk.wander_sigma", self.wander_sigma, 0.0..=0.2, "m")?;
        Ok(())
    }
}

/// Where one stride ends.
#[derive(Debug, Clone, Copy)]
pub(super) struct Stride {
    /// Time the stride ends, seconds from the start.
    pub t: f64,
    /// The point on the route.
    pub on_route: Coord<f64>,
    /// That point moved sideways by the wander (the walker's choice when it is walkable).
    pub wandered: Coord<f64>,
}

/// The strides along `route` until it ends, drawing from `rng` (stride, period, wander, in
/// that order each step). `limit` caps a stride that starts or would end at a point where
/// walkers shorten their stride (on stairs a foot-mounted sensor's stride spans two
/// treads); `None` where the gait is free.
pub(super) fn strides<'a>(
    route: &'a Route,
    gait: Gait,
    limit: impl Fn(Coord<f64>) -> Option<f64> + 'a,
    rng: &'a mut Pcg64Mcg,
) -> impl Iterator<Item = Stride> + 'a {
    let total = route.length();
    let (mut s, mut t, mut wander) = (0.0, 0.0, 0.0);
    std::iter::from_fn(move || {
        if total - s < MIN_FINAL_STRIDE {
            return None;
        }
        let mut gauss = || crate::random::gauss(&mut *rng);
        let mean = gait.length_mean;
        let mut stride = (mean + gait.length_sigma * gauss()).clamp(0.5 * mean, 1.5 * mean);
        let cap = [route.at(s).0, route.at((s + stride).min(total)).0]
            .into_iter()
            .filter_map(&limit)
            .fold(f64::INFINITY, f64::min);
        stride = stride.min(cap);
        s = (s + stride).min(total);
        t += (1.0 + gait.period_jitter * gauss()).max(0.5) / gait.frequency;
        let (on_route, direction) = route.at(s);
        let rho = WANDER_CORRELATION;
        wander = rho * wander + (1.0 - rho * rho).sqrt() * gait.wander_sigma * gauss();
        let side = Coord {
            x: -direction.y,
            y: direction.x,
        };
        Some(Stride {
            t,
            on_route,
            wandered: on_route + side * wander,
        })
    })
}
