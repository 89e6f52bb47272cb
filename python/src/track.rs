//! `footslam.track`: one walk located and tracked on a known floor plan, as `footslam
//! track` runs it.

use crate::inputs::{self, Document};
use crate::outputs::{Column, columns, json_object};
use crate::tables::{self, STEPS, Table, WIFI};
use crate::{Reporter, detached, fail, py_error};
use footslam::filter::{RfMode, TrackerConfig};
use footslam::io::{SmoothedPoint, TrackPoint};
use footslam::model::wifi_distance::Normalisation;
use footslam::pipeline::{
    Named, PreparedTrack, SnapshotSteps, TrackAnswer, TrackOverrides, TrackRadioRequest,
    TrackReport, TrackRequest, TrackRun, prepare,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// What a tracking run gives, ready for Python.
struct TrackOut {
    /// The smoothed answer (`None` online).
    smoothed: Option<Vec<SmoothedPoint>>,
    filtered: Vec<TrackPoint>,
    /// Per step: particles, clusters (-1: not clustered), localised.
    records: Vec<(i64, i64, bool)>,
    /// The job's report (`summary.json`) and the configuration it ran.
    summary: serde_json::Value,
    config: serde_json::Value,
}

/// `obj` unless it is Python's `None`.
fn present<'a, 'py>(obj: Option<&'a Bound<'py, PyAny>>) -> Option<&'a Bound<'py, PyAny>> {
    obj.filter(|o| !o.is_none())
}

/// Tracks one walk on a known floor plan (``footslam track``): from an unknown start
/// (uniform over the plan) or a known one, with a radio map and the walk's WiFi when given.
///
/// Args:
///     plan: the floor plan: a path or GeoJSON dict (walkable polygons with ``level`` and
///         ``z``; e.g. :func:`plan`'s ``plan``).
///     steps: the walk's step trace: a CSV path, a pandas DataFrame or a dict of 1-D arrays
///         with columns ``t,length,dheading[,dz][,heading]``.
///     start: the known start ``"X,Y[,HEADING[,LEVEL]]"``, ``(x, y[, heading[, level]])``
///         or a dict (local metres, radians from east); default unknown.
///     wifi, radio_map: the walk's WiFi log (``t,bssid,rssi[,ssid,freq]``) and a radio map
///         (path or GeoJSON dict, as :func:`survey` makes): RF-assisted localisation.
///     hexmap: a map learned by :func:`learn` in the plan's frame: its transitions become a
///         motion prior; ``hexmap_weight`` its exponent (default 1).
///     origin: ``(lat, lon)`` of the local frame; overrides the plan's ``origin``.
///     plan_margin: grow the plan by this many metres first (for learned plans).
///     one_floor: allow steps without ``dz`` on a plan of several levels.
///     config: tracker configuration: a dict with the keys of ``config.json``, or a TOML
///         or JSON file.
///     seed: overrides the configuration's.
///     ignore_heading: ignore the steps' absolute ``heading`` column.
///     online: causal answers only (no smoothing): ``track`` is then the filtered track.
///     rf_mode: ``"auto"`` (the default), ``"evidence"``, ``"containment"``,
///         ``"probabilistic"`` or ``"prior-only"``.
///     rf_distance: ``"paper"`` or ``"sqrt"``; rf_epsilon: the region threshold, dBm;
///     rf_every_step: apply the latest scan at every step.
///     threads: worker threads (default: one per core); results do not depend on it.
///     progress: a callable ``progress(stage, done, total)`` told of the run's progress
///         from its start (``done`` 0) to its end (``done == total``), at most a few hundred
///         times a stage — a tqdm bar or a log line (default: none). An exception it
///         raises is raised when the run is over.
///
/// Returns:
///     dict: ``track`` — the answer, columns ``t`` (s), ``x``, ``y``, ``z`` (m, local
///     frame), ``level``, ``certain`` (bool), ``hypotheses``, ``spread`` (m), ``share``: one row per step with a
///     smoothed estimate, as ``track.csv``; ``filtered`` — each step's estimate as the
///     filter saw it, from localisation on (``t, x, y, z, level``, as
///     ``track_filtered.csv``); ``steps`` — per step ``particles``, ``clusters`` (-1: not
///     clustered), ``localised``; ``summary`` and ``config``.
///
/// Raises:
///     FootslamError: bad data or configuration, inputs that do not belong together.
///     FileNotFoundError: a path names no file.
///     TypeError: an input of the wrong type, or a column that is not numbers.
#[pyfunction]
#[pyo3(signature = (
    plan, steps, *, start=None, wifi=None, radio_map=None, hexmap=None, hexmap_weight=None,
    origin=None, plan_margin=None, one_floor=false, config=None, seed=None,
    ignore_heading=false, online=false, rf_mode=None, rf_distance=None, rf_epsilon=None,
    rf_every_step=false, threads=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn track<'py>(
    py: Python<'py>,
    plan: &Bound<'py, PyAny>,
    steps: &Bound<'py, PyAny>,
    start: Option<&Bound<'py, PyAny>>,
    wifi: Option<&Bound<'py, PyAny>>,
    radio_map: Option<&Bound<'py, PyAny>>,
    hexmap: Option<&Bound<'py, PyAny>>,
    hexmap_weight: Option<f64>,
    origin: Option<(f64, f64)>,
    plan_margin: Option<f64>,
    one_floor: bool,
    config: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    ignore_heading: bool,
    online: bool,
    rf_mode: Option<&str>,
    rf_distance: Option<&str>,
    rf_epsilon: Option<f64>,
    rf_every_step: bool,
    threads: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let seed = crate::int_arg("seed", seed, u64::MAX)?;
    let threads = crate::int_arg("threads", threads, 1 << 20)?.map(|n| n as usize);
    let overrides = TrackOverrides {
        seed,
        particles: None,
        start: inputs::start(start, "start")?,
        ignore_heading,
        rf_mode: rf_mode.map(rf_mode_named).transpose()?,
        rf_epsilon,
        rf_distance: rf_distance.map(rf_distance_named).transpose()?,
        rf_every_step,
        online,
        map_weight: hexmap_weight,
    };
    let config: TrackerConfig = inputs::config(config)?;
    let (wifi, radio_map) = together(present(wifi), present(radio_map))?;
    let docs = TrackDocs {
        plan: inputs::document(plan, "floor plan", "plan")?,
        steps: tables::table(steps, &STEPS, "steps")?,
        hexmap: present(hexmap)
            .map(|o| inputs::document(o, "learned map", "hexmap"))
            .transpose()?,
        radio_map: radio_map
            .map(|o| inputs::document(o, "radio map", "radio_map"))
            .transpose()?,
        wifi: wifi.map(|o| tables::table(o, &WIFI, "wifi")).transpose()?,
        origin: inputs::origin(origin)?,
    };
    let report = Reporter::new(progress)?;
    let started = std::time::Instant::now();
    let out = detached(py, threads, || {
        let options = (plan_margin, one_floor, config, overrides);
        let request = docs.request(options).map_err(py_error)?;
        let prepared = prepare(request, &report).map_err(py_error)?;
        let mut run = prepared.run(&report).map_err(py_error)?;
        let times: Vec<f64> = prepared.trace.steps().iter().map(|s| s.t).collect();
        let answer = TrackAnswer::read(&mut run, &times);
        let summary = TrackReport::new(&prepared, &run, &answer, started);
        TrackOut::new(&prepared, run, answer, &summary)
    })?;
    let result = out.to_python(py)?;
    report.emit(py)?;
    Ok(result)
}

/// `rf_mode`'s value.
fn rf_mode_named(name: &str) -> PyResult<RfMode> {
    RfMode::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "rf_mode must be \"auto\", \"evidence\", \"containment\", \"probabilistic\" or \
             \"prior-only\", got {name:?}"
        ))
    })
}

/// `rf_distance`'s value.
fn rf_distance_named(name: &str) -> PyResult<Normalisation> {
    Normalisation::ALL
        .into_iter()
        .find(|d| d.name() == name)
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "rf_distance must be \"paper\" or \"sqrt\", got {name:?}"
            ))
        })
}

/// Columns `t, x, y, z, level` (and, for the smoothed answer, `certain, hypotheses,
/// spread, share`).
fn points<'py>(
    py: Python<'py>,
    p: &[TrackPoint],
    smoothed: Option<&[SmoothedPoint]>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut cols = vec![
        ("t", Column::F64(p.iter().map(|q| q.t).collect())),
        ("x", Column::F64(p.iter().map(|q| q.x).collect())),
        ("y", Column::F64(p.iter().map(|q| q.y).collect())),
        ("z", Column::F64(p.iter().map(|q| q.z).collect())),
        (
            "level",
            Column::I64(p.iter().map(|q| i64::from(q.level)).collect()),
        ),
    ];
    if let Some(rows) = smoothed {
        cols.push((
            "certain",
            Column::Bool(rows.iter().map(|r| r.certain).collect()),
        ));
        cols.push((
            "hypotheses",
            Column::I64(
                rows.iter()
                    .map(|r| i64::try_from(r.hypotheses).unwrap_or(i64::MAX))
                    .collect(),
            ),
        ));
        cols.push((
            "spread",
            Column::F64(rows.iter().map(|r| r.spread).collect()),
        ));
        cols.push(("share", Column::F64(rows.iter().map(|r| r.share).collect())));
    }
    columns(py, cols)
}

/// The documents and tables `track` reads, converted while the GIL is held.
struct TrackDocs {
    plan: Document,
    steps: Table,
    hexmap: Option<Document>,
    radio_map: Option<Document>,
    wifi: Option<Table>,
    origin: Option<footslam::geometry::LocalFrame>,
}

impl TrackDocs {
    /// The job's request: the documents and tables parsed, with the options `(plan_margin,
    /// one_floor, config, overrides)`.
    fn request(
        &self,
        options: (Option<f64>, bool, TrackerConfig, TrackOverrides),
    ) -> footslam::Result<TrackRequest> {
        let (plan_margin, one_floor, config, overrides) = options;
        let (plan, frame) = self.plan.floor_plan(self.origin)?;
        let map = match &self.hexmap {
            Some(doc) => Some(Named::new(doc.stored_map()?, doc.label())),
            None => None,
        };
        let radio = match (&self.radio_map, &self.wifi) {
            (Some(doc), Some(table)) => {
                let (map, _) = doc.radio_map(Some(frame))?;
                let log = table.wifi_log()?;
                Some(TrackRadioRequest {
                    map: Named::new(map, doc.label()),
                    scans: Named::new(log.scans, table.label()),
                    duplicate_readings: log.duplicate_readings,
                })
            }
            _ => None,
        };
        Ok(TrackRequest {
            steps_have_dz: plan.levels().len() <= 1 || one_floor || self.steps.has_column("dz")?,
            plan: Named::new(plan, self.plan.label()),
            frame,
            plan_margin,
            steps: Named::new(self.steps.steps()?, self.steps.label()),
            one_floor,
            map,
            radio,
            snapshots: SnapshotSteps::Never,
            config,
            overrides,
        })
    }
}

impl TrackOut {
    /// What `track` returns of a run of `prepared`, its answer and its report.
    fn new(
        prepared: &PreparedTrack,
        mut run: TrackRun<'_>,
        answer: TrackAnswer,
        summary: &TrackReport,
    ) -> PyResult<Self> {
        let records = run
            .records
            .steps
            .iter()
            .map(|r| {
                let count = |n: usize| i64::try_from(n).unwrap_or(i64::MAX);
                let clusters = r.clusters().map_or(-1, count);
                (count(r.particles()), clusters, r.localised())
            })
            .collect();
        Ok(TrackOut {
            smoothed: answer.smoothing.is_some().then_some(answer.rows),
            filtered: std::mem::take(&mut run.filtered),
            records,
            summary: serde_json::to_value(summary).map_err(|e| fail(e.to_string()))?,
            config: serde_json::to_value(&prepared.config).map_err(|e| fail(e.to_string()))?,
        })
    }

    /// The dict `track` returns.
    fn to_python<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = self;
        let result = PyDict::new(py);
        let filtered = points(py, &out.filtered, None)?;
        match &out.smoothed {
            Some(rows) => {
                let p: Vec<TrackPoint> = rows.iter().map(|r| r.point).collect();
                result.set_item("track", points(py, &p, Some(rows))?)?;
            }
            None => result.set_item("track", points(py, &out.filtered, None)?)?,
        }
        result.set_item("filtered", filtered)?;
        let r = &out.records;
        result.set_item(
            "steps",
            columns(
                py,
                vec![
                    ("particles", Column::I64(r.iter().map(|r| r.0).collect())),
                    ("clusters", Column::I64(r.iter().map(|r| r.1).collect())),
                    ("localised", Column::Bool(r.iter().map(|r| r.2).collect())),
                ],
            )?,
        )?;
        result.set_item("summary", json_object(py, &out.summary)?)?;
        result.set_item("config", json_object(py, &out.config)?)?;
        Ok(result)
    }
}

/// An optional argument.
type Arg<'a, 'py> = Option<&'a Bound<'py, PyAny>>;

/// `wifi` and `radio_map`, both or neither.
fn together<'a, 'py>(
    wifi: Arg<'a, 'py>,
    radio_map: Arg<'a, 'py>,
) -> PyResult<(Arg<'a, 'py>, Arg<'a, 'py>)> {
    match (wifi, radio_map) {
        (Some(w), Some(r)) => Ok((Some(w), Some(r))),
        (None, None) => Ok((None, None)),
        _ => Err(fail(
            "radio_map and wifi go together: RF-assisted tracking needs the radio map and the \
             walk's WiFi log",
        )),
    }
}
