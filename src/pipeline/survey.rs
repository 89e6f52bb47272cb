//! A WiFi radio survey from ordinary walks on a known floor plan (Woodman & Harle 2009), as
//! stages:
//!
//! 1. **track** — each walk tracked on the plan (walk `k` with seed `seed + k`, from its own
//!    start when known); its steps placed by the whole-walk answer;
//! 2. **cells** — the plan cut into rooms and cells of the configured granularity, each
//!    walk's scans assigned to the cell of the step at or after them and counted into
//!    per-cell RSSI histograms;
//! 3. **merge** — radio maps surveyed before on the same plan added in (counts are sums);
//! 4. **calibrate** — the region threshold ε from the walks' own held-out scans;
//! 5. **coverage** — the same walks at 1 to 5 m cells (the paper's Table 1).

use super::Progress;
use super::quality::{Quality, QualityConfig, TrackEvidence, Verdict, track_quality};
use super::track_records::StepRecords;
use crate::filter::{
    Assignments, EPSILON_MISS, StartPose, TrackStep, Tracker, TrackerConfig, calibrate_map,
    placed_steps, survey_assignments, survey_walk,
};
use crate::map::{CellConfig, CellMap, FloorPlan, FloorTopology, RadioMap};
use crate::model::wifi_distance::HeldOut;
use crate::sensor::{StepTrace, WifiScan};
use crate::{Error, Result};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Granularities of the coverage table (the paper's Table 1), metres.
pub const COVERAGE_GRANULARITIES: [f64; 5] = [1.0, 2.0, 3.0, 4.0, 5.0];

/// The survey's configuration, written as `config.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SurveyConfig {
    /// The tracker of every walk (its seed is the first walk's; walk `k` uses seed + k).
    pub tracker: TrackerConfig,
    /// Rooms and cells.
    pub cells: CellConfig,
    /// Share of surveyed scans allowed outside their own cell's region when calibrating the
    /// map's `ε` (default 0.001; the paper's ε gave 0.00028 per step on its building).
    pub epsilon_miss: f64,
}

impl Default for SurveyConfig {
    fn default() -> Self {
        Self {
            tracker: TrackerConfig::default(),
            cells: CellConfig::default(),
            epsilon_miss: EPSILON_MISS,
        }
    }
}

impl SurveyConfig {
    /// Checks every part.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `tracker` fails
    /// [`TrackerConfig::validate`](crate::filter::TrackerConfig::validate), `cells` fails
    /// [`CellConfig::validate`](crate::map::CellConfig::validate), or `epsilon_miss` is outside
    /// [0, 0.5].
    pub fn validate(&self) -> Result<()> {
        self.tracker.validate()?;
        self.cells.validate()?;
        crate::error::check_range("epsilon_miss", self.epsilon_miss, 0.0..=0.5, "")
    }
}

/// One walk to survey.
#[derive(Debug, Clone, Default)]
pub struct SurveyWalk {
    /// Its steps.
    pub trace: StepTrace,
    /// Its WiFi scans, in time order on the steps' clock.
    pub scans: Vec<WifiScan>,
    /// Its own known start (else the configuration's, else unknown).
    pub start: Option<StartPose>,
}

/// What [`survey`] reads.
#[derive(Debug, Clone, Copy)]
pub struct SurveyInput<'a> {
    /// The floor plan.
    pub plan: &'a FloorPlan,
    /// Its topology (built with the tracker's topology configuration).
    pub topology: &'a FloorTopology,
    /// The walks.
    pub walks: &'a [SurveyWalk],
    /// Radio maps surveyed before on this plan at this granularity, merged in.
    pub earlier: &'a [RadioMap],
}

/// What the survey did with one walk.
#[derive(Debug, Clone)]
pub struct SurveyedWalk {
    /// The start it was tracked from.
    pub start: Option<StartPose>,
    /// Steps until the tracker was localised (1-based).
    pub steps_to_localise: Option<usize>,
    /// Steps whose place the survey knew.
    pub steps_placed: usize,
    /// Scans added to a cell, and scans left out.
    pub scans_added: usize,
    /// Scans from localisation on whose step had no estimate or no cell.
    pub scans_skipped: usize,
    /// How well the walk fitted the plan ([`track_quality`]). A `poor` walk's scans are
    /// left out of the map (they would land in the wrong cells).
    pub quality: Quality,
}

impl SurveyedWalk {
    /// Whether the walk's scans were left out of the map.
    #[must_use]
    pub fn left_out(&self) -> bool {
        self.quality.verdict == Verdict::Poor
    }
}

/// One row of the coverage table.
#[derive(Debug, Clone, Copy)]
pub struct Coverage {
    /// Cell granularity, metres.
    pub granularity: f64,
    /// Cells of the plan.
    pub cells: usize,
    /// Share of the plan's area in cells with a scan.
    pub share: f64,
    /// Scans per covered cell.
    pub mean_scans: f64,
}

/// What [`survey`] gives.
#[derive(Debug)]
pub struct Surveyed {
    /// The cells at the configured granularity.
    pub cells: CellMap,
    /// The radio map, merged and calibrated.
    pub map: RadioMap,
    /// Per walk, in order.
    pub walks: Vec<SurveyedWalk>,
    /// The held-out scans ε was calibrated on.
    pub held: Vec<HeldOut>,
    /// The coverage table ([`COVERAGE_GRANULARITIES`]).
    pub coverage: Vec<Coverage>,
    /// The survey's verdict: its walks', each named (a walk left out makes the map
    /// `doubtful`: it covers less than the walks did).
    pub quality: Quality,
}

/// Surveys the walks of `input` with `config` in the stages of the [module](self).
///
/// # Errors
///
/// - [`Error::Config`] when `config` fails [`SurveyConfig::validate`].
/// - As [`Tracker::new`](crate::filter::Tracker::new) for each walk: a start off the plan, or a
///   plan with no walkable surface; [`Error::InvalidData`] for a step that is not finite.
/// - [`Error::Mismatch`] when no walk fits the plan (and no earlier map is merged), the topology is
///   not the plan's, or an earlier radio map is not of this plan at this cell granularity.
pub fn survey(
    input: &SurveyInput,
    config: &SurveyConfig,
    progress: &dyn Progress,
) -> Result<Surveyed> {
    config.validate()?;
    let starts: Vec<Option<StartPose>> = input
        .walks
        .iter()
        .map(|w| w.start.or(config.tracker.start))
        .collect();
    // 1. track: per walk, the filter's reports, and the steps its scans are placed by.
    let total: u64 = input.walks.iter().map(|w| w.trace.len() as u64).sum();
    progress.start("surveying", total);
    // Several walks: each walk's steps beside the total.
    let several = input.walks.len() > 1;
    // The walks are independent (walk k's seed is the survey's plus k), so they run in
    // parallel; the results do not depend on the number of threads.
    let tracked: Vec<Result<TrackedWalk>> = input
        .walks
        .par_iter()
        .enumerate()
        .map(|(k, walk)| {
            let tracker_config = TrackerConfig {
                seed: config.tracker.seed.wrapping_add(k as u64),
                start: starts[k],
                ..config.tracker.clone()
            };
            let mut tracker = Tracker::new(input.topology, &tracker_config)?;
            let mut reports = Vec::with_capacity(walk.trace.len());
            if several {
                progress.item_start(k, &format!("walk {}", k + 1), walk.trace.len() as u64);
            }
            for step in walk.trace.steps() {
                reports.push(tracker.update(step)?);
                progress.advance(1);
                if several {
                    progress.item_advance(k, 1);
                }
            }
            if several {
                progress.item_finish(k);
            }
            let mut placed = placed_steps(&tracker, reports.clone());
            let quality = walk_quality(&reports, &placed, &tracker);
            if quality.verdict == Verdict::Poor {
                // A walk that does not fit the plan places its scans in the wrong cells.
                for step in &mut placed {
                    step.estimate = None;
                }
            }
            Ok((reports, placed, quality))
        })
        .collect();
    let mut runs: Vec<(Vec<TrackStep>, Vec<TrackStep>)> = Vec::with_capacity(input.walks.len());
    let mut qualities = Vec::with_capacity(input.walks.len());
    for walk in tracked {
        let (reports, placed, quality) = walk?;
        qualities.push(quality);
        runs.push((reports, placed));
    }
    progress.finish();
    if input.earlier.is_empty()
        && !qualities.is_empty()
        && qualities.iter().all(|q| q.verdict == Verdict::Poor)
    {
        return Err(Error::mismatch(
            format!(
                "no walk fits the floor plan, so no scan can be placed ({}{})",
                if qualities.len() > 1 { "walk 1: " } else { "" },
                qualities[0].line()
            ),
            "check that the plan is this building's, in the walks' frame (origin), with its floors",
        ));
    }
    // 2. cells
    let placed: Vec<&[TrackStep]> = runs.iter().map(|(_, p)| p.as_slice()).collect();
    let (cells, mut map, counts, assignments) =
        cells_and_map(input, &placed, &config.cells, config.cells.granularity)?;
    // 3. merge
    for (k, earlier) in input.earlier.iter().enumerate() {
        map.merge(earlier).map_err(|e| {
            Error::mismatch(
                format!(
                    "earlier radio map {}: not a map of this plan at {} m cells ({e})",
                    k + 1,
                    config.cells.granularity
                ),
                "merge maps surveyed on the same plan with the same cell granularity",
            )
        })?;
    }
    // 4. calibrate
    let calibration: Vec<(Assignments, &[WifiScan])> = assignments
        .into_iter()
        .zip(input.walks.iter().map(|w| w.scans.as_slice()))
        .collect();
    let held = calibrate_map(
        &mut map,
        &calibration,
        config.tracker.rf.missing_rssi,
        config.epsilon_miss,
    );
    // 5. coverage
    let coverage = COVERAGE_GRANULARITIES
        .iter()
        .map(|&g| {
            let (_, m, ..) = cells_and_map(input, &placed, &config.cells, g)?;
            let (share, mean_scans) = m.coverage();
            Ok(Coverage {
                granularity: g,
                cells: m.cells.len(),
                share,
                mean_scans,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let walks: Vec<SurveyedWalk> = runs
        .iter()
        .zip(&counts)
        .zip(starts.iter().zip(qualities))
        .map(
            |(((reports, placed), &(added, skipped)), (start, quality))| SurveyedWalk {
                start: *start,
                steps_to_localise: reports.iter().position(|r| r.localised).map(|i| i + 1),
                steps_placed: placed.iter().filter(|r| r.estimate.is_some()).count(),
                scans_added: added,
                scans_skipped: skipped,
                quality,
            },
        )
        .collect();
    let quality = survey_quality(&walks);
    Ok(Surveyed {
        cells,
        map,
        walks,
        held,
        coverage,
        quality,
    })
}

/// One surveyed walk's verdict from the filter's reports and the steps placed.
fn walk_quality(reports: &[TrackStep], placed: &[TrackStep], tracker: &Tracker) -> Quality {
    // The tracking run's own records: the same fit and deaths `track` reports.
    let mut records = StepRecords::default();
    for (i, r) in reports.iter().enumerate() {
        records.push(i, r.t, r);
    }
    track_quality(
        &TrackEvidence {
            fit: &records.fit,
            recoveries: &records.recoveries,
            steps: reports.len(),
            settled: reports.iter().chain(placed).any(|r| r.localised),
            capped_draws: tracker.capped_draws(),
            smoothing_dropped_at: tracker.smoothing_dropped_at(),
        },
        &QualityConfig::default(),
    )
}

/// The survey's verdict: its walks' reasons, each named; a walk left out makes the map
/// doubtful at worst (the map holds the others' scans).
fn survey_quality(walks: &[SurveyedWalk]) -> Quality {
    let named: Vec<(String, Quality)> = walks
        .iter()
        .enumerate()
        .filter(|(_, w)| w.quality.verdict != Verdict::Ok)
        .map(|(k, w)| {
            let mut q = w.quality.clone();
            if w.left_out() {
                for r in &mut q.reasons {
                    r.verdict = Verdict::Doubtful;
                }
                q.reasons.push(super::quality::Reason {
                    code: "walk_left_out",
                    verdict: Verdict::Doubtful,
                    message: "its scans were left out of the map".into(),
                });
            }
            (format!("walk {}", k + 1), q)
        })
        .collect();
    let mut quality = Quality::combined(named.iter().map(|(n, q)| (n.clone(), q)));
    if !walks.is_empty() && walks.iter().all(SurveyedWalk::left_out) {
        quality.verdict = Verdict::Poor;
    }
    quality
}

/// One surveyed walk: the filter's reports, the steps its scans are placed by, its quality.
type TrackedWalk = (Vec<TrackStep>, Vec<TrackStep>, Quality);

/// Stage 2 at one granularity: the cells, the map of every walk's scans, each walk's scans
/// (added, skipped) and where they went.
type AtGranularity = (CellMap, RadioMap, Vec<(usize, usize)>, Vec<Assignments>);

fn cells_and_map(
    input: &SurveyInput,
    placed: &[&[TrackStep]],
    cell_config: &CellConfig,
    granularity: f64,
) -> Result<AtGranularity> {
    let cells = CellMap::build(
        input.plan,
        input.topology,
        &CellConfig {
            granularity,
            ..*cell_config
        },
    )?;
    let mut map = RadioMap::empty(&cells);
    let assignments: Vec<Assignments> = placed
        .iter()
        .zip(input.walks)
        .map(|(placed, walk)| survey_assignments(&cells, input.topology, placed, &walk.scans))
        .collect();
    let counts = assignments
        .iter()
        .zip(input.walks)
        .map(|(a, walk)| {
            let c = survey_walk(&mut map, a, &walk.scans);
            (c.added, c.skipped)
        })
        .collect();
    Ok((cells, map, counts, assignments))
}
