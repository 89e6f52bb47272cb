//! The lines `footslam track` prints at the end of a run, from its report
//! ([`TrackReport`], which is also `summary.json`).

use footslam::pipeline::TrackReport;
use std::path::Path;

/// Prints the run's outcome on stdout, `out` being the run's folder.
pub(super) fn print_report(report: &TrackReport, out: &Path) {
    let r = report;
    match r.steps_to_localise {
        Some(k) => info!(
            "localised after {k} of {} steps ({} particles at the start, {} at the end, {} deaths)",
            r.steps, r.particles_initial, r.particles_final, r.deaths
        ),
        None => info!(
            "not localised in {} steps ({} particles at the start, {} at the end, {} deaths)",
            r.steps, r.particles_initial, r.particles_final, r.deaths
        ),
    }
    if let Some(rf) = &r.rf {
        info!(
            "radio map: {} measurements, {} distance, epsilon {:.2} dBm ({}), started at step {}, {} scan(s) ignored",
            rf.mode.name(),
            rf.distance.name(),
            rf.epsilon_dbm,
            rf.epsilon_source.name(),
            rf.started_at_step.map_or("-".into(), |s| s.to_string()),
            rf.measurements_ignored
        );
    }
    if let Some(smoothing) = &r.smoothing
        && smoothing.steps_estimated < r.steps
    {
        let started = r.rf.as_ref().and_then(|rf| rf.started_at_step);
        info!(
            "track.csv: {} of {} steps have an estimate{}",
            smoothing.steps_estimated,
            r.steps,
            started.map_or(String::new(), |s| format!(
                " (the filter started at step {s}, after the first WiFi scan; the steps \
                 before it have no row)"
            ))
        );
    }
    info!(
        "filter: {:.2} s, {:.2e} particle-steps/s",
        r.filter_runtime_s, r.particle_steps_per_s
    );
    super::verbosity::done(out, Some(&r.quality.line()));
}
