//! What `footslam.learn` and `footslam.learn_one` give: per walk its path, map, plan,
//! figures and configuration (what `footslam learn` writes as `track.geojson`,
//! `map.geojson`, `plan.geojson`, `summary.json` and `config.json`), and a run's merged
//! maps and radio map.

use crate::learn_inputs::Inputs;
use crate::outputs::{Column, columns, json_object};
use footslam::filter::FootSlamConfig;
use footslam::geometry::path_length;
use footslam::geometry::{HexGrid, LocalFrame};
use footslam::io::field_map_geojson::field_map_to_geojson;
use footslam::io::floor_plan_geojson::floor_plan_to_geojson;
use footslam::io::map_geojson::walks_map_to_geojson;
use footslam::io::radio_map_geojson::radio_map_to_geojson;
use footslam::map::{PlanConfig, walkable_plan};
use footslam::model::wifi_distance::held_out_quantiles;
use footslam::pipeline::{LearnWalk, Learned, LearnedRadio, WalkRun};
use geojson::FeatureCollection;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::json;

/// One learned walk, ready for Python.
pub(crate) struct WalkOut {
    track: Vec<(f64, f64, f64, f64, i32)>,
    /// Per step, the spread of the averaged final paths (learn's `spread_m`).
    spread_m: Vec<f64>,
    map: FeatureCollection,
    plan: Option<FeatureCollection>,
    /// `fieldmap.geojson`: the learned magnetic field, when it weighed the particles.
    field_map: Option<FeatureCollection>,
    merged_with_prior: Option<FeatureCollection>,
    summary: serde_json::Value,
    config: FootSlamConfig,
}

/// The outputs of one walk, as `footslam learn` writes them (`track.geojson`'s points,
/// `map.geojson`, `plan.geojson`, `summary.json`'s figures and `config.json`).
pub(crate) fn walk_out(
    walk: &LearnWalk,
    label: &str,
    run: &WalkRun,
    frame: &LocalFrame,
) -> WalkOut {
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
        "quality": run.quality(&footslam::pipeline::QualityConfig::default()),
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
        "smoothing": run.smoothing_report(),
        "building_axes": run.axes_report(),
        "magnetic_field": run.field_report(),
        "departure_from_dead_reckoning": run.departure,
    });
    WalkOut {
        track,
        spread_m: estimate.spread_m.clone(),
        map: walks_map_to_geojson(&estimate.map, frame, 1),
        plan: learned.map(|l| floor_plan_to_geojson(&l.plan, frame)),
        field_map: estimate
            .field_map
            .as_ref()
            .filter(|f| !f.cells.is_empty())
            .map(|f| field_map_to_geojson(f, frame)),
        merged_with_prior: None,
        summary,
        config: config.clone(),
    }
}

impl WalkOut {
    pub(crate) fn to_python<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
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
                    ("spread_m", Column::F64(self.spread_m.clone())),
                ],
            )?,
        )?;
        d.set_item("map", json_object(py, &self.map)?)?;
        d.set_item("plan", json_object(py, &self.plan)?)?;
        d.set_item("field_map", json_object(py, &self.field_map)?)?;
        if let Some(m) = &self.merged_with_prior {
            d.set_item("merged_with_prior", json_object(py, m)?)?;
        }
        d.set_item("summary", json_object(py, &self.summary)?)?;
        d.set_item("config", json_object(py, &self.config)?)?;
        Ok(d)
    }
}

/// Everything `learn` gives, ready for Python.
pub(crate) struct LearnOut {
    pub(crate) walks: Vec<WalkOut>,
    pub(crate) merged: Option<FeatureCollection>,
    pub(crate) radio_map: Option<FeatureCollection>,
    pub(crate) radio_plan: Option<FeatureCollection>,
    pub(crate) summary: serde_json::Value,
}

pub(crate) fn learn_out(inputs: &Inputs, learned: &Learned) -> LearnOut {
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
        let mut summary = radio_summary(radio, inputs.cells.granularity);
        summary["scans"] = json!(
            inputs
                .walks
                .iter()
                .map(|w| w.scans.len())
                .collect::<Vec<_>>()
        );
        summary["ndist_leave_one_out_p50_p90_p99_max"] =
            json!(held_out_quantiles(&radio.survey.held));
        summary
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

/// The figures of a radio map learned from walks (`summary.json`'s `radio` block, less what
/// only `learn` knows): cells, scans placed, coverage, access points, ε.
pub(crate) fn radio_summary(radio: &LearnedRadio, granularity: f64) -> serde_json::Value {
    let survey = &radio.survey;
    let map = &survey.map;
    let (coverage, per_cell) = map.coverage();
    json!({
        "granularity_m": granularity,
        "cells": survey.cells.cells().len(),
        "rooms": survey.cells.rooms().len(),
        "scans_added": survey.counts.iter().map(|c| c.added).collect::<Vec<_>>(),
        "scans_skipped": survey.counts.iter().map(|c| c.skipped).collect::<Vec<_>>(),
        "coverage": coverage,
        "mean_scans_per_covered_cell": per_cell,
        "access_points": map.access_points().len(),
        "epsilon": map.epsilon,
        "epsilon_sqrt": map.epsilon_sqrt,
    })
}
