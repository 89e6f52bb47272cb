//! `footslam.radio_map`: `learn`'s radio stage for walks learned apart (the batch runner's
//! last step per building): the walks' scans placed on their learned tracks and added to the
//! cells of the plan learned from the merged map. `footslam.fingerprint`: each scan placed
//! by a radio map alone.

use crate::inputs::{self, Document};
use crate::outputs::{Column, columns, json_object};
use crate::tables::{WIFI, table};
use crate::{Reporter, detached, fail, py_error};
use footslam::filter::{FingerprintConfig, PathPoint};
use footslam::io::floor_plan_geojson::floor_plan_to_geojson;
use footslam::io::radio_map_geojson::radio_map_to_geojson;
use footslam::map::{CellConfig, PlanConfig};
use footslam::pipeline::{
    FingerprintRequest, LearnRadioReport, Named, learned_radio_map, run_fingerprint,
    scans_off_clock,
};
use footslam::sensor::WifiScan;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One column of a track dict as floats.
fn column(track: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<Vec<f64>> {
    let values = track
        .get_item(name)
        .map_err(|_| fail(format!("{what}: no `{name}` column")))?;
    let values = match values.call_method0("tolist") {
        Ok(list) => list,
        Err(_) => values,
    };
    values
        .extract::<Vec<f64>>()
        .map_err(|_| fail(format!("{what}: column `{name}` is not a list of numbers")))
}

/// A radio map with no drawn plan from walks learned apart (``footslam::pipeline::
/// learned_radio_map``): each walk's scans go to the cell of its learned track's step at or
/// after them, on the plan learned from ``map``; ε is calibrated on the walks' own scans.
/// With the merged map and the tracks of :func:`learn_one` (after the FeetSLAM passes) it
/// gives :func:`learn`'s ``radio_map`` for the same walks.
///
/// Args:
///     map: the merged map of the walks (GeoJSON dict or path), in the tracks' frame.
///     tracks: per walk with WiFi, its learned track (a dict with ``t``, ``x``, ``y``
///         columns, as ``learn_one``'s ``track``).
///     wifi: per walk, in the same order, its WiFi log (path, DataFrame or dict of columns
///         ``t, bssid, rssi``), on the track's clock.
///     cell: radio-map cell granularity, metres (default 3).
///
/// Returns:
///     dict: ``radio_map`` (GeoJSON, as ``radiomap.geojson``), ``plan`` (the learned plan
///     its cells lie on) and ``summary`` (cells, coverage, access points, ε).
///
/// Raises:
///     FootslamError: a map too small to cut cells from, a log on another clock, bad data.
///     FileNotFoundError: a path names no file.
#[pyfunction]
#[pyo3(signature = (map, tracks, wifi, *, cell=None))]
pub(crate) fn radio_map<'py>(
    py: Python<'py>,
    map: &Bound<'py, PyAny>,
    tracks: &Bound<'py, PyAny>,
    wifi: &Bound<'py, PyAny>,
    cell: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let map_doc: Document = inputs::document(map, "map", "map")?;
    let tracks = inputs::as_list(tracks)?.ok_or_else(|| fail("tracks: expected a list"))?;
    let logs = inputs::as_list(wifi)?.ok_or_else(|| fail("wifi: expected a list"))?;
    if tracks.len() != logs.len() || tracks.is_empty() {
        return Err(fail(format!(
            "{} tracks and {} WiFi logs: give one log per track, at least one",
            tracks.len(),
            logs.len()
        )));
    }
    let level = PlanConfig::default().level;
    let mut paths: Vec<Vec<PathPoint>> = Vec::with_capacity(tracks.len());
    let mut logs_read: Vec<Vec<WifiScan>> = Vec::with_capacity(tracks.len());
    for (i, (track, log)) in tracks.iter().zip(&logs).enumerate() {
        let what = format!("tracks[{i}]");
        let (t, x, y) = (
            column(track, "t", &what)?,
            column(track, "x", &what)?,
            column(track, "y", &what)?,
        );
        if t.len() != x.len() || t.len() != y.len() || t.is_empty() {
            return Err(fail(format!("{what}: columns t, x, y of one length > 0")));
        }
        let scans = table(log, &WIFI, &format!("wifi[{i}]"))?
            .wifi()
            .map_err(py_error)?;
        if let Some(problem) = scans_off_clock(&scans, t[0], t[t.len() - 1]) {
            return Err(fail(format!("wifi[{i}]: {problem}")));
        }
        let path = t
            .iter()
            .zip(&x)
            .zip(&y)
            .map(|((&t, &x), &y)| (t, x, y, level))
            .collect();
        paths.push(path);
        logs_read.push(scans);
    }
    let cells = CellConfig {
        granularity: cell.unwrap_or(CellConfig::default().granularity),
        ..CellConfig::default()
    };
    let (radio, frame) = detached(py, None, || {
        cells.validate().map_err(py_error)?;
        let stored = map_doc.stored_map().map_err(py_error)?;
        let walks: Vec<(Vec<PathPoint>, &[WifiScan])> = paths
            .into_iter()
            .zip(&logs_read)
            .map(|(path, scans)| (path, scans.as_slice()))
            .collect();
        let radio = learned_radio_map(&walks, &stored.map, &cells).map_err(py_error)?;
        Ok((radio, stored.frame))
    })?;
    let scans = logs_read.iter().map(Vec::len).collect();
    let summary = LearnRadioReport::new(scans, &radio, &cells);
    let result = PyDict::new(py);
    result.set_item(
        "radio_map",
        json_object(py, &radio_map_to_geojson(&radio.survey.map, &frame))?,
    )?;
    result.set_item(
        "plan",
        json_object(py, &floor_plan_to_geojson(&radio.plan.plan, &frame))?,
    )?;
    result.set_item("summary", json_object(py, &summary)?)?;
    Ok(result)
}

/// Places each WiFi scan by the radio map alone (``footslam fingerprint``; weighted
/// k-nearest fingerprints): the baseline that tracking with the radio map should beat.
///
/// Args:
///     radiomap: the radio map (path or GeoJSON dict, ``radiomap.geojson`` of ``survey``
///         or ``learn --wifi``).
///     wifi: the WiFi log (``t,bssid,rssi[,ssid,freq]``): a CSV path, a pandas DataFrame or
///         a dict of 1-D arrays.
///     k: nearest cells averaged (overrides the configuration's).
///     config: fingerprint configuration: a dict with the keys of ``config.json``, or a TOML
///         or JSON file.
///
/// Returns:
///     dict: ``track`` — columns ``t, x, y, level, ndist`` (one row per scan placed, local
///     metres in the map's frame; ``ndist`` the distance to the nearest cell, dBm);
///     ``summary`` — as ``summary.json``; ``config`` — as ``config.json``.
///
/// Raises:
///     FootslamError: a log of another building than the map, bad configuration.
///     FileNotFoundError: a path names no file.
#[pyfunction]
#[pyo3(signature = (radiomap, wifi, *, k=None, config=None))]
pub(crate) fn fingerprint<'py>(
    py: Python<'py>,
    radiomap: &Bound<'py, PyAny>,
    wifi: &Bound<'py, PyAny>,
    k: Option<usize>,
    config: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let config: FingerprintConfig = inputs::config(config)?;
    let map_doc = inputs::document(radiomap, "radio map", "radiomap")?;
    let log = table(wifi, &WIFI, "wifi")?;
    let report = Reporter::default();
    let job = detached(py, None, || {
        let read = || -> footslam::Result<FingerprintRequest> {
            let (map, _) = map_doc.radio_map(None)?;
            let log_read = log.wifi_log()?;
            Ok(FingerprintRequest {
                map: Named::new(map, map_doc.label()),
                wifi: Named::new(log_read.scans, log.label()),
                duplicate_readings: log_read.duplicate_readings,
                config,
                k,
            })
        };
        run_fingerprint(read().map_err(py_error)?, &report).map_err(py_error)
    })?;
    report.emit(py)?;
    let f = &job.fixes;
    let result = PyDict::new(py);
    result.set_item(
        "track",
        columns(
            py,
            vec![
                ("t", Column::F64(f.iter().map(|p| p.t).collect())),
                ("x", Column::F64(f.iter().map(|p| p.x).collect())),
                ("y", Column::F64(f.iter().map(|p| p.y).collect())),
                (
                    "level",
                    Column::I64(f.iter().map(|p| i64::from(p.level)).collect()),
                ),
                ("ndist", Column::F64(f.iter().map(|p| p.ndist).collect())),
            ],
        )?,
    )?;
    result.set_item("summary", json_object(py, &job.report)?)?;
    result.set_item("config", json_object(py, &job.config)?)?;
    Ok(result)
}
