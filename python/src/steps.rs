//! `footslam.steps`: a raw IMU recording → step events, as `footslam steps` makes them.

use crate::inputs;
use crate::outputs::{Column, columns, json_object, points3};
use crate::tables::{self, IMU};
use crate::{Reporter, detached, fail, py_error, with_context};
use footslam::inertial::frame_check::{axes_flag, parse_axes};
use footslam::inertial::{Mount, StepsConfig};
use footslam::io::ImuUnits;
use footslam::pipeline::{FrameVerdict, StepsRun};
use footslam::sensor::SamplingReport;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::json;

/// Detects the steps of a raw IMU recording (``footslam steps``).
///
/// Args:
///     imu: the recording: a CSV path, a pandas DataFrame, a dict of 1-D arrays or a numpy
///         structured array with columns ``t,ax,ay,az,gx,gy,gz`` (s, m/s² with gravity,
///         rad/s, sensor frame) and optionally ``mx,my,mz`` (µT), ``qx,qy,qz,qw``
///         (orientation sensor → ENU) and ``pressure`` (hPa); NaN in an optional column is
///         an empty cell (the channel's previous value holds); other columns are ignored.
///     mount: ``"foot"`` (zero-velocity-aided INS, one event per stride) or ``"phone"``
///         (held in the hand: step-and-heading, one event per step).
///     config: detector configuration: a dict with the keys of ``config.json``, or a TOML
///         or JSON file.
///     accel_unit: ``"m/s2"`` or ``"g"``, the unit of ``ax,ay,az``.
///     gyro_unit: ``"rad/s"`` or ``"deg/s"``, the unit of ``gx,gy,gz``.
///     gyro_flip: gyroscope axes to negate (e.g. ``"y"``), for a mirrored gyroscope.
///
/// Returns:
///     dict: ``steps`` — columns ``t`` (s), ``length`` (m), ``dheading`` (rad,
///     counter-clockwise), ``dz`` (m), ``heading`` (rad from east; NaN where none);
///     ``path`` — the dead-reckoned ``(n + 1, 3)`` array of ``x, y, z`` in metres (x at the
///     start heading); ``summary`` — the figures of ``summary.json``; ``config`` — the
///     configuration used.
///
/// Raises:
///     FootslamError: bad data (NaN, times out of order, …), a configuration error, a
///         recording that does not match ``mount``, or no steps found.
///     FileNotFoundError: ``imu`` names no file.
///     TypeError: a column holds something other than numbers.
#[pyfunction]
#[pyo3(signature = (imu, mount, *, config=None, accel_unit="m/s2", gyro_unit="rad/s", gyro_flip=None))]
pub(crate) fn steps<'py>(
    py: Python<'py>,
    imu: &Bound<'py, PyAny>,
    mount: &str,
    config: Option<&Bound<'py, PyAny>>,
    accel_unit: &str,
    gyro_unit: &str,
    gyro_flip: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let config: StepsConfig = inputs::config(config)?;
    config.validate().map_err(py_error)?;
    let mount = match mount {
        "foot" => Mount::Foot,
        "phone" => Mount::Phone,
        other => {
            return Err(PyValueError::new_err(format!(
                "mount must be \"foot\" or \"phone\", got {other:?}"
            )));
        }
    };
    let units = ImuUnits {
        accel: match accel_unit {
            "m/s2" => 1.0,
            "g" => ImuUnits::G,
            other => {
                return Err(PyValueError::new_err(format!(
                    "accel_unit must be \"m/s2\" or \"g\", got {other:?}"
                )));
            }
        },
        gyro: match gyro_unit {
            "rad/s" => 1.0,
            "deg/s" => std::f64::consts::PI / 180.0,
            other => {
                return Err(PyValueError::new_err(format!(
                    "gyro_unit must be \"rad/s\" or \"deg/s\", got {other:?}"
                )));
            }
        },
    };
    let flip = gyro_flip
        .map(|axes| parse_axes(axes).map_err(|m| fail(format!("gyro_flip: {m}"))))
        .transpose()?;
    let table = tables::table(imu, &IMU, "imu")?;
    let label = table.label();
    let started = std::time::Instant::now();
    let (run, sampling) = detached(py, None, || {
        let mut recording = table.imu(units).map_err(py_error)?;
        if let Some(flip) = flip {
            recording = recording.with_gyro_flipped(flip);
        }
        let run = footslam::pipeline::steps(&recording, mount, &config)
            .map_err(with_context(format!("{label}: cannot detect steps")))?;
        Ok((run, recording.report().clone()))
    })?;
    // The command line's order: a rejected frame before an empty trace.
    let list: Vec<String> = run
        .recording_warnings()
        .into_iter()
        .chain(frame_warnings(&label, flip, run.frame_verdict())?)
        .collect();
    if run.trace.is_empty() {
        return Err(fail(format!(
            "{label}: no {} detected in {:.1} s of data (is the mount right? is the walker \
             moving?)",
            match mount {
                Mount::Foot => "strides",
                Mount::Phone => "steps",
            },
            sampling.duration_s
        )));
    }
    let result = PyDict::new(py);
    let steps = run.trace.steps();
    let mut step_columns = vec![
        ("t", Column::F64(steps.iter().map(|s| s.t).collect())),
        (
            "length",
            Column::F64(steps.iter().map(|s| s.length).collect()),
        ),
        (
            "dheading",
            Column::F64(steps.iter().map(|s| s.dheading).collect()),
        ),
        ("dz", Column::F64(steps.iter().map(|s| s.dz).collect())),
        (
            "heading",
            Column::F64(
                steps
                    .iter()
                    .map(|s| s.heading.unwrap_or(f64::NAN))
                    .collect(),
            ),
        ),
    ];
    // The magnetic field over each step, as `steps.csv`'s `field` and `field_up` (NaN: none).
    if let Some(field) = run.field.as_ref().filter(|f| f.observed() > 0) {
        let value = |i: usize, up: bool| {
            field
                .get(i)
                .and_then(|f| if up { f.vertical } else { Some(f.magnitude) })
        };
        for (name, up) in [("field", false), ("field_up", true)] {
            step_columns.push((
                name,
                Column::F64(
                    (0..steps.len())
                        .map(|i| value(i, up).unwrap_or(f64::NAN))
                        .collect(),
                ),
            ));
        }
    }
    result.set_item("steps", columns(py, step_columns)?)?;
    result.set_item("path", points3(py, &run.path)?)?;
    let report = Reporter::default();
    for w in &list {
        report.push(format!("{label}: {w}"));
    }
    let summary = summary(&label, &run, list, sampling, started);
    result.set_item("summary", json_object(py, &summary)?)?;
    result.set_item("config", json_object(py, &config)?)?;
    report.emit(py)?;
    Ok(result)
}

/// The frame check's verdict as an error, or as warnings where the output does not depend
/// on the finding (the command line's wording, `gyro_flip` for `--gyro-flip`).
fn frame_warnings(
    label: &str,
    flip: Option<[bool; 3]>,
    verdict: FrameVerdict,
) -> PyResult<Vec<String>> {
    let flipped = match flip {
        Some(flip) => format!(" (after gyro_flip=\"{}\")", axes_flag(flip)),
        None => String::new(),
    };
    verdict
        .messages(&flipped)
        .map_err(|problem| fail(format!("{label}: {problem}")))
}

/// `summary.json`'s figures.
fn summary(
    label: &str,
    run: &StepsRun,
    warnings: Vec<String>,
    sampling: SamplingReport,
    started: std::time::Instant,
) -> serde_json::Value {
    let steps = run.trace.steps();
    let total_length_m: f64 = steps.iter().map(|s| s.length).sum();
    json!({
        "quality": footslam::pipeline::steps_quality(&warnings),
        "imu": label,
        "mount": run.mount,
        "steps": steps.len(),
        "mean_stride_m": total_length_m / steps.len().max(1) as f64,
        "total_length_m": total_length_m,
        "net_height_change_m": steps.iter().map(|s| s.dz).sum::<f64>(),
        "heading_source": run.heading_source,
        "steps_with_heading": run.trace.with_heading(),
        "steps_with_field": run.field.as_ref().map_or(0, |f| f.observed()),
        "steps_with_field_up": run.field.as_ref().map_or(0, |f| f.with_vertical()),
        "warnings": warnings,
        "sampling": sampling,
        "detector": run.figures,
        "runtime_s": started.elapsed().as_secs_f64(),
        "version": env!("CARGO_PKG_VERSION"),
    })
}
