//! The `track` job, request in, report out: what the command line and the Python package
//! both run, so that neither repeats the other.
//!
//! 1. **overrides** — the faces' options that change the configuration
//!    ([`TrackOverrides`]), applied by the library to the configuration file's;
//! 2. **prepare** — the plan grown by its margin, the learned map on the plan's frame, the
//!    steps' height changes on a plan of several floors, the topology, the WiFi log on the
//!    steps' clock and of the radio map's building, the localiser ([`prepare`]): a failed
//!    check is an error naming the input, with a [`Remedy`](crate::error::Remedy) where one
//!    option fixes it;
//! 3. **track** — [`track`](super::track()) on what was prepared;
//! 4. **answer** — the smoothed whole-walk answer read into rows
//!    ([`TrackAnswer`](super::TrackAnswer));
//! 5. **report** — `summary.json` as one typed struct ([`TrackReport`](super::TrackReport)).

use super::Progress;
use super::input_checks::SAME_ORIGIN_M;
use super::job_checks::{check_height_changes, check_scans_match, check_scans_on_clock};
use super::named::Named;
use super::track::{RadioInput, SnapshotSteps, TrackInput, TrackRun};
use crate::error::{Error, Result};
use crate::filter::{RfLocaliser, RfMode, StartPose, TrackerConfig};
use crate::geometry::LocalFrame;
use crate::io::map_geojson::StoredMap;
use crate::map::{FloorPlan, FloorTopology, RadioMap, grow_plan};
use crate::model::TransitionPrior;
use crate::model::wifi_distance::Normalisation;
use crate::sensor::{StepTrace, WifiScan};
use std::sync::Arc;

/// The options of `track` that change its configuration; `None` (or `false`) leaves the
/// configuration's value. Both faces fill it from their arguments.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrackOverrides {
    /// `seed`.
    pub seed: Option<u64>,
    /// KLD-sampling's cap ([`crate::filter::KldConfig::cap_particles`]).
    pub particles: Option<usize>,
    /// The known start.
    pub start: Option<StartPose>,
    /// `heading.enabled = false`.
    pub ignore_heading: bool,
    /// `rf.mode`.
    pub rf_mode: Option<RfMode>,
    /// `rf.epsilon`.
    pub rf_epsilon: Option<f64>,
    /// `rf.distance`.
    pub rf_distance: Option<Normalisation>,
    /// `rf.every_step = true`.
    pub rf_every_step: bool,
    /// `smoothing = false`: causal answers only.
    pub online: bool,
    /// `transitions.weight`: the learned map's exponent.
    pub map_weight: Option<f64>,
}

impl TrackOverrides {
    /// `config` with these overrides, validated.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when the result fails
    /// [`TrackerConfig::validate`](crate::filter::TrackerConfig::validate) (e.g. an `rf_epsilon`
    /// outside [0.01, 200] dBm).
    ///
    /// # Examples
    ///
    /// ```
    /// use footslam::filter::TrackerConfig;
    /// use footslam::pipeline::TrackOverrides;
    /// let o = TrackOverrides { seed: Some(3), online: true, ..Default::default() };
    /// let config = o.apply(TrackerConfig::default())?;
    /// assert_eq!(config.seed, 3);
    /// assert!(!config.smoothing);
    /// # Ok::<(), footslam::Error>(())
    /// ```
    pub fn apply(&self, mut config: TrackerConfig) -> Result<TrackerConfig> {
        if let Some(s) = self.seed {
            config.seed = s;
        }
        if let Some(n) = self.particles {
            config.kld.cap_particles(n);
        }
        if self.start.is_some() {
            config.start = self.start;
        }
        if self.ignore_heading {
            config.heading.enabled = false;
        }
        if let Some(m) = self.rf_mode {
            config.rf.mode = m;
        }
        if self.rf_epsilon.is_some() {
            config.rf.epsilon = self.rf_epsilon;
        }
        if self.rf_distance.is_some() {
            config.rf.distance = self.rf_distance;
        }
        if self.rf_every_step {
            config.rf.every_step = true;
        }
        if self.online {
            config.smoothing = false;
        }
        if let Some(w) = self.map_weight {
            config.transitions.weight = w;
        }
        config.validate()?;
        Ok(config)
    }
}

/// A walk's WiFi log and the radio map to place it with, read.
#[derive(Debug, Clone)]
pub struct TrackRadioRequest {
    /// The radio map, in the plan's frame.
    pub map: Named<RadioMap>,
    /// The walk's scans, in time order, on the steps' clock.
    pub scans: Named<Vec<WifiScan>>,
    /// Rows of the log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
}

/// Everything `track` runs on, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct TrackRequest {
    /// The floor plan, in `frame`.
    pub plan: Named<FloorPlan>,
    /// The local frame (the plan's, or the given origin).
    pub frame: LocalFrame,
    /// Grow the plan by this many metres first (a learned plan's edges are where walks
    /// stopped, not walls).
    pub plan_margin: Option<f64>,
    /// The walk's steps.
    pub steps: Named<StepTrace>,
    /// Whether the steps came with a `dz` column.
    pub steps_have_dz: bool,
    /// The walk stays on its start floor (steps without `dz` allowed on several floors).
    pub one_floor: bool,
    /// A learned map whose transitions become the motion prior.
    pub map: Option<Named<StoredMap>>,
    /// The radio map and the walk's scans.
    pub radio: Option<TrackRadioRequest>,
    /// The steps after which the particle cloud is kept.
    pub snapshots: SnapshotSteps,
    /// The configuration file's (or the defaults).
    pub config: TrackerConfig,
    /// The face's options over it.
    pub overrides: TrackOverrides,
}

/// Another walk on a prepared plan and radio map ([`PreparedTrack::for_walk`]; `track
/// --walks`).
#[derive(Debug, Clone)]
pub struct TrackWalkRequest {
    /// The walk's steps.
    pub steps: Named<StepTrace>,
    /// Whether the steps came with a `dz` column.
    pub steps_have_dz: bool,
    /// The walk's scans, with the rows of its log that repeated an access point within a
    /// scan; required with a radio map, refused without.
    pub scans: Option<(Named<Vec<WifiScan>>, usize)>,
    /// The walk's start (`None`: the configuration file's, normally unknown).
    pub start: Option<StartPose>,
}

/// The radio map as a localiser, with the walk's scans.
#[derive(Debug)]
pub struct PreparedRadio {
    /// The radio map's name.
    pub map_label: String,
    /// The WiFi log's name.
    pub wifi_label: String,
    /// The radio map (shared by the walks of a batch).
    pub map: Arc<RadioMap>,
    /// The localiser on the plan's topology (shared by the walks of a batch).
    pub localiser: Arc<RfLocaliser>,
    /// The scans.
    pub scans: Vec<WifiScan>,
    /// Scans that hear an access point of the map.
    pub matched: usize,
    /// Rows of the log that repeated an access point within a scan.
    pub duplicate_readings: usize,
}

/// What [`prepare`] made of a request: the filter's inputs, checked.
#[derive(Debug)]
pub struct PreparedTrack {
    /// The configuration run, overrides applied.
    pub config: TrackerConfig,
    /// The plan (grown by its margin).
    pub plan: FloorPlan,
    /// Its name.
    pub plan_label: String,
    /// The frame.
    pub frame: LocalFrame,
    /// The plan's walkable surfaces and their connections (shared by the walks of a batch).
    pub topology: Arc<FloorTopology>,
    /// The walk stays on its start floor.
    pub one_floor: bool,
    /// The configuration file's start, before the request's override: what a batch's walks
    /// without a start of their own take ([`Self::for_walk`]).
    pub base_start: Option<StartPose>,
    /// The learned map's transitions, and the map's name.
    pub transitions: Option<(TransitionPrior, String)>,
    /// The walk's steps.
    pub trace: StepTrace,
    /// Their name.
    pub steps_label: String,
    /// The radio map and the scans.
    pub radio: Option<PreparedRadio>,
    /// The steps after which the particle cloud is kept.
    pub snapshots: SnapshotSteps,
}

impl PreparedTrack {
    /// What [`track`](super::track()) tracks on.
    #[must_use]
    pub fn input(&self) -> TrackInput<'_> {
        TrackInput {
            topology: &self.topology,
            transitions: self.transitions.as_ref().map(|(t, _)| t),
            radio: self.radio.as_ref().map(|r| RadioInput {
                localiser: &r.localiser,
                scans: &r.scans,
            }),
        }
    }

    /// Tracks the walk ([`track`](super::track())).
    ///
    /// # Errors
    ///
    /// As [`track`](super::track()): a start off the plan, a plan with no walkable surface, or
    /// (with a radio map) no particle placeable at the first scan.
    pub fn run(&self, progress: &dyn Progress) -> Result<TrackRun<'_>> {
        super::track(
            &self.input(),
            &self.trace,
            &self.config,
            &self.snapshots,
            progress,
        )
    }

    /// What [`prepare`] makes of the same request with another walk's steps, WiFi log and
    /// start: the plan, its topology, the learned map and the radio map's localiser are
    /// shared or copied, not prepared again (a batch of walks on one floor).
    ///
    /// # Errors
    ///
    /// The walk's checks of [`prepare`]: height changes, snapshots, the log on the steps'
    /// clock and of the map's building; [`Error::Mismatch`] for scans without a radio map
    /// or a radio map without scans; [`Error::Config`] for a start the configuration
    /// refuses.
    pub fn for_walk(&self, walk: TrackWalkRequest, progress: &dyn Progress) -> Result<Self> {
        let mut config = self.config.clone();
        config.start = walk.start.or(self.base_start);
        config.validate()?;
        let plan = Named::new(&self.plan, self.plan_label.as_str());
        check_height_changes(&walk.steps.label, walk.steps_have_dz, &plan, self.one_floor)?;
        check_snapshots(&self.snapshots, &walk.steps)?;
        let radio = match (&self.radio, walk.scans) {
            (Some(radio), Some((scans, duplicate_readings))) => Some(walk_radio(
                (&radio.map_label, &radio.map, &radio.localiser),
                scans,
                duplicate_readings,
                &walk.steps.value,
                progress,
            )?),
            (None, None) => None,
            (Some(radio), None) => {
                return Err(Error::mismatch(
                    format!("{}: no WiFi log", walk.steps.label),
                    format!("every walk needs its WiFi log with {}", radio.map_label),
                ));
            }
            (None, Some((scans, _))) => {
                return Err(Error::mismatch(
                    format!("{}: a WiFi log without a radio map", scans.label),
                    "give the radio map, or leave the logs out",
                ));
            }
        };
        Ok(Self {
            config,
            plan: self.plan.clone(),
            plan_label: self.plan_label.clone(),
            frame: self.frame,
            topology: Arc::clone(&self.topology),
            one_floor: self.one_floor,
            base_start: self.base_start,
            transitions: self.transitions.clone(),
            trace: walk.steps.value,
            steps_label: walk.steps.label,
            radio,
            snapshots: self.snapshots.clone(),
        })
    }
}

/// The snapshots asked for lie within the walk.
fn check_snapshots(snapshots: &SnapshotSteps, steps: &Named<StepTrace>) -> Result<()> {
    if let SnapshotSteps::At(list) = snapshots
        && let Some(late) = list.iter().find(|&&k| k > steps.value.len())
    {
        return Err(Error::invalid(
            "snapshots",
            format!(
                "asks for step {late}, but {} has only {} steps",
                steps.label,
                steps.value.len()
            ),
        ));
    }
    Ok(())
}

/// Stage 2: checks that the request's inputs belong together and builds the filter's. What
/// the user should know but that does not stop the run (a log partly off the walk's clock,
/// few scans of the map's building, a radio map too sparse for evidence) goes to `progress`
/// as warnings.
///
/// # Errors
///
/// Each names the input or option at fault:
///
/// - [`Error::Config`] when the configuration with its overrides fails [`TrackerConfig::validate`],
///   or a learned map is given with `map_weight` outside [0, 10].
/// - [`Error::BadOption`] (`plan_margin`) outside [0, 5] m or on a plan with several heights on a
///   level.
/// - [`Error::Mismatch`] when the learned map is not in the plan's frame, or the WiFi log is off
///   the steps' clock or hears no access point of the radio map.
/// - [`Error::Remedied`] (`one_floor`) when the plan has several levels but the steps carry no
///   height changes.
/// - [`Error::InvalidData`] for a snapshot step beyond the walk, a plan that is not a usable floor
///   plan, or a radio map that cannot localise ([`RfLocaliser::new`]).
pub fn prepare(request: TrackRequest, progress: &dyn Progress) -> Result<PreparedTrack> {
    let base_start = request.config.start;
    let config = request.overrides.apply(request.config)?;
    let Named {
        value: plan,
        label: plan_label,
    } = request.plan;
    let plan = match request.plan_margin {
        Some(margin) => grow_plan(&plan, margin).map_err(|e| Error::BadOption {
            option: "plan_margin",
            problem: format!("{margin} for {plan_label}: {e}"),
        })?,
        None => plan,
    };
    let transitions = match request.map {
        Some(map) => Some((
            map_prior(&map, &request.frame, &plan_label, &config)?,
            map.label,
        )),
        None => None,
    };
    let steps = request.steps;
    check_height_changes(
        &steps.label,
        request.steps_have_dz,
        &Named::new(&plan, plan_label.as_str()),
        request.one_floor,
    )?;
    check_snapshots(&request.snapshots, &steps)?;
    let topology = FloorTopology::build(&plan, &config.topology)
        .map_err(|e| within(&plan_label, "not a usable floor plan", e))?;
    let radio = match request.radio {
        Some(radio) => Some(prepare_radio(
            radio,
            &steps.value,
            &topology,
            &config,
            progress,
        )?),
        None => None,
    };
    Ok(PreparedTrack {
        config,
        plan,
        plan_label,
        frame: request.frame,
        topology: Arc::new(topology),
        one_floor: request.one_floor,
        base_start,
        transitions,
        trace: steps.value,
        steps_label: steps.label,
        radio,
        snapshots: request.snapshots,
    })
}

/// The learned map's transitions, the map being in the plan's frame.
fn map_prior(
    map: &Named<StoredMap>,
    frame: &LocalFrame,
    plan_label: &str,
    config: &TrackerConfig,
) -> Result<TransitionPrior> {
    let off = frame.distance_to(&map.value.frame);
    if off > SAME_ORIGIN_M {
        return Err(Error::mismatch(
            format!(
                "{}: its origin lies {off:.3} m from the plan's ({plan_label})",
                map.label
            ),
            "the learned map must be in the plan's frame (the map and the plan.geojson of one \
             learn run)",
        ));
    }
    TransitionPrior::new(&map.value.map, config.transitions)
}

/// The WiFi log on the steps' clock and of the radio map's building, and the localiser.
fn prepare_radio(
    radio: TrackRadioRequest,
    trace: &StepTrace,
    topology: &FloorTopology,
    config: &TrackerConfig,
    progress: &dyn Progress,
) -> Result<PreparedRadio> {
    let map = radio.map;
    let localiser = RfLocaliser::new(&map.value, topology, &config.rf)
        .map_err(|e| within(&map.label, "cannot localise with this radio map", e))?;
    if let Some(why) = localiser.fallback() {
        progress.warn(&format!(
            "{}: {why}; containment regions are used instead of radio evidence",
            map.label
        ));
    }
    walk_radio(
        (&map.label, &Arc::new(map.value), &Arc::new(localiser)),
        radio.scans,
        radio.duplicate_readings,
        trace,
        progress,
    )
}

/// A walk's scans on the steps' clock and of the radio map's building, with the radio map
/// (its name, the map, its localiser) shared.
fn walk_radio(
    (map_label, map, localiser): (&str, &Arc<RadioMap>, &Arc<RfLocaliser>),
    scans: Named<Vec<WifiScan>>,
    duplicate_readings: usize,
    trace: &StepTrace,
    progress: &dyn Progress,
) -> Result<PreparedRadio> {
    check_scans_on_clock(&scans, duplicate_readings, trace, progress)?;
    let matched = check_scans_match(
        &Named::new(&**map, map_label),
        &Named::new(scans.value.as_slice(), scans.label.as_str()),
        progress,
    )?;
    Ok(PreparedRadio {
        map_label: map_label.to_owned(),
        wifi_label: scans.label,
        map: Arc::clone(map),
        localiser: Arc::clone(localiser),
        scans: scans.value,
        matched,
        duplicate_readings,
    })
}

/// `error` as a problem of `label`: `what`.
fn within(label: &str, what: &str, error: Error) -> Error {
    Error::invalid(label, format!("{what}: {error}"))
}
