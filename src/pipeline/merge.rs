//! Maps learned on several walks of one building, in one frame, combined into one: their
//! edge counts summed with weights (FeetSLAM's combination; counts are associative sums, so
//! maps learned apart — on other threads, machines or days — merge as if learned together).
//!
//! Maps of three walks in one frame, merged in two rounds or one:
//!
//! ```
//! use footslam::geometry::{LocalFrame, Pose2};
//! use footslam::io::map_geojson::StoredMap;
//! use footslam::map::map_of_path;
//! use footslam::pipeline::merge;
//!
//! let frame = LocalFrame::new(47.37, 8.54).expect("a valid origin");
//! let walk = |y: f64| {
//!     let path: Vec<Pose2> = (1..=10).map(|i| Pose2::new(f64::from(i), y, 0.0)).collect();
//!     let map = map_of_path(Pose2::new(0.0, y, 0.0), &path, &[0; 10], 0.5, 0.8);
//!     StoredMap { map, frame, walks: 1 }
//! };
//! // Two walks along one corridor, one along the next.
//! let (a, b, c) = (walk(0.0), walk(0.0), walk(5.0));
//! let ab = merge(&[(&a, 1.0), (&b, 1.0)])?;
//! let abc = merge(&[(&ab, 1.0), (&c, 1.0)])?;
//! assert_eq!(abc.walks, 3);
//! assert_eq!(abc.map.cells.len(), a.map.cells.len() + c.map.cells.len());
//! assert_eq!(abc.map, merge(&[(&a, 1.0), (&b, 1.0), (&c, 1.0)])?.map);
//!
//! // Maps placed by different origins do not merge.
//! let elsewhere = StoredMap { frame: LocalFrame::new(47.38, 8.54).expect("valid"), ..walk(0.0) };
//! assert!(merge(&[(&a, 1.0), (&elsewhere, 1.0)]).is_err());
//! # Ok::<(), footslam::Error>(())
//! ```

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
