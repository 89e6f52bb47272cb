//! The command line's checks that its readers do not make (they live in `src/cli/`), with
//! its messages: a WiFi log or GPS file on another clock than the steps, a prior map on
//! another grid, a multi-floor plan with steps that cannot change floor, a WiFi log of
//! another building than the radio map.

use crate::fail;
use crate::tables::Table;
use footslam::geometry::LocalFrame;
use footslam::map::{FloorPlan, RadioMap};
use footslam::pipeline::SAME_ORIGIN_M;
use footslam::sensor::{GpsFix, StepTrace, WifiScan, scans_off_clock};
use pyo3::PyResult;

/// Below this share of a WiFi log's scans hearing an access point of the radio map, `track`
/// warns (the command line's `MIN_MATCHED_SHARE`).
const MIN_MATCHED_SHARE: f64 = 0.5;

/// WiFi scans, checked to overlap the walk in time: a log on another clock would place no
/// scan (or every scan at one end of the walk).
pub(crate) fn read_scans(table: &Table, trace: &StepTrace) -> PyResult<Vec<WifiScan>> {
    let scans = table.wifi().map_err(crate::py_error)?;
    let steps = trace.steps();
    let (Some(first), Some(last)) = (steps.first(), steps.last()) else {
        return Ok(scans);
    };
    if let Some(problem) = scans_off_clock(&scans, first.t, last.t) {
        return Err(fail(format!("{}: {problem}", table.label())));
    }
    Ok(scans)
}

/// GPS fixes (CSV, GPX or columns), checked to overlap the walk in time.
pub(crate) fn read_fixes(
    table: &Table,
    t0: Option<f64>,
    trace: &StepTrace,
) -> PyResult<Vec<GpsFix>> {
    let fixes = table.gps(t0).map_err(crate::py_error)?;
    let steps = trace.steps();
    let (Some(first), Some(last), Some(f0), Some(f1)) =
        (steps.first(), steps.last(), fixes.first(), fixes.last())
    else {
        return Ok(fixes);
    };
    let (a, b) = (first.t, last.t);
    if !fixes.iter().any(|f| f.t >= a - 60.0 && f.t <= b) {
        let hint = if table.is_gpx() {
            "; pass gps_t0 with the UTC time of the steps' t = 0"
        } else {
            ""
        };
        return Err(fail(format!(
            "{}: no fix falls within the walk's time span [{a}, {b}] s (fixes run from {} to {} s){hint}",
            table.label(),
            f0.t,
            f1.t
        )));
    }
    Ok(fixes)
}

/// The prior map must lie on the run's hexagon grid.
pub(crate) fn check_same_grid(
    label: &str,
    radius: f64,
    map_frame: &LocalFrame,
    run_radius: f64,
    frame: &LocalFrame,
) -> PyResult<()> {
    if (radius - run_radius).abs() > 1e-9 {
        return Err(fail(format!(
            "{label}: hexagons of radius {radius} m, but this run uses {run_radius} m: pass \
             hex_radius={radius}"
        )));
    }
    let off = frame.distance_to(map_frame);
    if off > SAME_ORIGIN_M {
        return Err(fail(format!(
            "{label}: its origin ({}, {}) lies {off:.3} m from this run's ({}, {}); hexagons of \
             different origins do not line up: pass origin=({}, {}) (or leave origin out)",
            map_frame.lat, map_frame.lon, frame.lat, frame.lon, map_frame.lat, map_frame.lon
        )));
    }
    Ok(())
}

/// On a plan of several levels the steps must carry height changes (`dz`), unless the
/// caller says the walk stays on its floor.
pub(crate) fn check_height_changes(
    steps: &Table,
    plan_label: &str,
    plan: &FloorPlan,
    one_floor: bool,
) -> PyResult<()> {
    let levels = plan.levels().len();
    if levels > 1 && !one_floor && !steps.has_column("dz").map_err(crate::py_error)? {
        return Err(fail(format!(
            "{}: no `dz` column, but {plan_label} has {levels} levels: the steps' height \
             changes are what moves the walk between floors; add `dz` (footslam steps writes \
             it from the barometer or the foot's height), or pass one_floor=True if the walk \
             stays on its start floor",
            steps.label()
        )));
    }
    Ok(())
}

/// A WiFi log and a radio map must be of one building: an error when no scan hears an
/// access point of the map, a warning (returned) when fewer than half do. Returns how many
/// scans matched.
pub(crate) fn check_scans_match(
    map: &RadioMap,
    scans: &[WifiScan],
    map_label: &str,
    wifi_label: &str,
) -> PyResult<(usize, Option<String>)> {
    let matched = map.scans_matched(scans);
    let share = matched as f64 / scans.len().max(1) as f64;
    if matched == 0 {
        return Err(fail(format!(
            "{wifi_label} and {map_label}: none of the log's {} scans hears an access point of \
             the radio map: they are of different buildings (or the BSSIDs were renamed)",
            scans.len()
        )));
    }
    let warning = (share < MIN_MATCHED_SHARE).then(|| {
        format!(
            "only {matched} of {} scans of {wifi_label} ({:.0} %) hear an access point of \
             {map_label}: the rest cannot be placed by the radio map",
            scans.len(),
            100.0 * share
        )
    });
    Ok((matched, warning))
}
