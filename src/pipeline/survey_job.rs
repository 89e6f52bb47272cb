//! The `survey` job, request in, report out: what the command line and the Python package
//! both run, so that neither repeats the other.
//!
//! 1. **overrides** — the faces' options over the configuration ([`SurveyOverrides`]);
//! 2. **prepare** — the topology of the plan, every walk's steps able to change floor on a
//!    plan of several levels, its WiFi log on its steps' clock ([`prepare_survey`]): a
//!    failed check is an error naming the input, with a [`Remedy`](crate::error::Remedy)
//!    where one option fixes it;
//! 3. **survey** — [`survey`](super::survey()) on what was prepared
//!    ([`PreparedSurvey::run`]);
//! 4. **report** — `summary.json` as one typed struct ([`SurveyReport`]).

use super::Progress;
use super::job_checks::{check_height_changes, check_scans_on_clock};
use super::named::Named;
use super::quality::Quality;
use super::survey::{SurveyConfig, SurveyInput, SurveyWalk, Surveyed, survey};
use crate::error::{Error, Result};
use crate::filter::StartPose;
use crate::geometry::LocalFrame;
use crate::map::{FloorPlan, FloorTopology, RadioMap};
use crate::model::wifi_distance::held_out_quantiles;
use crate::sensor::{StepTrace, WifiScan};
use serde::Serialize;
use std::collections::BTreeMap;

/// The options of `survey` that change its configuration; `None` leaves the
/// configuration's value. Both faces fill it from their arguments.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurveyOverrides {
    /// `tracker.seed` (walk `k` has `seed + k`).
    pub seed: Option<u64>,
    /// KLD-sampling's cap ([`crate::filter::KldConfig::cap_particles`]).
    pub particles: Option<usize>,
    /// `tracker.start`: every walk's known start, unless the walk gives its own.
    pub start: Option<StartPose>,
    /// `cells.granularity`, metres.
    pub cell: Option<f64>,
}

impl SurveyOverrides {
    /// `config` with these overrides, validated.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when the result fails [`SurveyConfig::validate`] (e.g. a negative `cell`).
    ///
    /// # Examples
    ///
    /// ```
    /// use footslam::pipeline::{SurveyConfig, SurveyOverrides};
    /// let o = SurveyOverrides { seed: Some(9), cell: Some(4.0), ..Default::default() };
    /// let config = o.apply(SurveyConfig::default())?;
    /// assert_eq!((config.tracker.seed, config.cells.granularity), (9, 4.0));
    /// let bad = SurveyOverrides { cell: Some(-1.0), ..Default::default() };
    /// assert!(bad.apply(SurveyConfig::default()).is_err());
    /// # Ok::<(), footslam::Error>(())
    /// ```
    pub fn apply(&self, mut config: SurveyConfig) -> Result<SurveyConfig> {
        if let Some(s) = self.seed {
            config.tracker.seed = s;
        }
        if let Some(n) = self.particles {
            config.tracker.kld.cap_particles(n);
        }
        if self.start.is_some() {
            config.tracker.start = self.start;
        }
        if let Some(g) = self.cell {
            config.cells.granularity = g;
        }
        config.validate()?;
        Ok(config)
    }
}

/// One walk of a `survey` request, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct SurveyWalkRequest {
    /// The steps.
    pub steps: Named<StepTrace>,
    /// Whether the steps came with a `dz` column.
    pub steps_have_dz: bool,
    /// The WiFi scans, in time order on the steps' clock.
    pub wifi: Named<Vec<WifiScan>>,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
    /// The walk's own known start.
    pub start: Option<StartPose>,
}

/// Everything `survey` runs on, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct SurveyRequest {
    /// The floor plan, in `frame`.
    pub plan: Named<FloorPlan>,
    /// The local frame (the plan's, or the given origin).
    pub frame: LocalFrame,
    /// The walks.
    pub walks: Vec<SurveyWalkRequest>,
    /// Every walk stays on its start floor (steps without `dz` allowed on several floors).
    pub one_floor: bool,
    /// Radio maps surveyed before on this plan at this granularity, in `frame`, merged in.
    pub earlier: Vec<RadioMap>,
    /// The configuration file's (or the defaults).
    pub config: SurveyConfig,
    /// The face's options over it.
    pub overrides: SurveyOverrides,
}

/// The names of one walk's inputs, for the report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SurveyWalkLabels {
    /// The steps'.
    pub steps: String,
    /// The WiFi log's.
    pub wifi: String,
    /// Rows of the WiFi log that repeated an access point within a scan.
    pub duplicate_readings: usize,
}

/// What [`prepare_survey`] made of a request: the survey's inputs, checked.
#[derive(Debug)]
pub struct PreparedSurvey {
    /// The configuration run, overrides applied.
    pub config: SurveyConfig,
    /// The plan and its name.
    pub plan: Named<FloorPlan>,
    /// The frame.
    pub frame: LocalFrame,
    /// The plan's walkable surfaces and their connections.
    pub topology: FloorTopology,
    /// The walks.
    pub walks: Vec<SurveyWalk>,
    /// Their inputs' names, walk by walk.
    pub labels: Vec<SurveyWalkLabels>,
    /// The radio maps merged in.
    pub earlier: Vec<RadioMap>,
}

impl PreparedSurvey {
    /// What [`survey`](super::survey()) surveys.
    #[must_use]
    pub fn input(&self) -> SurveyInput<'_> {
        SurveyInput {
            plan: &self.plan.value,
            topology: &self.topology,
            walks: &self.walks,
            earlier: &self.earlier,
        }
    }

    /// Surveys the walks ([`survey`](super::survey())).
    ///
    /// # Errors
    ///
    /// Every error of [`survey`](super::survey()), as an [`Error::InvalidData`] naming the plan: a
    /// walk that fits no part of it, a start off it, or an earlier radio map of another plan.
    pub fn run(&self, progress: &dyn Progress) -> Result<Surveyed> {
        survey(&self.input(), &self.config, progress).map_err(|e| {
            Error::invalid(&self.plan.label, format!("cannot survey on this plan: {e}"))
        })
    }
}

/// Stage 2: checks that the request's inputs belong together and builds the plan's
/// topology. What the user should know but that does not stop the run (a log partly off
/// the walk's clock, repeated readings) goes to `progress` as warnings.
///
/// # Errors
///
/// Each names the input or option at fault:
///
/// - [`Error::Config`] when the configuration with its overrides fails [`SurveyConfig::validate`].
/// - [`Error::NotEnough`] when the request holds neither walks nor earlier radio maps.
/// - [`Error::InvalidData`] naming the plan when it is not a usable floor plan
///   ([`FloorTopology::build`]).
/// - [`Error::Remedied`] (`one_floor`) when the plan has several levels but a walk's steps carry no
///   height changes.
/// - [`Error::Mismatch`] when a walk's WiFi log has no scan within its steps' time span.
pub fn prepare_survey(request: SurveyRequest, progress: &dyn Progress) -> Result<PreparedSurvey> {
    let config = request.overrides.apply(request.config)?;
    if request.walks.is_empty() && request.earlier.is_empty() {
        return Err(Error::not_enough(
            "nothing to survey",
            "give walks (step traces with their WiFi logs) or radio maps to merge",
        ));
    }
    let plan = request.plan;
    let topology = FloorTopology::build(&plan.value, &config.tracker.topology)
        .map_err(|e| Error::invalid(&plan.label, format!("not a usable floor plan: {e}")))?;
    let mut walks = Vec::with_capacity(request.walks.len());
    let mut labels = Vec::with_capacity(request.walks.len());
    for w in request.walks {
        let on_plan = Named::new(&plan.value, plan.label.as_str());
        check_height_changes(&w.steps.label, w.steps_have_dz, &on_plan, request.one_floor)?;
        check_scans_on_clock(&w.wifi, w.duplicate_readings, &w.steps.value, progress)?;
        labels.push(SurveyWalkLabels {
            steps: w.steps.label,
            wifi: w.wifi.label,
            duplicate_readings: w.duplicate_readings,
        });
        walks.push(SurveyWalk {
            trace: w.steps.value,
            scans: w.wifi.value,
            start: w.start,
        });
    }
    Ok(PreparedSurvey {
        config,
        plan,
        frame: request.frame,
        topology,
        walks,
        labels,
        earlier: request.earlier,
    })
}

/// One walk's figures in `survey`'s `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SurveyWalkReport {
    /// The steps' name.
    pub steps_file: String,
    /// The WiFi log's name.
    pub wifi_file: String,
    /// The walk's known start (its own, else the shared one).
    pub start: Option<StartPose>,
    /// Steps.
    pub steps: usize,
    /// Scans.
    pub scans: usize,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
    /// Steps until the tracker was localised (1-based).
    pub steps_to_localise: Option<usize>,
    /// Steps whose place the survey knew (the whole-walk answer's certain steps, or the
    /// filtered estimates from localisation on with `tracker.smoothing = false`).
    pub steps_placed: usize,
    /// Scans added to a cell.
    pub scans_added: usize,
    /// Scans left out.
    pub scans_skipped: usize,
    /// How well the walk fitted the plan; a `poor` walk's scans are left out of the map.
    pub quality: Quality,
}

/// `summary.json` of `survey`.
#[derive(Debug, Clone, Serialize)]
pub struct SurveyReport {
    /// The survey's verdict and its reasons (docs/robustness.md).
    pub quality: Quality,
    /// Per walk, in order.
    pub walks: Vec<SurveyWalkReport>,
    /// Cells of the plan at the granularity.
    pub cells: usize,
    /// Rooms they divide.
    pub rooms: usize,
    /// Cell granularity, metres.
    pub granularity_m: f64,
    /// Share of the plan's area in cells with a scan.
    pub coverage: f64,
    /// Scans per covered cell.
    pub mean_scans_per_covered_cell: f64,
    /// The region threshold, calibrated.
    pub epsilon: Option<f64>,
    /// The same for the square-root distance.
    pub epsilon_sqrt: Option<f64>,
    /// Per distance (`paper`, `sqrt`): quantiles of the held-out distances ε is chosen from.
    pub ndist_leave_one_out_p50_p90_p99_max: BTreeMap<&'static str, [Option<f64>; 4]>,
    /// Access points of the map.
    pub access_points: usize,
    /// Seconds from the start of the job to the report.
    pub runtime_s: f64,
    /// The walks' duration, seconds.
    pub walk_duration_s: f64,
    /// Walking time surveyed per second of run.
    pub speed_vs_real_time: f64,
    /// The process's peak resident memory, where the system tells.
    pub peak_memory_bytes: Option<u64>,
    /// The frame of the plan and the map.
    pub origin: LocalFrame,
    /// The toolkit's version.
    pub version: &'static str,
}

impl SurveyReport {
    /// The report of `surveyed`, surveyed from `prepared` by a job begun at `started`.
    #[must_use]
    pub fn new(
        prepared: &PreparedSurvey,
        surveyed: &Surveyed,
        started: std::time::Instant,
    ) -> Self {
        let map = &surveyed.map;
        let (share, mean) = map.coverage();
        let duration: f64 = prepared
            .walks
            .iter()
            .map(|w| {
                let st = w.trace.steps();
                st.last().map_or(0.0, |l| l.t - st[0].t)
            })
            .sum();
        let runtime = started.elapsed().as_secs_f64();
        let walks = prepared
            .labels
            .iter()
            .zip(&prepared.walks)
            .zip(&surveyed.walks)
            .map(|((labels, walk), done)| SurveyWalkReport {
                steps_file: labels.steps.clone(),
                wifi_file: labels.wifi.clone(),
                start: done.start,
                steps: walk.trace.len(),
                scans: walk.scans.len(),
                duplicate_readings: labels.duplicate_readings,
                steps_to_localise: done.steps_to_localise,
                steps_placed: done.steps_placed,
                scans_added: done.scans_added,
                scans_skipped: done.scans_skipped,
                quality: done.quality.clone(),
            })
            .collect();
        Self {
            quality: surveyed.quality.clone(),
            walks,
            cells: surveyed.cells.cells().len(),
            rooms: surveyed.cells.rooms().len(),
            granularity_m: prepared.config.cells.granularity,
            coverage: share,
            mean_scans_per_covered_cell: mean,
            epsilon: map.epsilon,
            epsilon_sqrt: map.epsilon_sqrt,
            ndist_leave_one_out_p50_p90_p99_max: held_out_quantiles(&surveyed.held),
            access_points: map.access_points().len(),
            runtime_s: runtime,
            walk_duration_s: duration,
            speed_vs_real_time: duration / runtime.max(1e-9),
            peak_memory_bytes: crate::memory::peak_bytes(),
            origin: prepared.frame,
            version: env!("CARGO_PKG_VERSION"),
        }
    }
}
