//! The library's checks that a run's inputs belong together
//! ([`footslam::pipeline::input_checks`]), as the command line makes them, with the file's
//! label before each message and the way out in Python's spelling of the option after it:
//! a WiFi log or GPS file on another clock than the steps, a prior map on another grid, a
//! multi-floor plan with steps that cannot change floor, a WiFi log of another building than
//! the radio map.

use crate::fail;
use crate::tables::Table;
use footslam::map::FloorPlan;
use footslam::pipeline::{missing_height_changes, partly_off_clock, scans_off_clock};
use footslam::sensor::{StepTrace, WifiScan};
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
