//! The `merge` job, request in, report out: maps of several walks in one frame combined
//! ([`merge`](super::merge())), their weights checked, and the merged map's walkable plan.

use super::merge::merge;
use super::named::Named;
use crate::error::{Error, Result};
use crate::io::map_geojson::StoredMap;
use crate::map::{LearnedPlan, PlanConfig, walkable_plan};
use serde::Serialize;

/// Everything `merge` runs on, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct MergeRequest {
    /// The maps, in one frame.
    pub maps: Vec<Named<StoredMap>>,
    /// One weight ≥ 0 per map, or none (all 1).
    pub weights: Vec<f64>,
}

/// `summary.json` of `merge`.
#[derive(Debug, Clone, Serialize)]
pub struct MergeReport {
    /// The maps' names.
    pub maps: Vec<String>,
    /// Their weights as given (none: all 1).
    pub weights: Vec<f64>,
    /// Walks behind the merged map (those of every map that counts).
    pub walks: u32,
    /// Hexagons of the merged map.
    pub hexagons: usize,
    /// Walkable area of its plan, m² (`None`: too little to make a plan of).
    pub walkable_plan_m2: Option<f64>,
    /// The toolkit's version.
    pub version: &'static str,
}

/// What [`run_merge`] gives.
#[derive(Debug, Clone)]
pub struct MergeJob {
    /// The merged map, in the maps' frame.
    pub merged: StoredMap,
    /// Its walkable plan (`None`: too little to make one of).
    pub plan: Option<LearnedPlan>,
    /// Its report.
    pub report: MergeReport,
}

/// Merges the request's maps.
///
/// # Errors
///
/// [`Error::BadOption`] (`weights`) unless the weights are absent or one finite weight ≥ 0 per map,
/// not all 0; [`Error::Mismatch`] naming a map in another frame than the first, or as [`merge`] on
/// another hexagon radius; [`Error::NotEnough`] when the request holds no map.
pub fn run_merge(request: MergeRequest) -> Result<MergeJob> {
    let weights = &request.weights;
    let maps = &request.maps;
    if !weights.is_empty() && weights.len() != maps.len() {
        return Err(Error::BadOption {
            option: "weights",
            problem: format!(
                "{} weights for {} maps: give one weight per map",
                weights.len(),
                maps.len()
            ),
        });
    }
    if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        return Err(Error::BadOption {
            option: "weights",
            problem: format!("{w} is not a finite weight ≥ 0"),
        });
    }
    if !weights.is_empty() && weights.iter().all(|&w| w == 0.0) {
        return Err(Error::BadOption {
            option: "weights",
            problem: "all 0: the merged map would be empty; give at least one map weight > 0"
                .into(),
        });
    }
    if let Some(first) = maps.first() {
        let frame = first.value.frame;
        for m in maps.iter().skip(1) {
            let off = frame.distance_to(&m.value.frame);
            if off > super::input_checks::SAME_ORIGIN_M {
                return Err(Error::mismatch(
                    format!(
                        "{}: its origin ({}, {}) lies {off:.3} m from the first map's ({}, {})",
                        m.label, m.value.frame.lat, m.value.frame.lon, frame.lat, frame.lon
                    ),
                    "only maps in one frame merge (learn the walks with one origin)",
                ));
            }
        }
    }
    let weighted: Vec<_> = maps
        .iter()
        .enumerate()
        .map(|(i, m)| (&m.value, weights.get(i).copied().unwrap_or(1.0)))
        .collect();
    let merged = merge(&weighted)?;
    let plan = walkable_plan(&merged.map, &PlanConfig::default()).ok();
    let report = MergeReport {
        maps: maps.iter().map(|m| m.label.clone()).collect(),
        weights: weights.clone(),
        walks: merged.walks,
        hexagons: merged.map.cells.len(),
        walkable_plan_m2: plan.as_ref().map(|p| p.area_m2),
        version: env!("CARGO_PKG_VERSION"),
    };
    Ok(MergeJob {
        merged,
        plan,
        report,
    })
}
