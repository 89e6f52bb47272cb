//! `footslam.steps`: a raw IMU recording → step events, as `footslam steps` makes them.

use crate::inputs;
use crate::outputs::{Column, columns, json_object, points3};
use crate::tables::{self, IMU};
use crate::{Reporter, detached, fail, py_error};
use footslam::inertial::frame_check::parse_axes;
use footslam::inertial::{Mount, StepsConfig};
use footslam::io::ImuUnits;
use footslam::pipeline::{Named, StepsRequest, StepsRun, run_steps};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
    let (mount, units) = mount_and_units(mount, accel_unit, gyro_unit)?;
    let flip = gyro_flip
        .map(|axes| parse_axes(axes).map_err(|m| fail(format!("gyro_flip: {m}"))))
        .transpose()?;
    let table = tables::table(imu, &IMU, "imu")?;
    let started = std::time::Instant::now();
    let job = detached(py, None, || {
        let request = StepsRequest {
            recording: Named::new(table.imu(units).map_err(py_error)?, table.label()),
            mount,
            gyro_flip: flip,
            config: config.clone(),
        };
        run_steps(request, started).map_err(py_error)
    })?;
    let run = &job.run;
    let result = PyDict::new(py);
    result.set_item("steps", step_columns(py, run)?)?;
    result.set_item("path", points3(py, &run.path)?)?;
    let report = Reporter::default();
    for w in &job.report.warnings {
        report.push(format!("{}: {w}", job.report.imu_file));
    }
    let summary = serde_json::to_value(&job.report).map_err(|e| fail(e.to_string()))?;
    result.set_item("summary", json_object(py, &summary)?)?;
    result.set_item("config", json_object(py, &config)?)?;
    report.emit(py)?;
    Ok(result)
}

/// The mount and the units named by `steps`' arguments.
fn mount_and_units(mount: &str, accel_unit: &str, gyro_unit: &str) -> PyResult<(Mount, ImuUnits)> {
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
    Ok((mount, units))
}

/// The steps' columns, as `steps.csv` holds them (with the magnetic field's `field` and
/// `field_up` when the recording had one; NaN: none at that step).
fn step_columns<'py>(py: Python<'py>, run: &StepsRun) -> PyResult<Bound<'py, PyDict>> {
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
    columns(py, step_columns)
}
