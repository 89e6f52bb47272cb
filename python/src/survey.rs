//! `footslam.survey`: a WiFi radio map from walks tracked on a known floor plan, as
//! `footslam survey` makes it.

use crate::inputs::{self, Document};
use crate::outputs::{Column, columns, json_object};
use crate::tables::{self, STEPS, Table, WIFI};
use crate::{Reporter, detached, py_error};
use footslam::filter::StartPose;
use footslam::io::radio_map_geojson::radio_map_to_geojson;
use footslam::pipeline::{
    Coverage, Named, SurveyConfig, SurveyOverrides, SurveyReport, SurveyRequest, SurveyWalkRequest,
    prepare_survey,
};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

/// One walk to survey, as given.
struct WalkTables {
    steps: Table,
    wifi: Table,
    start: Option<StartPose>,
}

/// The walks: a list of `(steps, wifi)` pairs or of dicts with `steps`, `wifi` and
/// optionally `start`.
fn walk_tables(walks: &Bound<'_, PyAny>) -> PyResult<Vec<WalkTables>> {
    let Some(list) = inputs::as_list(walks)? else {
        return Err(PyTypeError::new_err(
            "walks: expected a list of (steps, wifi) pairs or of dicts with steps, wifi and \
             start",
        ));
    };
    list.iter()
        .enumerate()
        .map(|(i, walk)| {
            let (steps, wifi, start) = if let Ok(d) = walk.cast::<PyDict>() {
                let get = |key: &str| d.get_item(key);
                let steps = get("steps")?
                    .ok_or_else(|| PyTypeError::new_err(format!("walks[{i}]: no `steps` entry")))?;
                let wifi = get("wifi")?
                    .ok_or_else(|| PyTypeError::new_err(format!("walks[{i}]: no `wifi` entry")))?;
                (steps, wifi, get("start")?)
            } else if (walk.is_instance_of::<PyTuple>() || walk.is_instance_of::<PyList>())
                && walk.len()? == 2
            {
                (walk.get_item(0)?, walk.get_item(1)?, None)
            } else {
                return Err(PyTypeError::new_err(format!(
                    "walks[{i}]: expected a (steps, wifi) pair or a dict with steps and wifi"
                )));
            };
            Ok(WalkTables {
                steps: tables::table(&steps, &STEPS, &format!("walks[{i}].steps"))?,
                wifi: tables::table(&wifi, &WIFI, &format!("walks[{i}].wifi"))?,
                start: inputs::start(start.as_ref(), &format!("walks[{i}].start"))?,
            })
        })
        .collect()
}

/// Builds a WiFi radio map from walks tracked on a known floor plan (``footslam survey``;
/// Woodman & Harle 2009): each walk tracked (walk ``k`` with seed ``seed + k``), its scans
/// added to the cells where it was, ε calibrated on the walks' own scans.
///
/// Args:
///     plan: the floor plan (path or GeoJSON dict).
///     walks: a list of ``(steps, wifi)`` pairs, or of dicts with ``steps``, ``wifi`` and
///         optionally ``start`` (the walk's own known start); each a CSV path, a pandas
///         DataFrame or a dict of 1-D arrays (steps ``t,length,dheading[,dz][,heading]``,
///         WiFi ``t,bssid,rssi[,ssid,freq]`` on the steps' clock).
///     start: every walk's known start (unless the walk gives its own), as :func:`track`'s.
///     cell: cell granularity, metres (default 3).
///     config: survey configuration: a dict (``tracker``, ``cells``, ``epsilon_miss``) or a
///         TOML or JSON file.
///     seed: the first walk's tracker seed (overrides the configuration's).
///     origin: ``(lat, lon)`` of the local frame; overrides the plan's ``origin``.
///     one_floor: allow steps without ``dz`` on a plan of several levels.
///     merge: radio maps surveyed before on this plan at this granularity, merged in.
///     threads: worker threads (default: one per core); results do not depend on it.
///     progress: a callable ``progress(stage, done, total)`` told of the run's progress
///         from its start (``done`` 0) to its end (``done == total``), at most a few hundred
///         times a stage — a tqdm bar or a log line (default: none). An exception it
///         raises is raised when the run is over.
///
/// Returns:
///     dict: ``radio_map`` — GeoJSON as ``radiomap.geojson`` (one feature per cell with
///     ``cell``, ``level``, ``scans``, ``aps``; ``epsilon``); ``coverage`` — columns
///     ``granularity_m``, ``cells``, ``coverage`` (share of the plan's area in cells with a
///     scan), ``mean_scans`` at 1 to 5 m cells; ``walks`` — per walk ``start``,
///     ``steps_to_localise``, ``steps_placed``, ``scans_added``, ``scans_skipped``,
///     ``quality`` (a ``poor`` walk's scans are left out); ``summary`` (with the survey's
///     ``quality``) and ``config``.
///
/// Raises:
///     FootslamError: bad data or configuration, a WiFi log on another clock.
///     FileNotFoundError: a path names no file.
///     TypeError: an input of the wrong type, or a column that is not numbers.
#[pyfunction]
#[pyo3(signature = (
    plan, walks, *, start=None, cell=None, config=None, seed=None, origin=None,
    one_floor=false, merge=None, threads=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn survey<'py>(
    py: Python<'py>,
    plan: &Bound<'py, PyAny>,
    walks: &Bound<'py, PyAny>,
    start: Option<&Bound<'py, PyAny>>,
    cell: Option<f64>,
    config: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    one_floor: bool,
    merge: Option<&Bound<'py, PyAny>>,
    threads: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let seed = crate::int_arg("seed", seed, u64::MAX)?;
    let threads = crate::int_arg("threads", threads, 1 << 20)?.map(|n| n as usize);
    let started = std::time::Instant::now();
    let config: SurveyConfig = inputs::config(config)?;
    let overrides = SurveyOverrides {
        seed,
        particles: None,
        start: inputs::start(start, "start")?,
        cell,
    };
    let plan_doc = inputs::document(plan, "floor plan", "plan")?;
    let tables = walk_tables(walks)?;
    let earlier_docs = match merge.filter(|m| !m.is_none()) {
        Some(m) => inputs::as_list(m)?
            .ok_or_else(|| PyTypeError::new_err("merge: expected a list of radio maps"))?
            .iter()
            .enumerate()
            .map(|(i, m)| inputs::document(m, "radio map", &format!("merge[{i}]")))
            .collect::<PyResult<Vec<_>>>()?,
        None => Vec::new(),
    };
    let origin = inputs::origin(origin)?;
    let report = Reporter::new(progress)?;
    let (collection, coverage, summary, config) = detached(py, threads, || {
        let read = || -> footslam::Result<SurveyRequest> {
            let (plan, frame) = plan_doc.floor_plan(origin)?;
            Ok(SurveyRequest {
                walks: read_walks(&tables, &plan, one_floor)?,
                plan: Named::new(plan, plan_doc.label()),
                frame,
                one_floor,
                earlier: earlier_maps(&earlier_docs, frame)?,
                config,
                overrides,
            })
        };
        let prepared = prepare_survey(read().map_err(py_error)?, &report).map_err(py_error)?;
        let surveyed = prepared.run(&report).map_err(py_error)?;
        let summary = SurveyReport::new(&prepared, &surveyed, started);
        Ok((
            radio_map_to_geojson(&surveyed.map, &prepared.frame),
            surveyed.coverage,
            summary,
            prepared.config,
        ))
    })?;
    let result = PyDict::new(py);
    result.set_item("radio_map", json_object(py, &collection)?)?;
    result.set_item("coverage", coverage_columns(py, &coverage)?)?;
    result.set_item("walks", json_object(py, &summary.walks)?)?;
    result.set_item("summary", json_object(py, &summary)?)?;
    result.set_item("config", json_object(py, &config)?)?;
    report.emit(py)?;
    Ok(result)
}

/// The walks' tables parsed: steps (with whether they carry `dz`, where the plan has
/// several levels and the walks may change floor) and WiFi logs.
fn read_walks(
    tables: &[WalkTables],
    plan: &footslam::map::FloorPlan,
    one_floor: bool,
) -> footslam::Result<Vec<SurveyWalkRequest>> {
    tables
        .iter()
        .map(|w| {
            let log = w.wifi.wifi_log()?;
            let several = plan.levels().len() > 1 && !one_floor;
            Ok(SurveyWalkRequest {
                steps: Named::new(w.steps.steps()?, w.steps.label()),
                steps_have_dz: !several || w.steps.has_column("dz")?,
                wifi: Named::new(log.scans, w.wifi.label()),
                duplicate_readings: log.duplicate_readings,
                start: w.start,
            })
        })
        .collect()
}

/// The radio maps to merge, in `frame`.
fn earlier_maps(
    docs: &[Document],
    frame: footslam::geometry::LocalFrame,
) -> footslam::Result<Vec<footslam::map::RadioMap>> {
    docs.iter()
        .map(|d| d.radio_map(Some(frame)).map(|(m, _)| m))
        .collect()
}

/// The coverage table (the paper's Table 1) as columns.
fn coverage_columns<'py>(py: Python<'py>, c: &[Coverage]) -> PyResult<Bound<'py, PyDict>> {
    columns(
        py,
        vec![
            (
                "granularity_m",
                Column::F64(c.iter().map(|c| c.granularity).collect()),
            ),
            (
                "cells",
                Column::I64(
                    c.iter()
                        .map(|c| i64::try_from(c.cells).unwrap_or(i64::MAX))
                        .collect(),
                ),
            ),
            ("coverage", Column::F64(c.iter().map(|c| c.share).collect())),
            (
                "mean_scans",
                Column::F64(c.iter().map(|c| c.mean_scans).collect()),
            ),
        ],
    )
}
