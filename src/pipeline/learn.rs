//! FootSLAM on one walk or a batch of walks (Robertson et al. 2009; FeetSLAM for batches),
//! anchored to the world by GPS fixes, a rough building outline and a map learned on earlier
//! walks, as stages:
//!
//! 1. **prior** — the Dirichlet prior `α`, lowered across the outline's edges and raised by
//!    the prior map's counts;
//! 2. **walks** — each walk learned alone, then, for a batch in one frame, FeetSLAM passes
//!    in which each walk is learned again with the others' merged map as its prior;
//! 3. **merge** — each walk with the prior map (the next walk's prior), or the batch's maps
//!    into one;
//! 4. **radio** — with WiFi, every walk's scans placed on its learned path and added to the
//!    cells of the plan learned from everything the run learned (Woodman & Harle 2009's
//!    survey with no drawn plan).

use super::Progress;
use super::learn_config::LearnConfig;
use super::learn_walks::{Shared, learn_batch, learn_walk_at, walk_prior};
use crate::Result;
use crate::filter::{
    EPSILON_MISS, FootSlamEstimate, PathPoint, PathSurvey, RfConfig, path_points, survey_paths,
};
use crate::geometry::{HexGrid, LocalFrame};
use crate::io::map_geojson::StoredMap;
use crate::map::{
    CellConfig, EdgePrior, HexMapSnapshot, LearnedPlan, PlanConfig, merge_maps, shift_map,
    walkable_plan,
};
use crate::sensor::WifiScan;
use geo::Polygon;

pub use super::learn_walks::{LearnWalk, WalkRun, feetslam_passes, others_map};

/// What [`learn`] reads besides the walks.
#[derive(Debug, Clone, Copy)]
pub struct LearnInput<'a> {
    /// The walks: one, or a batch learned in parallel (walk `i` has seed `seed + i`).
    pub walks: &'a [LearnWalk],
    /// The local frame of maps and paths ([`default_frame`] when the user gives none).
    pub frame: LocalFrame,
    /// The building's rough outline in the frame's metres: crossing it becomes improbable.
    pub outline: Option<&'a Polygon<f64>>,
    /// A map learned earlier, on the run's grid: its counts become prior pseudo-counts.
    pub prior_map: Option<&'a StoredMap>,
}

/// What [`learn`] gives.
#[derive(Debug)]
pub struct Learned {
    /// Each walk's run, in the order of the walks (the last FeetSLAM pass).
    pub walks: Vec<WalkRun>,
    /// FeetSLAM passes run after the first (0 for one walk, or walks in frames of their own).
    pub iterations: u32,
    /// Hexagon edges the outline crosses.
    pub outline_edges: usize,
    /// Hexagons and walks of the prior map (0, 0 without one).
    pub prior_map_hexagons: usize,
    /// Walks whose counts the prior map holds.
    pub prior_map_walks: u32,
    /// The merged maps and the radio map.
    pub combined: Combined,
}

/// What [`combine`] makes of the walks' answers.
#[derive(Debug)]
pub struct Combined {
    /// Per walk, with a prior map: the prior moved into the walk's frame merged with the
    /// walk's map (the next walk's prior). Empty without a prior map.
    pub merged_with_prior: Vec<HexMapSnapshot>,
    /// A batch without a prior map: the walks' maps merged.
    pub merged: Option<HexMapSnapshot>,
    /// The radio map of the walks' WiFi (when any walk has scans).
    pub radio: Option<LearnedRadio>,
}

/// The radio map `learn` makes of the walks' WiFi.
#[derive(Debug)]
pub struct LearnedRadio {
    /// The plan learned from the run's map, whose cells hold the scans.
    pub plan: LearnedPlan,
    /// The cells, the map and each walk's scans added and skipped.
    pub survey: PathSurvey,
}

/// The frame of a run without a given origin: the prior map's, else the first GPS fix's,
/// else the default (0, 0).
#[must_use]
pub fn default_frame(prior_map: Option<&StoredMap>, walks: &[LearnWalk]) -> LocalFrame {
    let first_fix = walks.iter().find_map(|w| w.fixes.first());
    prior_map
        .map(|m| m.frame)
        .or(first_fix.and_then(|f| LocalFrame::new(f.lat, f.lon)))
        .unwrap_or_default()
}

/// Learns the walks of `input` with `config` in the stages of the [module](self).
///
/// # Errors
///
/// - [`Error::Config`](crate::Error::Config) when `config` fails [`LearnConfig::validate`].
/// - [`Error::TooLarge`](crate::Error::TooLarge) when a walk's particles would not fit in the
///   memory the machine has available.
/// - [`Error::InvalidData`](crate::Error::InvalidData) when a walk's GPS fixes are not in
///   increasing time order.
/// - As [`combine`]: a prior map on another hexagon radius than the run's, or walks with scans
///   whose learned map is too small to cut radio-map cells from, or whose scans fall in none.
pub fn learn(input: &LearnInput, config: &LearnConfig, progress: &dyn Progress) -> Result<Learned> {
    config.validate()?;
    // 1. prior
    let base = base_prior(input, config);
    // 2. walks
    let shared = base.shared(input, config);
    let (walks, iterations) = learn_batch(input.walks, &shared, progress)?;
    let estimates: Vec<&FootSlamEstimate> = walks.iter().map(|r| &r.estimate).collect();
    let combined = combine(input, &estimates, &config.cells)?;
    Ok(Learned {
        walks,
        iterations,
        outline_edges: base.outline_edges,
        prior_map_hexagons: base.prior_map_hexagons,
        prior_map_walks: base.prior_map_walks,
        combined,
    })
}

/// Stages 3 and 4 of [`learn`] on the walks' answers (one per walk of `input`, in order,
/// from [`learn`]'s stage 2 or from [`learn_one`] tasks after the FeetSLAM passes): the
/// merged maps and the radio map on `cells`.
///
/// # Errors
///
/// - [`Error::Mismatch`](crate::Error::Mismatch) when `estimates` is not one answer per walk, or
///   the prior map's hexagon radius is not the walks' maps'.
/// - As [`learned_radio_map`] when a walk has scans: the run's map too small to cut cells from,
///   `cells` out of range, or no scan in a cell.
pub fn combine(
    input: &LearnInput,
    estimates: &[&FootSlamEstimate],
    cells: &CellConfig,
) -> Result<Combined> {
    if estimates.len() != input.walks.len() {
        return Err(crate::Error::mismatch(
            format!(
                "{} answers for {} walks",
                estimates.len(),
                input.walks.len()
            ),
            "give one answer per walk, in the order of the walks",
        ));
    }
    // 3. merge
    let batch = input.walks.len() > 1;
    let mut merged_with_prior = Vec::new();
    if let Some(stored) = input.prior_map {
        for estimate in estimates {
            let prior = shift_map(&stored.map, estimate.prior_shift);
            merged_with_prior.push(merge_maps(&[(&prior, 1.0), (&estimate.map, 1.0)])?);
        }
    }
    let merged = if batch && input.prior_map.is_none() {
        let maps: Vec<_> = estimates.iter().map(|e| (&e.map, 1.0)).collect();
        Some(merge_maps(&maps)?)
    } else {
        None
    };
    // 4. radio
    let radio = if input.walks.iter().any(|w| !w.scans.is_empty()) {
        // Everything the run learned: the batch's merged map, or the walks' maps with the
        // prior moved into the first's frame.
        let run_map = match &merged {
            Some(m) => m.clone(),
            None => {
                let prior = input
                    .prior_map
                    .zip(estimates.first())
                    .map(|(stored, first)| shift_map(&stored.map, first.prior_shift));
                let mut all: Vec<_> = estimates.iter().map(|e| (&e.map, 1.0)).collect();
                all.extend(prior.as_ref().map(|p| (p, 1.0)));
                merge_maps(&all)?
            }
        };
        Some(radio_map(input.walks, estimates, &run_map, cells)?)
    } else {
        None
    };
    Ok(Combined {
        merged_with_prior,
        merged,
        radio,
    })
}

/// Stage 1's result.
struct BasePrior {
    /// `α`, with the outline and the prior map's counts.
    prior: EdgePrior,
    outline_edges: usize,
    prior_map_hexagons: usize,
    prior_map_walks: u32,
}

impl BasePrior {
    /// What every walk of `input`'s run shares.
    fn shared<'a>(&'a self, input: &'a LearnInput, config: &'a LearnConfig) -> Shared<'a> {
        Shared {
            config,
            frame: &input.frame,
            prior: &self.prior,
            prior_map: input.prior_map.map(|m| &m.map),
            prior_walks: self.prior_map_walks,
        }
    }
}

/// Stage 1: the Dirichlet prior every walk of the run starts from.
fn base_prior(input: &LearnInput, learn: &LearnConfig) -> BasePrior {
    let config = &learn.footslam;
    let grid = HexGrid::new(config.hex_radius);
    let mut prior = EdgePrior::uniform(config.alpha);
    let outline_edges = input
        .outline
        .map_or(0, |o| prior.add_outline(&grid, o, config.outline_alpha));
    let (mut prior_map_hexagons, mut prior_map_walks) = (0, 0);
    if let Some(stored) = input.prior_map {
        prior.add_counts(&stored.map, learn.prior_weight);
        prior_map_hexagons = stored.map.cells.len();
        prior_map_walks = stored.walks;
    }
    BasePrior {
        prior,
        outline_edges,
        prior_map_hexagons,
        prior_map_walks,
    }
}

/// One walk of a batch alone, as one task of a batch spread over threads, processes or
/// machines: `walk`, the batch's walk number `index` (0-based; its seed is `seed + index`),
/// learned in `input`'s frame with its outline and prior map (`input.walks` is not read, so
/// a task needs only its own walk) and, in a FeetSLAM pass, `others` — the merged map of
/// the other walks' previous pass ([`others_map`]) — as prior pseudo-counts. The same
/// computation as that walk's in [`learn`] (its stage 2), so a batch fanned out walk by walk
/// and pass by pass ([`feetslam_passes`]) gives the same maps and paths; [`combine`] then
/// merges them. `steps` hears of the walk's steps (e.g. an [`ItemProgress`] of a shard's
/// bar).
///
/// # Errors
///
/// As that walk in [`learn`]: `config` out of range ([`LearnConfig::validate`]), particles beyond
/// the machine's available memory, or GPS fixes out of time order.
///
/// [`ItemProgress`]: super::ItemProgress
pub fn learn_one(
    input: &LearnInput,
    walk: &LearnWalk,
    index: usize,
    others: Option<&HexMapSnapshot>,
    config: &LearnConfig,
    steps: Option<&dyn Progress>,
) -> Result<WalkRun> {
    config.validate()?;
    let base = base_prior(input, config);
    let shared = base.shared(input, config);
    let prior = walk_prior(&base.prior, others, config.prior_weight);
    learn_walk_at(walk, index, &shared, &prior, steps, None)
}

/// Stage 4: the walks' scans on the plan learned from `map`, each walk's placed by its
/// learned path.
fn radio_map(
    walks: &[LearnWalk],
    estimates: &[&FootSlamEstimate],
    map: &HexMapSnapshot,
    cells: &CellConfig,
) -> Result<LearnedRadio> {
    let level = PlanConfig::default().level;
    let paths: Vec<_> = walks
        .iter()
        .zip(estimates)
        .map(|(walk, estimate)| {
            let path = path_points(walk.trace.steps(), &estimate.path, level);
            (path, walk.scans.as_slice())
        })
        .collect();
    learned_radio_map(&paths, map, cells)
}

/// A radio map with no drawn plan: the walks' scans (`paths`: per walk its `(t, x, y,
/// level)` per step — a learned path — and its scans in time order) added to the cells of
/// the plan learned from `map` (everything the run learned, in the paths' frame), `ε`
/// calibrated on the walks' own scans. [`learn`]'s stage 4, for walks learned apart.
///
/// # Errors
///
/// [`Error::NotEnough`](crate::Error::NotEnough) when no walkable plan can be cut from `map` (too
/// few visits, too small an area) or no scan falls in a cell of it;
/// [`Error::Config`](crate::Error::Config) when `cells` fails
/// [`CellConfig::validate`](crate::map::CellConfig::validate).
pub fn learned_radio_map(
    paths: &[(Vec<PathPoint>, &[WifiScan])],
    map: &HexMapSnapshot,
    cells: &CellConfig,
) -> Result<LearnedRadio> {
    let plan = walkable_plan(map, &PlanConfig::default()).map_err(|e| {
        crate::Error::not_enough(
            format!("the learned map is too small to cut radio-map cells from: {e}"),
            "walk more of the building, or leave out --wifi",
        )
    })?;
    let survey = survey_paths(
        &plan.plan,
        paths,
        cells,
        RfConfig::default().missing_rssi,
        EPSILON_MISS,
    )?;
    Ok(LearnedRadio { plan, survey })
}
