//! The checks of [`input_checks`](super::input_checks) as the jobs make them: each input
//! named, a failed check an [`Error`] (with a [`Remedy`] where one option fixes it), and
//! what does not stop the run a warning to [`Progress`].

use super::Progress;
use super::input_checks::{
    GPS_LEAD_S, GridMismatch, ScanMatch, fixes_off_clock, grid_mismatch, missing_height_changes,
    partly_off_clock, scans_off_clock,
};
use super::named::Named;
use crate::error::{Error, Remedy, RemedyValue, Result};
use crate::geometry::LocalFrame;
use crate::io::map_geojson::StoredMap;
use crate::map::{FloorPlan, RadioMap};
use crate::sensor::{GpsFix, StepTrace, WifiScan};

/// A walk's WiFi scans on its steps' clock: a warning when a part lies off it, and one when
/// `duplicate_readings` rows repeated an access point within their scan (the later reading
/// kept).
///
/// # Errors
///
/// [`Error::Mismatch`] when no scan falls within the walk's time span (a log on another clock would
/// place none, or every one at an end of the walk), an empty log included. A walk without steps
/// passes.
pub fn check_scans_on_clock(
    scans: &Named<Vec<WifiScan>>,
    duplicate_readings: usize,
    trace: &StepTrace,
    progress: &dyn Progress,
) -> Result<()> {
    warn_duplicate_readings(&scans.label, duplicate_readings, progress);
    let steps = trace.steps();
    let (Some(first), Some(last)) = (steps.first(), steps.last()) else {
        return Ok(());
    };
    if let Some(problem) = scans_off_clock(&scans.value, first.t, last.t) {
        return Err(Error::mismatch(format!("{}: {problem}", scans.label), ""));
    }
    let times: Vec<f64> = scans.value.iter().map(|s| s.t).collect();
    if let Some(w) = partly_off_clock(&times, "scans", first.t, last.t, 0.0) {
        progress.warn(&format!("{}: {w}", scans.label));
    }
    Ok(())
}

/// Tells `progress` that `duplicate_readings` rows of the WiFi log `label` repeated an
/// access point within their scan (the reader kept the later reading of each); nothing
/// when there were none.
pub fn warn_duplicate_readings(label: &str, duplicate_readings: usize, progress: &dyn Progress) {
    if duplicate_readings > 0 {
        progress.warn(&format!(
            "{label}: {duplicate_readings} row(s) repeated an access point already in their \
             scan; kept the later reading of each"
        ));
    }
}

/// A walk's GPS fixes on its steps' clock (`gpx`: read from a GPX file, whose UTC times
/// `gps_t0` places): a warning when a part lies off it.
///
/// # Errors
///
/// When no fix falls within the walk's time span (or up to [`GPS_LEAD_S`] before it):
/// [`Error::Remedied`] with the `gps_t0` option for fixes read from a GPX file, else
/// [`Error::Mismatch`]. No fixes, or a walk without steps, pass.
pub fn check_fixes_on_clock(
    fixes: &Named<Vec<GpsFix>>,
    gpx: bool,
    trace: &StepTrace,
    progress: &dyn Progress,
) -> Result<()> {
    let steps = trace.steps();
    let (Some(first), Some(last)) = (steps.first(), steps.last()) else {
        return Ok(());
    };
    if let Some(problem) = fixes_off_clock(&fixes.value, first.t, last.t) {
        let problem = format!("{}: {problem}", fixes.label);
        return Err(if gpx {
            Error::Remedied {
                problem,
                remedy: Remedy {
                    option: "gps_t0",
                    value: RemedyValue::Described(
                        "the UTC time, Unix seconds, of the steps' t = 0",
                    ),
                },
            }
        } else {
            Error::mismatch(problem, "")
        });
    }
    let times: Vec<f64> = fixes.value.iter().map(|f| f.t).collect();
    if let Some(w) = partly_off_clock(&times, "fixes", first.t, last.t, GPS_LEAD_S) {
        progress.warn(&format!("{}: {w}", fixes.label));
    }
    Ok(())
}

/// A prior map on the run's hexagon grid (`radius` metres, `frame`).
///
/// # Errors
///
/// [`Error::Remedied`] with the option that puts the run on the map's grid: `hex_radius`
/// (the map's) when its hexagons have another size, `origin` (the map's) when its origin lies more
/// than [`SAME_ORIGIN_M`](super::input_checks::SAME_ORIGIN_M) from `frame`'s.
pub fn check_same_grid(map: &Named<StoredMap>, radius: f64, frame: &LocalFrame) -> Result<()> {
    let stored = &map.value;
    let Some(mismatch) = grid_mismatch(stored.map.radius, &stored.frame, radius, frame) else {
        return Ok(());
    };
    let remedy = match mismatch {
        GridMismatch::Radius { map, .. } => Remedy {
            option: "hex_radius",
            value: RemedyValue::Number(map),
        },
        GridMismatch::Origin { map, .. } => Remedy {
            option: "origin",
            value: RemedyValue::LatLon(map.lat, map.lon),
        },
    };
    Err(Error::Remedied {
        problem: format!("{}: {mismatch}", map.label),
        remedy,
    })
}

/// On a plan of several levels the steps (`steps_label`; `has_dz`: with height changes)
/// must carry height changes, unless the walk stays on its floor (`one_floor`).
///
/// # Errors
///
/// [`Error::Remedied`] with the `one_floor` option when `plan` has several levels but the steps
/// carry no height changes (`has_dz` false) and `one_floor` is not set.
pub fn check_height_changes(
    steps_label: &str,
    has_dz: bool,
    plan: &Named<&FloorPlan>,
    one_floor: bool,
) -> Result<()> {
    match missing_height_changes(plan.value, &plan.label, has_dz, one_floor) {
        None => Ok(()),
        Some(problem) => Err(Error::Remedied {
            problem: format!("{steps_label}: {problem}"),
            remedy: Remedy {
                option: "one_floor",
                value: RemedyValue::Flag,
            },
        }),
    }
}

/// A WiFi log and a radio map of one building: a warning when fewer than half the scans
/// hear an access point of the map. Returns how many scans matched.
///
/// # Errors
///
/// [`Error::Mismatch`] when no scan hears an access point of the map (the log and the map are of
/// different buildings), an empty log included.
pub fn check_scans_match(
    map: &Named<&RadioMap>,
    scans: &Named<&[WifiScan]>,
    progress: &dyn Progress,
) -> Result<usize> {
    let found = ScanMatch::of(map.value, scans.value);
    if let Some(problem) = found.unmatched() {
        return Err(Error::mismatch(
            format!("{} and {}: {problem}", scans.label, map.label),
            "",
        ));
    }
    if let Some(w) = found.warning(&scans.label, &map.label) {
        progress.warn(&w);
    }
    Ok(found.matched)
}
