//! `footslam.merge`, `footslam.others_map` and `footslam.plan`: learned maps combined, and
//! a learned map as a walkable floor plan with occupancy grids.

use crate::inputs::{self, Document};
use crate::outputs::{grid_i8, json_object};
use crate::{detached, fail, py_error};
use footslam::io::floor_plan_geojson::floor_plan_to_geojson;
use footslam::io::map_geojson::{StoredMap, walks_map_to_geojson};
use footslam::map::Occupancy;
use footslam::pipeline::{
    MergeRequest, Named, PlanOverrides, PlanRequest, PlanRunConfig, Planned, run_merge, run_plan,
};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The maps of a list (paths, GeoJSON dicts or GeoJSON text), read.
fn read_maps(py: Python<'_>, maps: &Bound<'_, PyAny>) -> PyResult<(Vec<StoredMap>, Vec<String>)> {
    let Some(list) = inputs::as_list(maps)? else {
        return Err(PyTypeError::new_err(
            "maps: expected a list of maps (paths, GeoJSON dicts or GeoJSON text)",
        ));
    };
    let docs = list
        .iter()
        .enumerate()
        .map(|(i, m)| inputs::document(m, "map", &format!("maps[{i}]")))
        .collect::<PyResult<Vec<_>>>()?;
    let labels = docs.iter().map(Document::label).collect();
    let maps = detached(py, None, || {
        docs.iter()
            .map(|d| d.stored_map().map_err(py_error))
            .collect::<PyResult<Vec<_>>>()
    })?;
    Ok((maps, labels))
}

/// Merges maps learned on several walks of one building, in one frame (``footslam merge``):
/// their edge counts summed with weights.
///
/// Args:
///     maps: the maps: paths, GeoJSON dicts or GeoJSON text (``map.geojson`` of ``learn``,
///         or merges).
///     weights: one weight ≥ 0 per map (default all 1; a map of weight 0 is left out).
///
/// Returns:
///     dict: the merged map as GeoJSON (the format of ``map.geojson``, ``walks`` the sum
///     of the walks of the maps that count).
///
/// Raises:
///     FootslamError: maps in different frames or on different grids, bad weights.
///     FileNotFoundError: a path names no file.
#[pyfunction]
#[pyo3(signature = (maps, weights=None))]
pub(crate) fn merge<'py>(
    py: Python<'py>,
    maps: &Bound<'py, PyAny>,
    weights: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (maps, labels) = read_maps(py, maps)?;
    let maps = maps
        .into_iter()
        .zip(labels)
        .map(|(m, label)| Named::new(m, label))
        .collect();
    let request = MergeRequest {
        maps,
        weights: weights.unwrap_or_default(),
    };
    let collection = detached(py, None, || {
        let merged = run_merge(request).map_err(py_error)?.merged;
        Ok(walks_map_to_geojson(
            &merged.map,
            &merged.frame,
            merged.walks,
        ))
    })?;
    json_object(py, &collection)
}

/// The merged map of every map but the ``i``-th (the library's ``pipeline::others_map``):
/// walk ``i``'s ``others`` in a FeetSLAM pass of a batch fanned out with :func:`learn_one`.
///
/// Args:
///     maps: the batch's maps of the previous pass, in the order of the walks (paths,
///         GeoJSON dicts or GeoJSON text — text is read as it is, where a dict is first
///         written out as JSON —, in one frame).
///     i: the walk (0-based) left out.
///
/// Returns:
///     dict: the merged map as GeoJSON, in the frame of the first map.
///
/// Raises:
///     FootslamError: maps on different grids, ``i`` out of range.
#[pyfunction]
pub(crate) fn others_map<'py>(
    py: Python<'py>,
    maps: &Bound<'py, PyAny>,
    i: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let (maps, _) = read_maps(py, maps)?;
    if i >= maps.len() {
        return Err(fail(format!(
            "walk {i}: the batch has {} maps (0-based index)",
            maps.len()
        )));
    }
    let collection = detached(py, None, || {
        let snapshots: Vec<_> = maps.iter().map(|m| &m.map).collect();
        let merged = footslam::pipeline::others_map(&snapshots, i).map_err(py_error)?;
        let walks = maps
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .map(|(_, m)| m.walks)
            .sum::<u32>()
            .max(1);
        Ok(walks_map_to_geojson(&merged, &maps[0].frame, walks))
    })?;
    json_object(py, &collection)
}

/// A learned map as a walkable floor plan and occupancy grids (``footslam plan``).
///
/// Args:
///     map: the learned map (path or GeoJSON dict: ``map.geojson``, ``merged.geojson`` or
///         a merge).
///     config: a dict (or TOML/JSON file) with ``plan`` and ``grid`` tables.
///     min_visits: passes through a hexagon that make it walkable (default 1).
///     resolution: side of an occupancy-grid square, metres (default 0.05).
///
/// Returns:
///     dict: ``plan`` — the floor plan as GeoJSON (``plan.geojson``, what :func:`track` and
///     :func:`survey` read); ``grids`` — per floor (the main one first) a dict with
///     ``level``, ``resolution`` (m), ``origin`` (``(x, y)`` of the south-west corner,
///     local metres) and ``occupancy`` (an ``int8`` array of shape ``(height, width)``,
///     row 0 the southernmost: 0 free, 100 occupied, -1 unknown, as ROS maps); ``summary``.
///
/// Raises:
///     FootslamError: a map with too little walked to make a plan of, a bad configuration.
///     FileNotFoundError: ``map`` names no file.
#[pyfunction]
#[pyo3(signature = (map, *, config=None, min_visits=None, resolution=None))]
pub(crate) fn plan<'py>(
    py: Python<'py>,
    map: &Bound<'py, PyAny>,
    config: Option<&Bound<'py, PyAny>>,
    min_visits: Option<u32>,
    resolution: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let config: PlanRunConfig = inputs::config(config)?;
    let overrides = PlanOverrides {
        min_visits,
        resolution,
    };
    let doc = inputs::document(map, "map", "map")?;
    let job = detached(py, None, || {
        let map = Named::new(doc.stored_map().map_err(py_error)?, doc.label());
        let request = PlanRequest {
            map,
            config,
            overrides,
        };
        run_plan(request).map_err(py_error)
    })?;
    let Planned { learned, grids } = &job.planned;
    let result = PyDict::new(py);
    let plan = floor_plan_to_geojson(&learned.plan, &job.frame);
    result.set_item("plan", json_object(py, &plan)?)?;
    let mut out = Vec::with_capacity(grids.len());
    for (level, grid) in grids {
        let values: Vec<i8> = grid
            .cells
            .iter()
            .map(|c| match c {
                Occupancy::Free => 0,
                Occupancy::Occupied => 100,
                Occupancy::Unknown => -1,
            })
            .collect();
        let g = PyDict::new(py);
        g.set_item("level", level)?;
        g.set_item("resolution", grid.resolution)?;
        g.set_item("origin", grid.origin)?;
        g.set_item("occupancy", grid_i8(py, values, grid.height, grid.width)?)?;
        out.push(g);
    }
    result.set_item("grids", out)?;
    result.set_item("summary", json_object(py, &job.report)?)?;
    result.set_item("config", json_object(py, &job.config)?)?;
    Ok(result)
}
