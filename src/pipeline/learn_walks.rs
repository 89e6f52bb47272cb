//! Learning the walks of [`learn`](super::learn): one walk's FootSLAM run (its start from a
//! given start, GPS fixes or step headings; registered onto a prior map first when it has
//! GPS), and a batch's FeetSLAM passes, each walk learned again on the others' merged maps.

use super::learn_config::LearnConfig;
use super::{ItemProgress, Progress};
use crate::Result;
use crate::filter::StartPose;
use crate::filter::departure::{Departure, Trust};
use crate::filter::gps_start::heading_from_fixes;
use crate::filter::{Anchors, FootSlam, FootSlamConfig, FootSlamEstimate};
use crate::geometry::{Hex, LocalFrame, Pose2};
use crate::map::{EdgePrior, HexMapSnapshot, map_of_path, merge_maps, register_maps};
use crate::model::{
    AxisEvidence, FieldEvidence, GpsObservation, HeadingLikelihood, PlacedScan, ReferenceScans,
    ScanEvidence, ScanPairsUnused, find_levels,
};
use crate::sensor::step::step_at_time;
use crate::sensor::{GpsFix, StepFields, StepTrace, WifiScan};
use rayon::prelude::*;
use std::sync::Arc;
use std::time::Instant;

/// The widest shift searched when registering a walk's map onto a prior map, metres.
const MAX_REGISTRATION: f64 = 25.0;
/// Step headings that set a walk's start heading (the most probable under the heading
/// model, so disturbed ones among them do not pull it).
const START_HEADING_READINGS: usize = 10;

/// One walk to learn.
#[derive(Debug, Clone, Default)]
pub struct LearnWalk {
    /// Its steps.
    pub trace: StepTrace,
    /// Its GPS fixes, in time order on the steps' clock (empty: none).
    pub fixes: Vec<GpsFix>,
    /// Its WiFi scans, in time order (empty: none).
    pub scans: Vec<WifiScan>,
    /// Its known start.
    pub start: Option<StartPose>,
    /// The magnetic field over each of its steps, when recorded (`steps.csv`'s `field`).
    pub field: Option<StepFields>,
}

/// What every walk of a run shares.
pub(super) struct Shared<'a> {
    pub(super) config: &'a LearnConfig,
    pub(super) frame: &'a LocalFrame,
    /// `α` with the outline and the prior map's counts.
    pub(super) prior: &'a EdgePrior,
    pub(super) prior_map: Option<&'a HexMapSnapshot>,
    pub(super) prior_walks: u32,
}

/// FeetSLAM passes after the first for `walks`: `config.iterations` for a batch whose walks
/// share a frame (each starts at a known place), else 0. (Walks placed by GPS alone carry
/// each its own GPS bias: they meet through a prior map's registration instead.)
#[must_use]
pub fn feetslam_passes(walks: &[LearnWalk], config: &LearnConfig) -> u32 {
    let one_frame = walks.iter().all(|w| w.start.is_some());
    if walks.len() > 1 && one_frame {
        config.iterations
    } else {
        0
    }
}

/// The merged map of every map of `maps` but the `i`-th: walk `i`'s prior in a FeetSLAM pass.
///
/// # Errors
///
/// As [`merge_maps`]: [`Error::NotEnough`](crate::Error::NotEnough) when `maps` holds no map but
/// the `i`-th, [`Error::Mismatch`](crate::Error::Mismatch) when the maps' hexagon radii differ.
pub fn others_map(maps: &[&HexMapSnapshot], i: usize) -> Result<HexMapSnapshot> {
    let others: Vec<_> = maps
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != i)
        .map(|(_, m)| (*m, 1.0))
        .collect();
    merge_maps(&others)
}

/// A walk's prior: the run's `base` with, in a FeetSLAM pass, the other walks' merged map
/// as pseudo-counts of weight `prior_weight`.
pub(super) fn walk_prior(
    base: &EdgePrior,
    others: Option<&HexMapSnapshot>,
    prior_weight: f64,
) -> EdgePrior {
    let mut prior = base.clone();
    if let Some(others) = others {
        prior.add_counts(others, prior_weight);
    }
    prior
}

/// Walk `i` of a run, with seed `seed + i` and prior `prior`; `steps` reports its steps.
pub(super) fn learn_walk_at(
    walk: &LearnWalk,
    i: usize,
    shared: &Shared,
    prior: &EdgePrior,
    steps: Option<&dyn Progress>,
    references: Option<Arc<ReferenceScans>>,
) -> Result<WalkRun> {
    let mut config = shared.config.footslam.clone();
    config.seed = config.seed.wrapping_add(i as u64);
    learn_walk(walk, config, shared, prior, steps, references)
}

/// Where a pass placed each of a walk's scans: its answer's position and level at the
/// scan's time less the walk's calibrated latency (interpolated within the step; before the
/// first step, the start).
pub fn placed_scans(walk: &LearnWalk, run: &WalkRun) -> Vec<(f64, f64, i32)> {
    let latency = match &run.wifi {
        Some(Ok(e)) => e.latency_s,
        _ => 0.0,
    };
    let steps = walk.trace.steps();
    let path = &run.estimate.path;
    let levels = &run.estimate.levels;
    let start = (
        run.config.start.x,
        run.config.start.y,
        run.config.start_level,
    );
    walk.scans
        .iter()
        .map(|scan| {
            let (k, along) = step_at_time(steps, scan.t - latency);
            let before = k
                .checked_sub(1)
                .map_or(start, |j| (path[j].x, path[j].y, levels[j]));
            if k == steps.len() {
                return before;
            }
            (
                before.0 + along * (path[k].x - before.0),
                before.1 + along * (path[k].y - before.1),
                if along < 0.5 { before.2 } else { levels[k] },
            )
        })
        .collect()
}

/// For each walk of a pass, its scans against the other walks' scans where `runs` placed
/// them ([`ReferenceScans`]); `None` for a walk without scans, or whose pairs do not
/// calibrate.
pub(super) fn cross_walk_references(
    walks: &[LearnWalk],
    runs: &[WalkRun],
    config: &FootSlamConfig,
) -> Vec<Option<Arc<ReferenceScans>>> {
    if !config.wifi.enabled || !config.wifi.cross_walk {
        return vec![None; walks.len()];
    }
    let places: Vec<Vec<(f64, f64, i32)>> = walks
        .iter()
        .zip(runs)
        .map(|(w, r)| placed_scans(w, r))
        .collect();
    (0..walks.len())
        .into_par_iter()
        .map(|i| {
            let usable = matches!(runs[i].wifi, Some(Ok(_)));
            if !usable {
                return None;
            }
            let others: Vec<PlacedScan> = (0..walks.len())
                .filter(|&j| j != i)
                .flat_map(|j| {
                    walks[j]
                        .scans
                        .iter()
                        .zip(&places[j])
                        .map(|(scan, &(x, y, level))| PlacedScan { scan, x, y, level })
                })
                .collect();
            ReferenceScans::new(&walks[i].scans, &places[i], &others, &config.wifi).map(Arc::new)
        })
        .collect()
}

/// Learns the walks, each with seed `seed + i`: alone, then — for a batch in one frame —
/// [`feetslam_passes`] passes in which each walk is learned again with the merged map of the
/// other walks' previous pass as prior pseudo-counts (weight `prior_weight`). Each pass
/// reads only the pass before, so the result does not depend on the order in which walks
/// finish or on the thread count. Returns the last pass and the passes run.
pub(super) fn learn_batch(
    walks: &[LearnWalk],
    shared: &Shared,
    progress: &dyn Progress,
) -> Result<(Vec<WalkRun>, u32)> {
    let batch = walks.len() > 1;
    let iterations = feetslam_passes(walks, shared.config);
    // A batch: the walks (of every pass) in total, and each walk's steps beside it.
    let bar = batch;
    if bar {
        let passes = u64::from(iterations) + 1;
        progress.start("learning walks", passes * walks.len() as u64);
    }
    let pass = |priors: Option<&[EdgePrior]>, references: &[Option<Arc<ReferenceScans>>]| {
        walks
            .par_iter()
            .enumerate()
            .map(|(i, walk)| {
                let prior = priors.map_or(shared.prior, |p| &p[i]);
                let item = ItemProgress {
                    inner: progress,
                    item: i,
                    label: format!("walk {}", i + 1),
                };
                let steps: &dyn Progress = if batch { &item } else { progress };
                let refs = references.get(i).cloned().flatten();
                let run = learn_walk_at(walk, i, shared, prior, Some(steps), refs);
                if bar {
                    progress.advance(1);
                }
                run
            })
            .collect::<Result<Vec<_>>>()
    };
    let mut runs = pass(None, &[])?;
    for _ in 0..iterations {
        let maps: Vec<&HexMapSnapshot> = runs.iter().map(|r| &r.estimate.map).collect();
        let priors = (0..runs.len())
            .map(|i| {
                let others = others_map(&maps, i)?;
                Ok(walk_prior(
                    shared.prior,
                    Some(&others),
                    shared.config.prior_weight,
                ))
            })
            .collect::<Result<Vec<_>>>()?;
        let references = cross_walk_references(walks, &runs, &shared.config.footslam);
        runs = pass(Some(&priors), &references)?;
    }
    if bar {
        progress.finish();
    }
    Ok((runs, iterations))
}

/// The result of learning one walk.
#[derive(Debug)]
pub struct WalkRun {
    /// The configuration it ran with (its seed, and its start from a given start, GPS
    /// fixes or step headings).
    pub config: FootSlamConfig,
    /// Where the start heading came from: `given`, `gps fixes`, `compass`, `config`,
    /// `assumed` or `unknown`.
    pub start_source: &'static str,
    /// The filter after the last step.
    pub filter: FootSlam,
    /// Its most probable map and path.
    pub estimate: FootSlamEstimate,
    /// Seconds spent in the filter.
    pub runtime_s: f64,
    /// The walk's steps dead-reckoned from its start, one pose per step.
    pub dead_reckoned: Vec<Pose2>,
    /// The learned path against `dead_reckoned`; when it answers with
    /// [`Trust::DeadReckoning`], `estimate` holds the dead-reckoned path and its map.
    pub departure: Departure,
    /// With scans: the WiFi evidence the filter weighed, or why it weighed none.
    pub wifi: Option<std::result::Result<Arc<ScanEvidence>, ScanPairsUnused>>,
    /// What the walk's dead-reckoned turns say of the building's axes; the filter weighed
    /// its straight steps by them when `axes.active`.
    pub axes: Arc<AxisEvidence>,
    /// In a FeetSLAM pass: the other walks' scans this walk's scans were weighed against.
    pub wifi_references: Option<Arc<ReferenceScans>>,
    /// With field readings: their calibration, and whether the filter weighed them.
    pub field: Option<Arc<FieldEvidence>>,
}

/// Learns one walk: with GPS it starts at the first fix (spread by its accuracy), heading
/// from the first fixes ([`heading_from_fixes`]) or, when they do not tell, unknown
/// (uniform) — unless the configuration gives a heading spread. Steps with absolute
/// headings set the start heading instead (the heading before the first step that best
/// explains the first readings, [`HeadingLikelihood::start_heading`]), so the learned map
/// keeps its orientation (x east, y north).
fn learn_walk(
    walk: &LearnWalk,
    mut config: FootSlamConfig,
    shared: &Shared,
    prior: &EdgePrior,
    progress: Option<&dyn Progress>,
    references: Option<Arc<ReferenceScans>>,
) -> Result<WalkRun> {
    let (frame, prior_map, prior_walks) = (shared.frame, shared.prior_map, shared.prior_walks);
    let gps: Vec<GpsObservation> = walk
        .fixes
        .iter()
        .map(|f| GpsObservation::from_fix(f, frame))
        .collect();
    let mut heading_given = config.start_heading_sigma != 0.0;
    let mut start_source = match config.start_heading_sigma {
        s if s >= std::f64::consts::PI => "unknown",
        s if s != 0.0 => "config",
        _ => "assumed",
    };
    // A given start (`--start`, a manifest's) places the walk; its heading, when given,
    // is known; without one it is unknown unless GPS fixes or step headings tell.
    if let Some(start) = walk.start {
        config.start.x = start.x;
        config.start.y = start.y;
        if let Some(level) = start.level {
            config.start_level = level;
        }
        if let Some(heading) = start.heading {
            config.start.heading = heading;
            heading_given = true;
            start_source = "given";
        } else if !heading_given {
            config.start_heading_sigma = std::f64::consts::PI;
            start_source = "unknown";
        }
    }
    if let Some(first) = gps.first() {
        if walk.start.is_none() {
            config.start.x = first.x;
            config.start.y = first.y;
            config.start_position_sigma = config.start_position_sigma.max(first.sigma);
        }
        if !heading_given {
            match heading_from_fixes(&gps, walk.trace.steps()) {
                Some((heading, sigma)) => {
                    config.start.heading = heading;
                    config.start_heading_sigma = sigma;
                    start_source = "gps fixes";
                }
                None => {
                    config.start_heading_sigma = std::f64::consts::PI;
                    start_source = "unknown";
                }
            }
        }
    }
    let compass = HeadingLikelihood::new(config.heading);
    if !heading_given
        && compass.enabled()
        && let Some((heading, sigma)) =
            compass.start_heading(walk.trace.steps(), START_HEADING_READINGS)
    {
        config.start.heading = heading;
        config.start_heading_sigma = sigma;
        start_source = "compass";
    }
    let started = Instant::now();
    // The walk's floors from its height changes, known before the first step so that a
    // stair climbed the first time already splits at half height.
    let levels = find_levels(walk.trace.steps(), config.levels, config.start_level)?;
    // The walk's scans against one another, calibrated on the walk itself.
    let wifi = (!walk.scans.is_empty())
        .then(|| ScanEvidence::new(&walk.scans, walk.trace.steps(), &config.wifi).map(Arc::new));
    let wifi_evidence = wifi.as_ref().and_then(|w| w.as_ref().ok()).cloned();
    // Which steps are straight, and whether the walk's turns show dominant directions.
    let axes = Arc::new(AxisEvidence::new(walk.trace.steps(), &config.axes));
    // The magnetic field against each particle's field map, calibrated on the walk itself.
    let field = walk
        .field
        .as_ref()
        .map(|f| Arc::new(FieldEvidence::new(&config.field, walk.trace.steps(), f)));
    // With GPS and a prior map: first learn the walk alone, in its own GPS frame, and
    // register its map onto the prior to find where the two frames meet.
    let mut prior_offset = Hex::ZERO;
    if let (Some(map), false) = (prior_map, gps.is_empty()) {
        let alone = Anchors {
            gps: gps.clone(),
            levels: levels.clone(),
            wifi: wifi_evidence.clone(),
            axes: Some(Arc::clone(&axes)),
            field: field.clone(),
            ..Default::default()
        };
        let mut first = FootSlam::with_anchors(config.clone(), alone)?;
        for step in walk.trace.steps() {
            first.update(step);
        }
        let n = f64::from(prior_walks.max(1));
        let reach = (3.0 * config.gps.bias_sigma * (1.0 + 1.0 / n).sqrt()).min(MAX_REGISTRATION);
        prior_offset = register_maps(&first.estimate().map, map, reach).0;
    }
    let anchors = Anchors {
        gps,
        prior: Some(prior.clone()),
        prior_walks,
        prior_offset,
        levels,
        wifi: wifi_evidence,
        wifi_references: references.clone(),
        axes: Some(Arc::clone(&axes)),
        field: field.clone(),
    };
    let mut filter = FootSlam::with_anchors(config.clone(), anchors)?;
    if let Some(p) = progress {
        p.start("learning", walk.trace.len() as u64);
    }
    for step in walk.trace.steps() {
        filter.update(step);
        if let Some(p) = progress {
            p.advance(1);
        }
    }
    if let Some(p) = progress {
        p.finish();
    }
    let runtime_s = started.elapsed().as_secs_f64();
    let wifi_references = references.filter(|_| filter.scans_cross_walk());
    let mut estimate = filter.estimate();
    let dead_reckoned = walk.trace.dead_reckon(config.start);
    let departure = check_departure(
        walk,
        &config,
        &filter,
        &dead_reckoned,
        &mut estimate,
        !prior.is_empty(),
    );
    Ok(WalkRun {
        config,
        start_source,
        filter,
        estimate,
        runtime_s,
        dead_reckoned,
        departure,
        wifi,
        axes,
        wifi_references,
        field,
    })
}

/// The learned path against `dead_reckoned`, the walk's steps from the same start
/// ([`Departure::check`]); when the run is to answer with dead reckoning, `estimate`
/// becomes the dead-reckoned path and its map.
fn check_departure(
    walk: &LearnWalk,
    config: &FootSlamConfig,
    filter: &FootSlam,
    dead_reckoned: &[Pose2],
    estimate: &mut FootSlamEstimate,
    prior_map: bool,
) -> Departure {
    let evidence = [
        (filter.scans_used() > 0, "wifi"),
        (filter.headings_used() > 0, "compass"),
        (filter.gps_fixes_used() > 0, "gps"),
        (filter.field_steps() > 0, "magnetic field"),
        (filter.axis_steps() > 0, "building axes"),
        (prior_map, "prior map or outline"),
    ];
    let evidence = evidence.iter().filter(|e| e.0).map(|e| e.1).collect();
    let departure = Departure::check(
        walk.trace.steps(),
        &estimate.path,
        dead_reckoned,
        evidence,
        &config.departure,
    );
    if departure.answer == Trust::DeadReckoning {
        let levels = std::mem::take(&mut estimate.map.levels);
        estimate.map = map_of_path(
            config.start,
            dead_reckoned,
            &estimate.levels,
            config.hex_radius,
            config.alpha,
        );
        estimate.map.levels = levels;
        estimate.path = dead_reckoned.to_vec();
        // The learned field map belongs to the learned path, not to this one.
        estimate.field_map = None;
        estimate.spread_m = vec![0.0; dead_reckoned.len()];
    }
    departure
}
