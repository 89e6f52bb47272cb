//! The `learn` job, request in, report out: what the command line and the Python package
//! both run, so that neither repeats the other.
//!
//! 1. **overrides** — the faces' options over the configuration ([`LearnOverrides`]);
//! 2. **prepare** — every walk's GPS fixes and WiFi scans on its steps' clock, the frame
//!    (the given origin, else [`default_frame`]), the outline (read in WGS84) projected in
//!    it, the fixes of the frame's place, the outline of the walks' building, the prior map
//!    on the run's grid ([`prepare_learn`]): a failed check is an error naming the input,
//!    with a [`Remedy`](crate::error::Remedy) where one option fixes it;
//! 3. **learn** — [`learn`](super::learn()) on what was prepared
//!    ([`PreparedLearn::run`]);
//! 4. **report** — `summary.json` as one typed struct ([`LearnReport`](super::LearnReport)).
//!
//! ```
//! use footslam::pipeline::{
//!     LearnConfig, LearnOverrides, LearnReport, LearnRequest, LearnWalkRequest, Named, Silent,
//!     WalkReport, prepare_learn,
//! };
//! use footslam::sim::{SimConfig, simulate};
//!
//! let started = std::time::Instant::now();
//! let mut sim = SimConfig { seed: 4, ..Default::default() };
//! sim.walk.laps = 1;
//! let walk = LearnWalkRequest {
//!     steps: Named::new(simulate(&sim)?.steps, "steps.csv"),
//!     field: None,
//!     gps: None,
//!     wifi: None,
//!     start: None,
//! };
//! let request = LearnRequest {
//!     walks: vec![walk],
//!     gps_t0: None,
//!     prior_map: None,
//!     outline: None,
//!     origin: None,
//!     config: LearnConfig::default(),
//!     overrides: LearnOverrides { particles: Some(300), ..Default::default() },
//! };
//! let prepared = prepare_learn(request, &Silent)?;
//! let learned = prepared.run(&Silent)?;
//! let walks = vec![WalkReport::new(&prepared.walks[0], &learned.walks[0], &prepared.labels[0], None)];
//! let report = LearnReport::new(&prepared, &learned, walks, started, 1);
//! assert_eq!(report.single.as_ref().map(|w| w.steps_file.as_str()), Some("steps.csv"));
//! # Ok::<(), footslam::Error>(())
//! ```

use super::Progress;
use super::input_checks::{fixes_far_from_origin, outline_off_walks};
use super::job_checks::{check_fixes_on_clock, check_same_grid, check_scans_on_clock};
use super::learn::{LearnInput, LearnWalk, Learned, default_frame, learn, learn_one};
use super::learn_config::{LearnConfig, LearnOverrides};
use super::learn_walks::WalkRun;
use super::named::Named;
use crate::error::{Error, Result};
use crate::filter::StartPose;
use crate::geometry::LocalFrame;
use crate::io::WorldOutline;
use crate::io::map_geojson::StoredMap;
use crate::map::HexMapSnapshot;
use crate::sensor::{GpsFix, StepFields, StepTrace, WifiScan};
use geo::Polygon;

/// One walk of a `learn` request, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct LearnWalkRequest {
    /// The steps.
    pub steps: Named<StepTrace>,
    /// The magnetic field over each step, when the steps carry it.
    pub field: Option<StepFields>,
    /// GPS fixes, on the steps' clock, and whether they came from a GPX file.
    pub gps: Option<(Named<Vec<GpsFix>>, bool)>,
    /// WiFi scans in time order, and the rows that repeated an access point within a scan
    /// (the later kept).
    pub wifi: Option<(Named<Vec<WifiScan>>, usize)>,
    /// The known start.
    pub start: Option<StartPose>,
}

/// Everything `learn` runs on, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct LearnRequest {
    /// The walks: one, or a batch (walk `i` has seed `seed + i`).
    pub walks: Vec<LearnWalkRequest>,
    /// The UTC time of the steps' `t = 0` the GPX files were read with (it must place a GPX).
    pub gps_t0: Option<f64>,
    /// A map learned earlier: its counts become prior pseudo-counts, its frame the default.
    pub prior_map: Option<Named<StoredMap>>,
    /// The building's rough outline.
    pub outline: Option<Named<WorldOutline>>,
    /// The frame's origin, when given.
    pub origin: Option<LocalFrame>,
    /// The configuration file's (or the defaults).
    pub config: LearnConfig,
    /// The face's options over it.
    pub overrides: LearnOverrides,
}

/// The names of one walk's inputs, and what their reading left out, for the report.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct WalkLabels {
    /// The steps'.
    pub steps: String,
    /// The GPS fixes'.
    pub gps: Option<String>,
    /// The WiFi log's.
    pub wifi: Option<String>,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    pub wifi_duplicate_readings: usize,
}

/// What [`prepare_learn`] made of a request: the run's inputs, checked.
#[derive(Debug)]
pub struct PreparedLearn {
    /// The configuration run, overrides applied.
    pub config: LearnConfig,
    /// The walks.
    pub walks: Vec<LearnWalk>,
    /// Their inputs' names, walk by walk.
    pub labels: Vec<WalkLabels>,
    /// The frame of maps and paths.
    pub frame: LocalFrame,
    /// The outline, in the frame.
    pub outline: Option<Polygon<f64>>,
    /// The prior map.
    pub prior_map: Option<StoredMap>,
}

impl PreparedLearn {
    /// What [`learn`](super::learn()) learns from.
    #[must_use]
    pub fn input(&self) -> LearnInput<'_> {
        LearnInput {
            walks: &self.walks,
            frame: self.frame,
            outline: self.outline.as_ref(),
            prior_map: self.prior_map.as_ref(),
        }
    }

    /// Learns the walks ([`learn`](super::learn())).
    ///
    /// # Errors
    ///
    /// As [`learn`](super::learn()): particles beyond the machine's available memory, or GPS fixes
    /// out of time order (the rest was checked by [`prepare_learn`]).
    pub fn run(&self, progress: &dyn Progress) -> Result<Learned> {
        learn(&self.input(), &self.config, progress)
    }

    /// The configuration `learned` ran with, as `config.json` holds it: one walk's as it
    /// ran (its seed, and its start from its anchors), a batch's shared one (each walk's own
    /// is in its [`WalkRun::config`]).
    #[must_use]
    pub fn config_run(&self, learned: &Learned) -> LearnConfig {
        match learned.walks.as_slice() {
            [one] => LearnConfig {
                footslam: one.config.clone(),
                ..self.config.clone()
            },
            _ => self.config.clone(),
        }
    }

    /// Learns walk `walk` of the request alone as walk `index` of a batch
    /// ([`learn_one`]), with `others` in a FeetSLAM pass.
    ///
    /// # Errors
    ///
    /// As [`learn_one`]: particles beyond the machine's available memory, or GPS fixes out of time
    /// order.
    ///
    /// # Panics
    ///
    /// If `walk` is not the index of a walk of the request.
    pub fn run_one(
        &self,
        walk: usize,
        index: usize,
        others: Option<&HexMapSnapshot>,
        steps: Option<&dyn Progress>,
    ) -> Result<WalkRun> {
        let input = self.input();
        learn_one(
            &input,
            &self.walks[walk],
            index,
            others,
            &self.config,
            steps,
        )
    }
}

/// Stage 2: checks that the request's inputs belong together and makes the run's. What the
/// user should know but that does not stop the run (a log partly off the walk's clock,
/// repeated readings) goes to `progress` as warnings.
///
/// # Errors
///
/// Each names the input or option at fault:
///
/// - [`Error::Config`] when the configuration with its overrides fails [`LearnConfig::validate`].
/// - [`Error::BadOption`] when `gps_t0` is given but no walk has a GPX file.
/// - [`Error::Remedied`] or [`Error::Mismatch`] when a walk's fixes or scans all lie off its steps'
///   clock ([`check_fixes_on_clock`], [`check_scans_on_clock`]).
/// - [`Error::Mismatch`] when a walk's fixes lie far from the origin, or the outline is far from
///   the walks' starts or too small; [`Error::Parse`] when the outline is not a valid polygon.
/// - [`Error::Remedied`] when the prior map is on another grid ([`check_same_grid`]).
pub fn prepare_learn(request: LearnRequest, progress: &dyn Progress) -> Result<PreparedLearn> {
    let config = request.overrides.apply(request.config)?;
    if request.gps_t0.is_some()
        && !request
            .walks
            .iter()
            .any(|w| w.gps.as_ref().is_some_and(|g| g.1))
    {
        return Err(Error::BadOption {
            option: "gps_t0",
            problem: "it places GPX files' UTC times on the steps' clock, and no walk has a GPX \
                      file (CSV fixes are on the steps' clock already): leave it out"
                .into(),
        });
    }
    let mut walks = Vec::with_capacity(request.walks.len());
    let mut labels = Vec::with_capacity(request.walks.len());
    for w in request.walks {
        let trace = &w.steps.value;
        if let Some((fixes, gpx)) = &w.gps {
            check_fixes_on_clock(fixes, *gpx, trace, progress)?;
        }
        if let Some((scans, duplicates)) = &w.wifi {
            check_scans_on_clock(scans, *duplicates, trace, progress)?;
        }
        labels.push(WalkLabels {
            steps: w.steps.label,
            gps: w.gps.as_ref().map(|g| g.0.label.clone()),
            wifi: w.wifi.as_ref().map(|s| s.0.label.clone()),
            wifi_duplicate_readings: w.wifi.as_ref().map_or(0, |s| s.1),
        });
        walks.push(LearnWalk {
            trace: w.steps.value,
            fixes: w.gps.map(|g| g.0.value).unwrap_or_default(),
            scans: w.wifi.map(|s| s.0.value).unwrap_or_default(),
            start: w.start,
            field: w.field,
        });
    }
    let frame = request
        .origin
        .unwrap_or_else(|| default_frame(request.prior_map.as_ref().map(|m| &m.value), &walks));
    for (walk, label) in walks.iter().zip(&labels) {
        if let (Some(gps), Some(problem)) = (&label.gps, fixes_far_from_origin(&walk.fixes, &frame))
        {
            return Err(Error::mismatch(format!("{gps}: {problem}"), ""));
        }
    }
    let outline = match &request.outline {
        Some(outline) => {
            let polygon = outline.value.project(&frame)?;
            let start = (config.footslam.start.x, config.footslam.start.y);
            if let Some(problem) = outline_off_walks(&polygon, &walks, start) {
                return Err(Error::mismatch(format!("{}: {problem}", outline.label), ""));
            }
            Some(polygon)
        }
        None => None,
    };
    if let Some(map) = &request.prior_map {
        check_same_grid(map, config.footslam.hex_radius, &frame)?;
    }
    Ok(PreparedLearn {
        config,
        walks,
        labels,
        frame,
        outline,
        prior_map: request.prior_map.map(|m| m.value),
    })
}
