//! The library's checks that a run's inputs belong together
//! ([`footslam::pipeline::input_checks`]), as the command line makes them, with the file's
//! label before each message and the way out in Python's spelling of the option after it:
//! a WiFi log or GPS file on another clock than the steps, a prior map on another grid, a
//! multi-floor plan with steps that cannot change floor, a WiFi log of another building than
//! the radio map.

use crate::fail;
use crate::tables::Table;
use footslam::geometry::LocalFrame;
use footslam::map::FloorPlan;
use footslam::pipeline::{
    GPS_LEAD_S, GridMismatch, fixes_off_clock, grid_mismatch, missing_height_changes,
    partly_off_clock, scans_off_clock,
};
use footslam::sensor::{GpsFix, StepTrace, WifiScan};
use pyo3::PyResult;

/// WiFi scans, checked to overlap the walk in time: a log on another clock would place no
/// scan (or every scan at one end of the walk). With the warning when the log lies partly
/// off the walk's clock ([`partly_off_clock`]).
pub(crate) fn read_scans(
    table: &Table,
    trace: &StepTrace,
) -> PyResult<(Vec<WifiScan>, Option<String>)> {
    let scans = table.wifi().map_err(crate::py_error)?;
    let steps = trace.steps();
    let (Some(first), Some(last)) = (steps.first(), steps.last()) else {
        return Ok((scans, None));
    };
    if let Some(problem) = scans_off_clock(&scans, first.t, last.t) {
        return Err(fail(format!("{}: {problem}", table.label())));
    }
    let times: Vec<f64> = scans.iter().map(|s| s.t).collect();
    let warning = partly_off_clock(&times, "scans", first.t, last.t, 0.0)
        .map(|w| format!("{}: {w}", table.label()));
    Ok((scans, warning))
}

/// GPS fixes (CSV, GPX or columns), checked to overlap the walk in time.
pub(crate) fn read_fixes(
    table: &Table,
    t0: Option<f64>,
    trace: &StepTrace,
) -> PyResult<(Vec<GpsFix>, Option<String>)> {
    let fixes = table.gps(t0).map_err(crate::py_error)?;
    let steps = trace.steps();
    let (Some(first), Some(last)) = (steps.first(), steps.last()) else {
        return Ok((fixes, None));
    };
    if let Some(problem) = fixes_off_clock(&fixes, first.t, last.t) {
        let hint = if table.is_gpx() {
            "; pass gps_t0 with the UTC time of the steps' t = 0"
        } else {
            ""
        };
        return Err(fail(format!("{}: {problem}{hint}", table.label())));
    }
    let times: Vec<f64> = fixes.iter().map(|f| f.t).collect();
    let warning = partly_off_clock(&times, "fixes", first.t, last.t, GPS_LEAD_S)
        .map(|w| format!("{}: {w}", table.label()));
    Ok((fixes, warning))
}

/// The prior map must lie on the run's hexagon grid.
pub(crate) fn check_same_grid(
    label: &str,
    radius: f64,
    map_frame: &LocalFrame,
    run_radius: f64,
    frame: &LocalFrame,
) -> PyResult<()> {
    let Some(mismatch) = grid_mismatch(radius, map_frame, run_radius, frame) else {
        return Ok(());
    };
    let fix = match mismatch {
        GridMismatch::Radius { map, .. } => format!("pass hex_radius={map}"),
        GridMismatch::Origin { map, .. } => format!(
            "pass origin=({}, {}) (or leave origin out)",
            map.lat, map.lon
        ),
    };
    Err(fail(format!("{label}: {mismatch}: {fix}")))
}

/// On a plan of several levels the steps must carry height changes (`dz`), unless the
/// caller says the walk stays on its floor.
pub(crate) fn check_height_changes(
    steps: &Table,
    plan_label: &str,
    plan: &FloorPlan,
    one_floor: bool,
) -> PyResult<()> {
    let has_dz = steps.has_column("dz").map_err(crate::py_error)?;
    if let Some(problem) = missing_height_changes(plan, plan_label, has_dz, one_floor) {
        return Err(fail(format!(
            "{}: {problem}, or pass one_floor=True if the walk stays on its start floor",
            steps.label()
        )));
    }
    Ok(())
}
