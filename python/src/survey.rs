//! `footslam.survey`: a WiFi radio map from walks tracked on a known floor plan, as
//! `footslam survey` makes it.

use crate::checks::{check_height_changes, read_scans};
use crate::inputs;
use crate::outputs::{Column, columns, json_object};
use crate::tables::{self, STEPS, Table, WIFI};
use crate::{Reporter, detached, fail, py_error, with_context};
use footslam::filter::StartPose;
use footslam::io::radio_map_geojson::radio_map_to_geojson;
use footslam::map::FloorTopology;
use footslam::model::wifi_distance::held_out_quantiles;
use footslam::pipeline::{SurveyConfig, SurveyInput, SurveyWalk};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use serde_json::json;

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
    let mut config: SurveyConfig = inputs::config(config)?;
    if let Some(s) = seed {
        config.tracker.seed = s;
    }
    if let Some(s) = inputs::start(start, "start")? {
        config.tracker.start = Some(s);
    }
    if let Some(g) = cell {
        config.cells.granularity = g;
    }
    config.validate().map_err(py_error)?;
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
    if tables.is_empty() && earlier_docs.is_empty() {
        return Err(fail(
            "nothing to survey: give walks (steps and WiFi log pairs) or radio maps to merge",
        ));
    }
    let origin = inputs::origin(origin)?;
    let report = Reporter::new(progress)?;
    let (collection, surveyed_walks, coverage, summary) = detached(py, threads, || {
        let plan_label = plan_doc.label();
        let (plan, frame) = plan_doc.floor_plan(origin).map_err(py_error)?;
        let topology = FloorTopology::build(&plan, &config.tracker.topology).map_err(
            with_context(format!("{plan_label}: not a usable floor plan")),
        )?;
        let mut walks = Vec::with_capacity(tables.len());
        for w in &tables {
            let trace = w.steps.steps().map_err(py_error)?;
            check_height_changes(&w.steps, &plan_label, &plan, one_floor)?;
            let (scans, warning) = read_scans(&w.wifi, &trace)?;
            if let Some(w) = warning {
                report.push(w);
            }
            walks.push(SurveyWalk {
                trace,
                scans,
                start: w.start,
            });
        }
        let earlier = earlier_docs
            .iter()
            .map(|d| d.radio_map(Some(frame)).map(|(m, _)| m))
            .collect::<footslam::Result<Vec<_>>>()
            .map_err(py_error)?;
        let input = SurveyInput {
            plan: &plan,
            topology: &topology,
            walks: &walks,
            earlier: &earlier,
        };
        let surveyed = footslam::pipeline::survey(&input, &config, &report).map_err(py_error)?;
        let map = &surveyed.map;
        let (share, mean) = map.coverage();
        let summary = json!({
            "quality": surveyed.quality,
            "cells": surveyed.cells.cells().len(),
            "rooms": surveyed.cells.rooms().len(),
            "granularity_m": config.cells.granularity,
            "coverage": share,
            "mean_scans_per_covered_cell": mean,
            "epsilon": map.epsilon,
            "epsilon_sqrt": map.epsilon_sqrt,
            "ndist_leave_one_out_p50_p90_p99_max": held_out_quantiles(&surveyed.held),
            "access_points": map.access_points().len(),
            "origin": frame,
            "version": env!("CARGO_PKG_VERSION"),
        });
        let surveyed_walks: Vec<serde_json::Value> = walks
            .iter()
            .zip(&surveyed.walks)
            .map(|(walk, done)| {
                json!({
                    "start": done.start,
                    "steps": walk.trace.len(),
                    "scans": walk.scans.len(),
                    "steps_to_localise": done.steps_to_localise,
                    "steps_placed": done.steps_placed,
                    "scans_added": done.scans_added,
                    "scans_skipped": done.scans_skipped,
                    "quality": done.quality,
                })
            })
            .collect();
        Ok((
            radio_map_to_geojson(map, &frame),
            surveyed_walks,
            surveyed.coverage,
            summary,
        ))
    })?;
    let result = PyDict::new(py);
    result.set_item("radio_map", json_object(py, &collection)?)?;
    let c = &coverage;
    result.set_item(
        "coverage",
        columns(
            py,
            vec![
                (
                    "granularity_m",
                    Column::F64(c.iter().map(|c| c.granularity).collect()),
                ),
                (
                    "cells",
                    Column::I64(c.iter().map(|c| c.cells as i64).collect()),
                ),
                ("coverage", Column::F64(c.iter().map(|c| c.share).collect())),
                (
                    "mean_scans",
                    Column::F64(c.iter().map(|c| c.mean_scans).collect()),
                ),
            ],
        )?,
    )?;
    result.set_item("walks", json_object(py, &surveyed_walks)?)?;
    result.set_item("summary", json_object(py, &summary)?)?;
    result.set_item("config", json_object(py, &config)?)?;
    report.emit(py)?;
    Ok(result)
}
