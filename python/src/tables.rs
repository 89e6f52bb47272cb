//! Tables from Python — a CSV file, a pandas (or polars) DataFrame, a dict of 1-D arrays or
//! a numpy structured array — for the step, IMU, WiFi and GPS formats.
//!
//! In-memory tables are written as the file format's CSV text — numbers in their shortest
//! exact form, NaN in an optional column as an empty cell — and read by the library's own
//! readers (`footslam::io::*::*_from_str`), so arrays pass exactly the checks a file does
//! and give exactly its values; errors name the table and the 0-based row.

use crate::fail;
use crate::inputs::{as_path, require_file, type_name};
use footslam::io::ImuUnits;
use footslam::io::{gps_csv, imu_csv, steps_csv, wifi_csv};
use footslam::sensor::{GpsFix, ImuRecording, StepFields, StepTrace, WifiScan};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The columns of one table format.
pub(crate) struct TableKind {
    /// What a file of it is, in a missing file's message (`step trace`).
    pub what: &'static str,
    /// Columns of numbers, required and optional.
    pub numbers: &'static [&'static str],
    /// Columns of numbers whose NaN is an empty cell (a value not given).
    pub optional: &'static [&'static str],
    /// Columns of text.
    pub texts: &'static [&'static str],
}

/// Step traces: `t,length,dheading[,dz][,heading]`.
pub(crate) const STEPS: TableKind = TableKind {
    what: "step trace",
    numbers: &[
        "t", "length", "dheading", "dz", "heading", "field", "field_up",
    ],
    optional: &["dz", "heading", "field", "field_up"],
    texts: &[],
};

/// Raw IMU recordings: `t,ax,ay,az,gx,gy,gz[,mx,my,mz][,qx,qy,qz,qw][,pressure]`.
pub(crate) const IMU: TableKind = TableKind {
    what: "IMU recording",
    numbers: &[
        "t", "ax", "ay", "az", "gx", "gy", "gz", "mx", "my", "mz", "qx", "qy", "qz", "qw",
        "pressure",
    ],
    optional: &["mx", "my", "mz", "qx", "qy", "qz", "qw", "pressure"],
    texts: &[],
};

/// WiFi logs: `t,bssid,rssi[,ssid,freq]`, one row per sighting.
pub(crate) const WIFI: TableKind = TableKind {
    what: "WiFi log",
    numbers: &["t", "rssi", "freq"],
    optional: &["freq"],
    texts: &["bssid", "ssid"],
};

/// GPS fixes: `t,lat,lon[,accuracy]`.
pub(crate) const GPS: TableKind = TableKind {
    what: "GPS file",
    numbers: &["t", "lat", "lon", "accuracy"],
    optional: &["accuracy"],
    texts: &[],
};

/// A table given from Python.
pub(crate) enum Table {
    /// A file (it exists).
    File(PathBuf),
    /// Columns written as the format's CSV text.
    Text {
        /// The CSV text.
        text: String,
        /// The table's name in messages (`steps`, `steps[1]`).
        name: String,
        /// Its columns, lower case.
        columns: Vec<String>,
    },
}

impl Table {
    /// The file's path or the table's name, as messages name it.
    pub(crate) fn label(&self) -> String {
        match self {
            Table::File(path) => path.display().to_string(),
            Table::Text { name, .. } => name.clone(),
        }
    }

    /// Whether the table has the column `name` (a file: its header); for `dz`, a column with
    /// at least one value (all empty or NaN says nothing about height).
    pub(crate) fn has_column(&self, name: &str) -> footslam::Result<bool> {
        match self {
            Table::File(path) => {
                if name == "dz" {
                    steps_csv::has_dz_column(path)
                } else {
                    let table = footslam::io::csv_table::CsvTable::open(path)?;
                    Ok(table.optional_column(name).is_some())
                }
            }
            Table::Text {
                text, name: label, ..
            } if name == "dz" => steps_csv::has_dz_column_in_str(text, label),
            Table::Text { columns, .. } => Ok(columns.iter().any(|c| c == name)),
        }
    }

    /// The step trace it holds.
    pub(crate) fn steps(&self) -> footslam::Result<StepTrace> {
        match self {
            Table::File(path) => steps_csv::read_steps(path),
            Table::Text { text, name, .. } => steps_csv::steps_from_str(text, name),
        }
    }

    /// The step trace it holds and, with a `field` column, the magnetic field over each step.
    pub(crate) fn steps_with_field(&self) -> footslam::Result<(StepTrace, Option<StepFields>)> {
        match self {
            Table::File(path) => steps_csv::read_steps_with_field(path),
            Table::Text { text, name, .. } => steps_csv::steps_with_field_from_str(text, name),
        }
    }

    /// The IMU recording it holds, its columns in `units`.
    pub(crate) fn imu(&self, units: ImuUnits) -> footslam::Result<ImuRecording> {
        match self {
            Table::File(path) => imu_csv::read_imu_in(path, units),
            Table::Text { text, name, .. } => imu_csv::imu_from_str(text, name, units),
        }
    }

    /// The WiFi scans it holds.
    pub(crate) fn wifi(&self) -> footslam::Result<Vec<WifiScan>> {
        match self {
            Table::File(path) => wifi_csv::read_wifi(path),
            Table::Text { text, name, .. } => wifi_csv::wifi_from_str(text, name),
        }
    }

    /// The WiFi log it holds, with the count of repeated readings left out.
    pub(crate) fn wifi_log(&self) -> footslam::Result<wifi_csv::WifiLog> {
        match self {
            Table::File(path) => wifi_csv::read_wifi_log(path),
            Table::Text { text, name, .. } => wifi_csv::wifi_log_from_str(text, name),
        }
    }

    /// The GPS fixes it holds (a `.gpx` file as GPX 1.1, its times less `t0`).
    pub(crate) fn gps(&self, t0: Option<f64>) -> footslam::Result<Vec<GpsFix>> {
        match self {
            Table::File(path) if is_gpx(path) => footslam::io::read_gpx(path, t0.unwrap_or(0.0)),
            Table::File(path) => gps_csv::read_gps_csv(path),
            Table::Text { text, name, .. } => gps_csv::gps_from_str(text, name),
        }
    }

    /// Whether it is a GPX file.
    pub(crate) fn is_gpx(&self) -> bool {
        matches!(self, Table::File(path) if is_gpx(path))
    }
}

fn is_gpx(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gpx"))
}

/// The table `obj` gives, of format `kind`, called `name` in messages: a path (which must
/// exist), a pandas (or polars) DataFrame, a dict of 1-D arrays or a numpy structured array.
/// Columns the format does not know are kept as empty cells (the readers ignore them).
pub(crate) fn table(obj: &Bound<'_, PyAny>, kind: &TableKind, name: &str) -> PyResult<Table> {
    if let Some(path) = as_path(obj) {
        require_file(&path, kind.what)?;
        return Ok(Table::File(path));
    }
    let py = obj.py();
    let mut named: Vec<(String, Bound<'_, PyAny>)> = Vec::new();
    if let Ok(dict) = obj.cast::<PyDict>() {
        for (k, v) in dict.iter() {
            named.push((k.str()?.to_string(), v));
        }
    } else if let Some(names) = structured_names(obj)? {
        for n in names {
            let v = obj.get_item(&n)?;
            named.push((n, v));
        }
    } else if obj.hasattr("columns")? && obj.hasattr("__getitem__")? {
        for c in obj.getattr("columns")?.try_iter()? {
            let c = c?;
            let v = obj.get_item(&c)?;
            named.push((c.str()?.to_string(), v));
        }
    } else {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a path, a pandas DataFrame or a dict of 1-D arrays, got {}",
            type_name(obj)
        )));
    }
    if named.is_empty() {
        return Err(PyValueError::new_err(format!(
            "{name}: no columns (expected those of a {}: {})",
            kind.what,
            kind.numbers
                .iter()
                .chain(kind.texts)
                .copied()
                .collect::<Vec<_>>()
                .join(",")
        )));
    }
    let numpy = py.import("numpy")?;
    let mut columns: Vec<(String, Column)> = Vec::with_capacity(named.len());
    for (key, value) in named {
        let key = key.trim().to_ascii_lowercase();
        let column = if kind.numbers.contains(&key.as_str()) {
            let optional = kind.optional.contains(&key.as_str());
            Column::Numbers(numbers(&numpy, &value, name, &key)?, optional)
        } else if kind.texts.contains(&key.as_str()) {
            Column::Texts(texts(&numpy, &value, name, &key)?)
        } else {
            Column::Ignored(column_len(&numpy, &value, name, &key)?)
        };
        columns.push((key, column));
    }
    let (first, rest) = columns.split_first().ok_or_else(|| fail("no columns"))?;
    for (key, column) in rest {
        if column.len() != first.1.len() {
            return Err(PyValueError::new_err(format!(
                "{name}: column `{key}` has {} values but column `{}` has {}",
                column.len(),
                first.0,
                first.1.len()
            )));
        }
    }
    Ok(Table::Text {
        text: csv_text(&columns),
        name: name.to_owned(),
        columns: columns.into_iter().map(|(k, _)| k).collect(),
    })
}

/// The field names of a numpy structured array (`None` for anything else).
fn structured_names(obj: &Bound<'_, PyAny>) -> PyResult<Option<Vec<String>>> {
    if !obj.hasattr("dtype")? {
        return Ok(None);
    }
    let names = obj.getattr("dtype")?.getattr("names");
    match names {
        Ok(n) if !n.is_none() => Ok(Some(n.extract()?)),
        _ => Ok(None),
    }
}

/// One column of an in-memory table.
enum Column {
    /// Numbers; `true`: NaN is an empty cell.
    Numbers(Vec<f64>, bool),
    /// Text (`None`: an empty cell).
    Texts(Vec<Option<String>>),
    /// A column the format does not read, of this many values (written empty).
    Ignored(usize),
}

impl Column {
    fn len(&self) -> usize {
        match self {
            Column::Numbers(v, _) => v.len(),
            Column::Texts(v) => v.len(),
            Column::Ignored(n) => *n,
        }
    }
}

/// `value` as a 1-D numpy array (an error naming the column otherwise).
fn one_dimensional<'py>(
    numpy: &Bound<'py, PyModule>,
    value: &Bound<'py, PyAny>,
    table: &str,
    key: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let array = numpy.call_method1("asarray", (value,)).map_err(|e| {
        PyTypeError::new_err(format!(
            "{table}: column `{key}` is not an array of values: {e}"
        ))
    })?;
    let ndim: usize = array.getattr("ndim")?.extract()?;
    if ndim != 1 {
        let shape = array.getattr("shape")?.str()?.to_string();
        return Err(PyValueError::new_err(format!(
            "{table}: column `{key}` must be one-dimensional, got an array of shape {shape}"
        )));
    }
    Ok(array)
}

/// The values of a column of numbers as `f64` (integers and floats; anything else a
/// `TypeError` naming the column and its dtype).
fn numbers(
    numpy: &Bound<'_, PyModule>,
    value: &Bound<'_, PyAny>,
    table: &str,
    key: &str,
) -> PyResult<Vec<f64>> {
    let array = one_dimensional(numpy, value, table, key)?;
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let not_numbers = || {
        let dtype = dtype.str().map_or_else(|_| "?".into(), |s| s.to_string());
        PyTypeError::new_err(format!(
            "{table}: column `{key}` has dtype {dtype}: expected numbers (integers or floats)"
        ))
    };
    let floats = match kind.as_str() {
        "f" | "i" | "u" => array.call_method1("astype", ("float64",))?,
        // Python objects: numbers (and missing values, read as NaN) pass, anything else is
        // an error.
        "O" => {
            let list = array.call_method0("tolist")?;
            let mut values = Vec::new();
            for item in list.try_iter()? {
                let item = item?;
                // None and pandas' NA (nullable dtypes) are missing values.
                if item.is_none() || type_name(&item) == "NAType" {
                    values.push(f64::NAN);
                } else if item.is_instance_of::<PyString>()
                    || item.is_instance_of::<pyo3::types::PyBool>()
                {
                    return Err(not_numbers());
                } else {
                    values.push(item.extract::<f64>().map_err(|_| not_numbers())?);
                }
            }
            return Ok(values);
        }
        _ => return Err(not_numbers()),
    };
    let floats: PyReadonlyArray1<'_, f64> = floats.extract()?;
    Ok(floats.as_array().to_vec())
}

/// The values of a column of text (`None`, NaN and empty strings: empty cells).
fn texts(
    numpy: &Bound<'_, PyModule>,
    value: &Bound<'_, PyAny>,
    table: &str,
    key: &str,
) -> PyResult<Vec<Option<String>>> {
    let array = one_dimensional(numpy, value, table, key)?;
    let list = array.call_method0("tolist")?;
    let mut values = Vec::new();
    for item in list.try_iter()? {
        let item = item?;
        let missing = item.is_none()
            || type_name(&item) == "NAType"
            || item.extract::<f64>().is_ok_and(f64::is_nan);
        values.push(if missing {
            None
        } else {
            Some(item.str()?.to_string())
        });
    }
    Ok(values)
}

/// The number of values of a column the format does not read.
fn column_len(
    numpy: &Bound<'_, PyModule>,
    value: &Bound<'_, PyAny>,
    table: &str,
    key: &str,
) -> PyResult<usize> {
    one_dimensional(numpy, value, table, key)?.len()
}

/// The columns as CSV text: a header, then one row per value; numbers in their shortest
/// exact form (Rust's `Display` reads back to the same `f64`), NaN as an empty cell in an
/// optional column and as `NaN` in a required one (the reader then names it).
fn csv_text(columns: &[(String, Column)]) -> String {
    let rows = columns.first().map_or(0, |(_, c)| c.len());
    let mut text = String::with_capacity(rows * columns.len() * 12 + 64);
    let header: Vec<String> = columns.iter().map(|(k, _)| quoted(k)).collect();
    text.push_str(&header.join(","));
    text.push('\n');
    for i in 0..rows {
        for (j, (_, column)) in columns.iter().enumerate() {
            if j > 0 {
                text.push(',');
            }
            match column {
                Column::Numbers(values, optional) => {
                    let v = values[i];
                    if !(v.is_nan() && *optional) {
                        let _ = write!(text, "{v}");
                    }
                }
                Column::Texts(values) => {
                    if let Some(s) = &values[i] {
                        text.push_str(&quoted(s));
                    }
                }
                Column::Ignored(_) => {}
            }
        }
        text.push('\n');
    }
    text
}

/// A CSV field: quoted (quotes doubled) when it holds a comma, quote or line break.
fn quoted(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_owned()
    }
}
