//! `footslam.learn`, `footslam.learn_one` and `footslam.feetslam_passes`: FootSLAM on one
//! walk or a batch, as `footslam learn` runs it, and a batch fanned out walk by walk.

use crate::inputs::{self, Document};
use crate::learn_inputs::{Args, read_request};
use crate::learn_outputs::{learn_out, walk_out};
use crate::outputs::json_object;
use crate::{Reporter, detached, py_error};
use footslam::filter::StartPose;
use footslam::pipeline::{LearnConfig, LearnWalk, prepare_learn};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Learns the map of one walk or a batch of walks (FootSLAM; ``footslam learn``).
///
/// Args:
///     steps: one walk's step trace — a CSV path, a pandas DataFrame or a dict of 1-D
///         arrays with columns ``t,length,dheading[,dz][,heading]`` (s, m, rad
///         counter-clockwise, m, rad from east; NaN in ``dz``/``heading`` = not given) — or
///         a list of them: a batch learned in parallel (walk ``i`` has seed ``seed + i``;
///         walks with known starts share one frame and run FeetSLAM passes).
///     gps: GPS fixes (``t,lat,lon[,accuracy]`` on the steps' clock, or a GPX file); for a
///         batch a list with one entry (or None) per walk.
///     wifi: the walk's WiFi log (``t,bssid,rssi[,ssid,freq]``; its scans weigh the
///         particles inside the filter and make a radio map on the plan learned from the
///         run's map); for a batch one per walk.
///     start: the known start: ``"X,Y[,HEADING[,LEVEL]]"``, ``(x, y[, heading[, level]])``
///         or a dict (metres in the local frame, radians from east); for a batch one per
///         walk.
///     prior_map: a map learned earlier (path or GeoJSON dict): its counts become prior
///         pseudo-counts; its origin the default origin.
///     outline: the building's rough outline (GeoJSON Polygon, Feature or collection of
///         one): crossing it becomes improbable.
///     origin: ``(lat, lon)`` of the local frame, degrees (default: the prior map's, else
///         the first GPS fix, else 0, 0).
///     config: FootSLAM configuration: a dict with the keys of ``config.json``, or a TOML or
///         JSON file; unknown keys are errors.
///     seed, particles, hex_radius, prior_weight: override the configuration.
///     ignore_heading: ignore the steps' absolute ``heading`` column.
///     cell: radio-map cell granularity with WiFi, metres (default 3).
///     gps_t0: UTC time (Unix seconds) of the steps' ``t = 0`` for GPX files.
///     threads: worker threads (default: one per core); results do not depend on it.
///     progress: a callable ``progress(stage, done, total)`` told of the run's progress
///         from its start (``done`` 0) to its end (``done == total``), at most a few hundred
///         times a stage — a tqdm bar or a log line (default: none). An exception it
///         raises is raised when the run is over.
///
/// Returns:
///     dict: ``walks`` — per walk a dict with ``track`` (columns ``t, x, y, z, level,
///     spread_m``: the whole-walk answer, metres in the local frame, and how far the final
///     paths spread about it), ``map`` (GeoJSON as ``map.geojson``),
///     ``plan`` (its walkable plan as ``plan.geojson``, or None when too small),
///     ``merged_with_prior`` (with a prior map), ``summary`` and ``config``; ``merged`` —
///     a batch's merged map (GeoJSON, or None); ``radio_map`` and ``radio_plan`` — with
///     WiFi, the radio map (as ``radiomap.geojson``) and the learned plan it lies on;
///     ``summary`` — the run's report, as ``summary.json`` (one walk's figures at the top
///     level, a batch's under ``walks``); ``config`` — the configuration the run ran with,
///     as ``config.json`` (each walk's own in its entry of ``walks``).
///
/// Raises:
///     FootslamError: bad data or configuration, or inputs that do not belong together
///         (the command line's message).
///     FileNotFoundError: a path names no file.
///     TypeError: an input of the wrong type, or a column that is not numbers.
#[pyfunction]
#[pyo3(signature = (
    steps, *, gps=None, wifi=None, start=None, prior_map=None, outline=None, origin=None,
    config=None, seed=None, particles=None, hex_radius=None, prior_weight=None,
    ignore_heading=false, cell=None, gps_t0=None, threads=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn learn<'py>(
    py: Python<'py>,
    steps: &Bound<'py, PyAny>,
    gps: Option<&Bound<'py, PyAny>>,
    wifi: Option<&Bound<'py, PyAny>>,
    start: Option<&Bound<'py, PyAny>>,
    prior_map: Option<&Bound<'py, PyAny>>,
    outline: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    config: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    particles: Option<&Bound<'py, PyAny>>,
    hex_radius: Option<f64>,
    prior_weight: Option<f64>,
    ignore_heading: bool,
    cell: Option<f64>,
    gps_t0: Option<f64>,
    threads: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let seed = crate::int_arg("seed", seed, u64::MAX)?;
    let particles = crate::int_arg("particles", particles, 100_000_000)?.map(|n| n as usize);
    let threads = crate::int_arg("threads", threads, 1 << 20)?.map(|n| n as usize);
    let args = Args {
        steps,
        gps,
        wifi,
        start,
        prior_map,
        outline,
        origin,
        config,
        seed,
        particles,
        hex_radius,
        prior_weight,
        ignore_heading,
        cell,
        gps_t0,
    };
    let started = std::time::Instant::now();
    let request = read_request(py, &args, false)?;
    let report = Reporter::new(progress)?;
    let out = detached(py, threads, || {
        let prepared = prepare_learn(request, &report).map_err(py_error)?;
        let learned = prepared.run(&report).map_err(py_error)?;
        Ok(learn_out(&prepared, &learned, started))
    })?;
    let result = PyDict::new(py);
    let walks = out
        .walks
        .iter()
        .map(|w| w.to_python(py))
        .collect::<PyResult<Vec<_>>>()?;
    result.set_item("walks", walks)?;
    result.set_item("merged", json_object(py, &out.merged)?)?;
    result.set_item("radio_map", json_object(py, &out.radio_map)?)?;
    result.set_item("radio_plan", json_object(py, &out.radio_plan)?)?;
    result.set_item("summary", json_object(py, &out.summary)?)?;
    result.set_item("config", json_object(py, &out.config)?)?;
    report.emit(py)?;
    Ok(result)
}

/// Learns walk ``index`` of a batch alone: one task of a batch spread over processes or
/// machines (the library's ``pipeline::learn_one``).
///
/// The same computation as that walk's in :func:`learn` (seed ``seed + index``, the run's
/// frame, outline and prior map), so a batch fanned out walk by walk — and, for walks with
/// known starts, pass by pass with ``others`` from :func:`others_map` of the previous
/// pass's maps (:func:`feetslam_passes` passes) — gives the maps and paths :func:`learn`
/// gives.
///
/// Args:
///     steps: this walk's steps (a path, DataFrame or dict of arrays; not a list).
///     index: the walk's 0-based number in the batch.
///     others: in a FeetSLAM pass, the merged map of the other walks' previous pass
///         (GeoJSON dict or path), as prior pseudo-counts.
///     gps, wifi, start: this walk's GPS fixes, WiFi log and known start.
///     origin: the batch's frame ``(lat, lon)``: give it (the batch's default frame comes
///         from the first GPS fix of any walk, which a task alone cannot see).
///     Other arguments: as :func:`learn`.
///
/// Returns:
///     dict: the walk's ``track``, ``map``, ``plan``, ``summary`` and ``config``, as an
///     entry of :func:`learn`'s ``walks``.
///
/// Raises:
///     FootslamError, FileNotFoundError, TypeError: as :func:`learn`.
#[pyfunction]
#[pyo3(signature = (
    steps, index, *, others=None, gps=None, wifi=None, start=None, prior_map=None,
    outline=None, origin=None, config=None, seed=None, particles=None, hex_radius=None,
    prior_weight=None, ignore_heading=false, gps_t0=None, threads=None
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn learn_one<'py>(
    py: Python<'py>,
    steps: &Bound<'py, PyAny>,
    index: usize,
    others: Option<&Bound<'py, PyAny>>,
    gps: Option<&Bound<'py, PyAny>>,
    wifi: Option<&Bound<'py, PyAny>>,
    start: Option<&Bound<'py, PyAny>>,
    prior_map: Option<&Bound<'py, PyAny>>,
    outline: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    config: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    particles: Option<&Bound<'py, PyAny>>,
    hex_radius: Option<f64>,
    prior_weight: Option<f64>,
    ignore_heading: bool,
    gps_t0: Option<f64>,
    threads: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let seed = crate::int_arg("seed", seed, u64::MAX)?;
    let particles = crate::int_arg("particles", particles, 100_000_000)?.map(|n| n as usize);
    let threads = crate::int_arg("threads", threads, 1 << 20)?.map(|n| n as usize);
    let args = Args {
        steps,
        gps,
        wifi,
        start,
        prior_map,
        outline,
        origin,
        config,
        seed,
        particles,
        hex_radius,
        prior_weight,
        ignore_heading,
        cell: None,
        gps_t0,
    };
    let others_doc = others
        .filter(|o| !o.is_none())
        .map(|o| inputs::document(o, "map", "others"))
        .transpose()?;
    let request = read_request(py, &args, true)?;
    let report = Reporter::default();
    let out = detached(py, threads, || {
        let others = others_doc
            .as_ref()
            .map(Document::stored_map)
            .transpose()
            .map_err(py_error)?;
        let prepared = prepare_learn(request, &report).map_err(py_error)?;
        let others = others.as_ref().map(|m| &m.map);
        let run = prepared.run_one(0, index, others, None).map_err(py_error)?;
        Ok(walk_out(&prepared, 0, &run))
    })?;
    report.emit(py)?;
    out.to_python(py)
}

/// FeetSLAM passes after the first for a batch (the library's
/// ``pipeline::feetslam_passes``): the configuration's ``iterations`` for a batch of
/// several walks that all have known starts (one frame), else 0.
///
/// Args:
///     walks: the number of walks in the batch.
///     known_starts: whether every walk has a known start.
///     config: FootSLAM configuration (dict or file), as :func:`learn`'s.
///
/// Returns:
///     int: the passes after the first.
#[pyfunction]
#[pyo3(signature = (walks, *, known_starts, config=None))]
pub(crate) fn feetslam_passes(
    walks: usize,
    known_starts: bool,
    config: Option<&Bound<'_, PyAny>>,
) -> PyResult<u32> {
    let config: LearnConfig = inputs::config(config)?;
    config.validate().map_err(py_error)?;
    let start = known_starts.then_some(StartPose {
        x: 0.0,
        y: 0.0,
        heading: None,
        level: None,
    });
    let walks: Vec<LearnWalk> = (0..walks)
        .map(|_| LearnWalk {
            start,
            ..LearnWalk::default()
        })
        .collect();
    Ok(footslam::pipeline::feetslam_passes(&walks, &config))
}
