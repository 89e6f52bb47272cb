//! Maps learned on several walks of one building, in one frame, combined into one: their
//! edge counts summed with weights (FeetSLAM's combination; counts are associative sums, so
//! maps learned apart — on other threads, machines or days — merge as if learned together).

use super::input_checks::SAME_ORIGIN_M;
use crate::io::map_geojson::StoredMap;
use crate::map::merge_maps;
use crate::{Error, Result};

/// Merges `maps`, each with its weight (a map of weight 0 is left out; its walks do not
/// count), into one map in their frame, holding the walks of the maps that count.
///
/// # Errors
///
/// - [`Error::NotEnough`] when `maps` is empty or every weight is 0.
/// - [`Error::Mismatch`] when a map's origin lies more than [`SAME_ORIGIN_M`] from the first map's,
///   or its hexagon radius differs.
/// - [`Error::InvalidData`] when a weight is negative or not finite.
pub fn merge(maps: &[(&StoredMap, f64)]) -> Result<StoredMap> {
    let (first, _) = maps
        .first()
        .ok_or_else(|| Error::not_enough("no maps to merge", "give at least one map"))?;
    let frame = first.frame;
    for (i, (m, _)) in maps.iter().enumerate().skip(1) {
        let off = frame.distance_to(&m.frame);
        if off > SAME_ORIGIN_M {
            return Err(Error::mismatch(
                format!(
                    "map {}'s origin ({}, {}) lies {off:.3} m from map 1's ({}, {})",
                    i + 1,
                    m.frame.lat,
                    m.frame.lon,
                    frame.lat,
                    frame.lon
                ),
                "only maps in one frame merge (learn the walks with one origin)",
            ));
        }
    }
    if maps.iter().all(|&(_, w)| w == 0.0) {
        return Err(Error::not_enough(
            "every map has weight 0: the merged map would be empty",
            "give at least one map a weight > 0",
        ));
    }
    let weighted: Vec<_> = maps.iter().map(|&(m, w)| (&m.map, w)).collect();
    let map = merge_maps(&weighted)?;
    // The walks behind the merge: those of every map that counts.
    let walks: u32 = maps
        .iter()
        .filter(|&&(_, w)| w > 0.0)
        .map(|(m, _)| m.walks)
        .sum();
    Ok(StoredMap {
        map,
        frame,
        walks: walks.max(1),
    })
}
