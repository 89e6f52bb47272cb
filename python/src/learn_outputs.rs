//! What `footslam.learn` and `footslam.learn_one` give: per walk its path, map, plan,
//! figures and configuration (what `footslam learn` writes as `track.geojson`,
//! `map.geojson`, `plan.geojson`, `summary.json` and `config.json`), and a run's merged
//! maps and radio map.

use crate::outputs::{Column, columns, json_object};
use footslam::filter::FootSlamConfig;
use footslam::io::field_map_geojson::field_map_to_geojson;
use footslam::io::floor_plan_geojson::floor_plan_to_geojson;
use footslam::io::map_geojson::walks_map_to_geojson;
use footslam::io::radio_map_geojson::radio_map_to_geojson;
use footslam::map::{PlanConfig, walkable_plan};
use footslam::pipeline::{LearnConfig, LearnReport, Learned, PreparedLearn, WalkReport, WalkRun};
use geojson::FeatureCollection;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
    summary: WalkReport,
    config: FootSlamConfig,
}

/// The outputs of walk `i` of `prepared`, learned as `run`, as `footslam learn` writes them
/// (`track.geojson`'s points, `map.geojson`, `plan.geojson`, its report and `config.json`).
pub(crate) fn walk_out(prepared: &PreparedLearn, i: usize, run: &WalkRun) -> WalkOut {
    let (walk, frame) = (&prepared.walks[i], &prepared.frame);
    let estimate = &run.estimate;
    let track = walk
        .trace
        .steps()
        .iter()
        .zip(&estimate.path)
        .zip(&estimate.levels)
        .map(|((s, p), &level)| (s.t, p.x, p.y, estimate.map.level_height(level), level))
        .collect();
    let plan = walkable_plan(&estimate.map, &PlanConfig::default()).ok();
    WalkOut {
        track,
        spread_m: estimate.spread_m.clone(),
        map: walks_map_to_geojson(&estimate.map, frame, 1),
        plan: plan.as_ref().map(|l| floor_plan_to_geojson(&l.plan, frame)),
        field_map: estimate
            .field_map
            .as_ref()
            .filter(|f| !f.cells.is_empty())
            .map(|f| field_map_to_geojson(f, frame)),
        merged_with_prior: None,
        summary: WalkReport::new(walk, run, &prepared.labels[i], plan.as_ref()),
        config: run.config.clone(),
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
    pub(crate) summary: LearnReport,
    /// The configuration the run ran with (`config.json`).
    pub(crate) config: LearnConfig,
}

/// What `learn` gives of `learned`, learned from `prepared` by a job begun at `started`.
pub(crate) fn learn_out(
    prepared: &PreparedLearn,
    learned: &Learned,
    started: std::time::Instant,
) -> LearnOut {
    let frame = &prepared.frame;
    let mut walks: Vec<WalkOut> = (0..prepared.walks.len())
        .map(|i| walk_out(prepared, i, &learned.walks[i]))
        .collect();
    let combined = &learned.combined;
    if let Some(stored) = &prepared.prior_map {
        for (out, merged) in walks.iter_mut().zip(&combined.merged_with_prior) {
            out.merged_with_prior = Some(walks_map_to_geojson(merged, frame, stored.walks + 1));
        }
    }
    let merged = combined
        .merged
        .as_ref()
        .map(|m| walks_map_to_geojson(m, frame, learned.walks.len() as u32));
    let reports = walks.iter().map(|w| w.summary.clone()).collect();
    let threads = rayon::current_num_threads();
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
        summary: LearnReport::new(prepared, learned, reports, started, threads),
        config: prepared.config_run(learned),
    }
}
