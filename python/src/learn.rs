//! `footslam.learn`, `footslam.learn_one` and `footslam.feetslam_passes`: FootSLAM on one
//! walk or a batch, as `footslam learn` runs it, and a batch fanned out walk by walk.

use crate::checks::{check_same_grid, path_length, read_fixes, read_scans};
use crate::inputs::{self, Document, GPS, STEPS, Table, WIFI};
use crate::outputs::{Column, columns, json_object};
use crate::survey::held_out_quantiles;
use crate::{Warnings, detached, py_error};
use footslam::filter::{FootSlamConfig, StartPose};
use footslam::geometry::{HexGrid, LocalFrame};
use footslam::io::floor_plan_geojson::floor_plan_to_geojson;
use footslam::io::map_geojson::{StoredMap, walks_map_to_geojson};
use footslam::io::radio_map_geojson::radio_map_to_geojson;
use footslam::map::{CellConfig, PlanConfig, walkable_plan};
use footslam::pipeline::{LearnInput, LearnWalk, Learned, WalkRun, default_frame};
use geojson::FeatureCollection;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::json;

/// What `learn` and `learn_one` read from their arguments, as `footslam learn` reads its
/// flags and files.
struct Inputs {
    config: FootSlamConfig,
    walks: Vec<LearnWalk>,
    /// Each walk's steps, as messages name them.
    labels: Vec<String>,
    prior_map: Option<StoredMap>,
    frame: LocalFrame,
    outline: Option<geo::Polygon<f64>>,
    cells: CellConfig,
}

/// The arguments `learn` and `learn_one` share.
struct Args<'a, 'py> {
    steps: &'a Bound<'py, PyAny>,
    gps: Option<&'a Bound<'py, PyAny>>,
    wifi: Option<&'a Bound<'py, PyAny>>,
    start: Option<&'a Bound<'py, PyAny>>,
    prior_map: Option<&'a Bound<'py, PyAny>>,
    outline: Option<&'a Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    config: Option<&'a Bound<'py, PyAny>>,
    seed: Option<u64>,
    particles: Option<usize>,
    hex_radius: Option<f64>,
    prior_weight: Option<f64>,
    ignore_heading: bool,
    cell: Option<f64>,
    gps_t0: Option<f64>,
}

/// The tables of the walks and their start poses, converted while the GIL is held.
struct WalkTables {
    steps: Vec<Table>,
    gps: Vec<Option<Table>>,
    wifi: Vec<Option<Table>>,
    starts: Vec<Option<StartPose>>,
}

impl Args<'_, '_> {
    /// The configuration: `config`'s (or the defaults) with the keyword overrides, checked.
    fn learn_config(&self) -> PyResult<FootSlamConfig> {
        let mut config: FootSlamConfig = inputs::config(self.config)?;
        if let Some(n) = self.particles {
            config.particles = n;
        }
        if let Some(s) = self.seed {
            config.seed = s;
        }
        if let Some(r) = self.hex_radius {
            config.hex_radius = r;
        }
        if let Some(w) = self.prior_weight {
            config.prior_weight = w;
        }
        if self.ignore_heading {
            config.heading.enabled = false;
        }
        config.validate().map_err(py_error)?;
        Ok(config)
    }

    /// The walks' tables: `steps` one walk's or a list of walks', with `gps`, `wifi` and
    /// `start` one per walk.
    fn tables(&self, one_walk_only: bool) -> PyResult<WalkTables> {
        let list = if one_walk_only {
            None
        } else {
            inputs::as_list(self.steps)?
        };
        let batch = list.is_some();
        let steps_objects = list.unwrap_or_else(|| vec![self.steps.clone()]);
        if steps_objects.is_empty() {
            return Err(crate::fail("steps: an empty list of walks"));
        }
        let n = steps_objects.len();
        let name = |what: &str, i: usize| {
            if batch {
                format!("{what}[{i}]")
            } else {
                what.to_owned()
            }
        };
        let steps = steps_objects
            .iter()
            .enumerate()
            .map(|(i, o)| inputs::table(o, &STEPS, &name("steps", i)))
            .collect::<PyResult<Vec<_>>>()?;
        let optional_tables = |obj, what: &str, kind| -> PyResult<Vec<Option<Table>>> {
            inputs::per_walk(obj, n, batch, what)?
                .iter()
                .enumerate()
                .map(|(i, o)| {
                    o.as_ref()
                        .map(|o| inputs::table(o, kind, &name(what, i)))
                        .transpose()
                })
                .collect()
        };
        let gps = optional_tables(self.gps, "gps", &GPS)?;
        let wifi = optional_tables(self.wifi, "wifi", &WIFI)?;
        let starts = inputs::per_walk(self.start, n, batch, "start")?
            .iter()
            .enumerate()
            .map(|(i, o)| inputs::start(o.as_ref(), &name("start", i)))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(WalkTables {
            steps,
            gps,
            wifi,
            starts,
        })
    }
}

impl WalkTables {
    /// Reads the walks, each file and its time span checked as `footslam learn` checks them.
    fn read(self, gps_t0: Option<f64>) -> PyResult<(Vec<LearnWalk>, Vec<String>)> {
        let mut walks = Vec::with_capacity(self.steps.len());
        let mut labels = Vec::with_capacity(self.steps.len());
        for (((steps, gps), wifi), start) in self
            .steps
            .iter()
            .zip(&self.gps)
            .zip(&self.wifi)
            .zip(self.starts)
        {
            let trace = steps.steps().map_err(py_error)?;
            let fixes = match gps {
                Some(t) => read_fixes(t, gps_t0, &trace)?,
                None => Vec::new(),
            };
            let scans = match wifi {
                Some(t) => read_scans(t, &trace)?,
                None => Vec::new(),
            };
            labels.push(steps.label());
            walks.push(LearnWalk {
                trace,
                fixes,
                scans,
                start,
            });
        }
        Ok((walks, labels))
    }
}

/// Reads everything `learn` needs, in the command line's order: the configuration, the
/// walks, the cells, the prior map, the frame and the outline.
fn read_inputs(py: Python<'_>, args: &Args<'_, '_>, one_walk_only: bool) -> PyResult<Inputs> {
    let config = args.learn_config()?;
    let tables = args.tables(one_walk_only)?;
    let prior_doc = args
        .prior_map
        .filter(|o| !o.is_none())
        .map(|o| inputs::document(o, "prior map", "prior_map"))
        .transpose()?;
    let outline_doc = args
        .outline
        .filter(|o| !o.is_none())
        .map(|o| inputs::document(o, "outline", "outline"))
        .transpose()?;
    let origin = inputs::origin(args.origin)?;
    let gps_t0 = args.gps_t0;
    let cells = CellConfig {
        granularity: args.cell.unwrap_or(CellConfig::default().granularity),
        ..CellConfig::default()
    };
    detached(py, None, move || {
        let (walks, labels) = tables.read(gps_t0)?;
        cells.validate().map_err(py_error)?;
        let prior_map = prior_doc
            .as_ref()
            .map(Document::stored_map)
            .transpose()
            .map_err(py_error)?;
        let frame = origin.unwrap_or_else(|| default_frame(prior_map.as_ref(), &walks));
        let outline = outline_doc
            .as_ref()
            .map(|d| d.outline(&frame))
            .transpose()
            .map_err(py_error)?;
        if let (Some(stored), Some(doc)) = (&prior_map, &prior_doc) {
            let radius = stored.map.radius;
            check_same_grid(
                &doc.label(),
                radius,
                &stored.frame,
                config.hex_radius,
                &frame,
            )?;
        }
        Ok(Inputs {
            config,
            walks,
            labels,
            prior_map,
            frame,
            outline,
            cells,
        })
    })
}

impl Inputs {
    fn input(&self) -> LearnInput<'_> {
        LearnInput {
            walks: &self.walks,
            frame: self.frame,
            outline: self.outline.as_ref(),
            prior_map: self.prior_map.as_ref(),
            cells: self.cells,
        }
    }
}

/// One learned walk, ready for Python.
struct WalkOut {
    track: Vec<(f64, f64, f64, f64, i32)>,
    map: FeatureCollection,
    plan: Option<FeatureCollection>,
    merged_with_prior: Option<FeatureCollection>,
    summary: serde_json::Value,
    config: FootSlamConfig,
}

/// The outputs of one walk, as `footslam learn` writes them (`track.geojson`'s points,
/// `map.geojson`, `plan.geojson`, `summary.json`'s figures and `config.json`).
fn walk_out(walk: &LearnWalk, label: &str, run: &WalkRun, frame: &LocalFrame) -> WalkOut {
    let (config, estimate, filter) = (&run.config, &run.estimate, &run.filter);
    let steps = walk.trace.steps();
    let track = steps
        .iter()
        .zip(&estimate.path)
        .zip(&estimate.levels)
        .map(|((s, p), &level)| (s.t, p.x, p.y, estimate.map.level_height(level), level))
        .collect();
    let learned = walkable_plan(&estimate.map, &PlanConfig::default()).ok();
    let ess = filter.ess_history();
    let runtime = run.runtime_s;
    let summary = json!({
        "steps_file": label,
        "steps_with_heading": walk.trace.with_heading(),
        "headings_used": filter.headings_used(),
        "particles": config.particles,
        "steps": steps.len(),
        "seed": config.seed,
        "filter_runtime_s": runtime,
        "particle_steps_per_s": (config.particles * steps.len()) as f64 / runtime.max(1e-9),
        "final_effective_sample_size": filter.effective_sample_size(),
        "min_effective_sample_size": ess.iter().copied().fold(f64::INFINITY, f64::min),
        "resamplings": filter.resamplings(),
        "best_particle": estimate.index,
        "best_particle_weight": estimate.weight,
        "best_path_log_likelihood": estimate.path_log_likelihood,
        "hexagons": estimate.map.cells.len(),
        "levels": estimate.map.levels.len().max(1),
        "map_area_m2": estimate.map.cells.len() as f64
            * HexGrid::new(config.hex_radius).cell_area(),
        "path_length_m": path_length(estimate.path.iter().map(|p| (p.x, p.y))),
        "gps_fixes": walk.fixes.len(),
        "gps_fixes_used": filter.gps_fixes_used(),
        "prior_offset_m": estimate.prior_offset,
        "heading": {
            "start_source": run.start_source,
            "start_deg": config.start.heading.to_degrees(),
            "start_sigma_deg": config.start_heading_sigma.min(std::f64::consts::PI).to_degrees(),
            "final_sigma_deg": filter.heading_spread().to_degrees(),
        },
        "walkable_plan_m2": learned.as_ref().map(|l| l.area_m2),
    });
    WalkOut {
        track,
        map: walks_map_to_geojson(&estimate.map, frame, 1),
        plan: learned.map(|l| floor_plan_to_geojson(&l.plan, frame)),
        merged_with_prior: None,
        summary,
        config: config.clone(),
    }
}

impl WalkOut {
    fn to_python<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let t = &self.track;
        d.set_item(
            "track",
            columns(
                py,
                vec![
                    ("t", Column::F64(t.iter().map(|p| p.0).collect())),
                    ("x", Column::F64(t.iter().map(|p| p.1).collect())),
                    ("y", Column::F64(t.iter().map(|p| p.2).collect())),
                    ("z", Column::F64(t.iter().map(|p| p.3).collect())),
                    (
                        "level",
                        Column::I64(t.iter().map(|p| i64::from(p.4)).collect()),
                    ),
                ],
            )?,
        )?;
        d.set_item("map", json_object(py, &self.map)?)?;
        d.set_item("plan", json_object(py, &self.plan)?)?;
        if let Some(m) = &self.merged_with_prior {
            d.set_item("merged_with_prior", json_object(py, m)?)?;
        }
        d.set_item("summary", json_object(py, &self.summary)?)?;
        d.set_item("config", json_object(py, &self.config)?)?;
        Ok(d)
    }
}

/// Everything `learn` gives, ready for Python.
struct LearnOut {
    walks: Vec<WalkOut>,
    merged: Option<FeatureCollection>,
    radio_map: Option<FeatureCollection>,
    radio_plan: Option<FeatureCollection>,
    summary: serde_json::Value,
}

fn learn_out(inputs: &Inputs, learned: &Learned) -> LearnOut {
    let frame = &inputs.frame;
    let mut walks: Vec<WalkOut> = inputs
        .walks
        .iter()
        .zip(&inputs.labels)
        .zip(&learned.walks)
        .map(|((walk, label), run)| walk_out(walk, label, run, frame))
        .collect();
    let combined = &learned.combined;
    if let Some(stored) = &inputs.prior_map {
        for (out, merged) in walks.iter_mut().zip(&combined.merged_with_prior) {
            out.merged_with_prior = Some(walks_map_to_geojson(merged, frame, stored.walks + 1));
        }
    }
    let merged = combined
        .merged
        .as_ref()
        .map(|m| walks_map_to_geojson(m, frame, learned.walks.len() as u32));
    let radio = combined.radio.as_ref().map(|radio| {
        let survey = &radio.survey;
        let map = &survey.map;
        let (coverage, per_cell) = map.coverage();
        json!({
            "granularity_m": inputs.cells.granularity,
            "cells": survey.cells.cells().len(),
            "rooms": survey.cells.rooms().len(),
            "scans": inputs.walks.iter().map(|w| w.scans.len()).collect::<Vec<_>>(),
            "scans_added": survey.counts.iter().map(|c| c.added).collect::<Vec<_>>(),
            "scans_skipped": survey.counts.iter().map(|c| c.skipped).collect::<Vec<_>>(),
            "coverage": coverage,
            "mean_scans_per_covered_cell": per_cell,
            "access_points": map.access_points().len(),
            "epsilon": map.epsilon,
            "epsilon_sqrt": map.epsilon_sqrt,
            "ndist_leave_one_out_p50_p90_p99_max": held_out_quantiles(&survey.held),
        })
    });
    let summary = json!({
        "iterations": learned.iterations,
        "outline_edges": learned.outline_edges,
        "prior_map_hexagons": learned.prior_map_hexagons,
        "prior_map_walks": learned.prior_map_walks,
        "origin": frame,
        "radio": radio,
        "version": env!("CARGO_PKG_VERSION"),
    });
    LearnOut {
        walks,
        merged,
        radio_map: combined
            .radio
            .as_ref()
            .map(|r| radio_map_to_geojson(&r.survey.map, frame)),
        radio_plan: combined
            .radio
            .as_ref()
            .map(|r| floor_plan_to_geojson(&r.plan.plan, frame)),
        summary,
    }
}

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
///     wifi: the walk's WiFi log (``t,bssid,rssi[,ssid,freq]``; its scans make a radio map
///         on the plan learned from the run's map); for a batch one per walk.
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
///
/// Returns:
///     dict: ``walks`` — per walk a dict with ``track`` (columns ``t, x, y, z, level``: the
///     most probable path, metres in the local frame), ``map`` (GeoJSON as ``map.geojson``),
///     ``plan`` (its walkable plan as ``plan.geojson``, or None when too small),
///     ``merged_with_prior`` (with a prior map), ``summary`` and ``config``; ``merged`` —
///     a batch's merged map (GeoJSON, or None); ``radio_map`` and ``radio_plan`` — with
///     WiFi, the radio map (as ``radiomap.geojson``) and the learned plan it lies on;
///     ``summary`` — the run's figures.
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
    ignore_heading=false, cell=None, gps_t0=None, threads=None
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
    seed: Option<u64>,
    particles: Option<usize>,
    hex_radius: Option<f64>,
    prior_weight: Option<f64>,
    ignore_heading: bool,
    cell: Option<f64>,
    gps_t0: Option<f64>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
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
    let inputs = read_inputs(py, &args, false)?;
    let warnings = Warnings::default();
    let out = detached(py, threads, || {
        let learned = footslam::pipeline::learn(&inputs.input(), &inputs.config, &warnings)
            .map_err(py_error)?;
        Ok(learn_out(&inputs, &learned))
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
    warnings.emit(py)?;
    Ok(result)
}

/// Learns walk ``index`` of a batch alone: one task of a batch spread over processes or
/// machines (``footslam.pipeline::learn_one``).
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
    seed: Option<u64>,
    particles: Option<usize>,
    hex_radius: Option<f64>,
    prior_weight: Option<f64>,
    ignore_heading: bool,
    gps_t0: Option<f64>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
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
    let inputs = read_inputs(py, &args, true)?;
    let out = detached(py, threads, || {
        let others = others_doc
            .as_ref()
            .map(Document::stored_map)
            .transpose()
            .map_err(py_error)?;
        let walk = &inputs.walks[0];
        let run = footslam::pipeline::learn_one(
            &inputs.input(),
            walk,
            index,
            others.as_ref().map(|m| &m.map),
            &inputs.config,
        )
        .map_err(py_error)?;
        Ok(walk_out(walk, &inputs.labels[0], &run, &inputs.frame))
    })?;
    out.to_python(py)
}

/// FeetSLAM passes after the first for a batch (``footslam.pipeline::feetslam_passes``):
/// the configuration's ``iterations`` for a batch of several walks that all have known
/// starts (one frame), else 0.
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
    let config: FootSlamConfig = inputs::config(config)?;
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
