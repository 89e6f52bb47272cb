//! Inputs from Python: tables (a CSV file, a pandas DataFrame, a dict of 1-D arrays or a
//! numpy structured array), GeoJSON documents (a file, a dict, an object with
//! `__geo_interface__`, or JSON text), configurations (a dict or a TOML/JSON file) and
//! start poses.
//!
//! In-memory tables are written as the file format's CSV text — numbers in their shortest
//! exact form, NaN in an optional column as an empty cell — and read by the library's own
//! readers (`footslam::io::*::*_from_str`), so arrays pass exactly the checks a file does
//! and give exactly its values.

use crate::{fail, py_error};
use footslam::filter::StartPose;
use footslam::geometry::LocalFrame;
use footslam::io::ImuUnits;
use footslam::io::floor_plan_geojson::{floor_plan_from_str, read_floor_plan};
use footslam::io::map_geojson::{StoredMap, read_stored_map, stored_map_from_str};
use footslam::io::radio_map_geojson::{radio_map_from_str, read_radio_map_geojson};
use footslam::io::{gps_csv, imu_csv, outline_geojson, steps_csv, wifi_csv};
use footslam::map::{FloorPlan, RadioMap};
use footslam::sensor::{GpsFix, ImuRecording, StepTrace, WifiScan};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::{PyFileNotFoundError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use serde::de::DeserializeOwned;
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
    numbers: &["t", "length", "dheading", "dz", "heading"],
    optional: &["dz", "heading"],
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

    /// Whether the table has the column `name` (a file: its header).
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

/// `FileNotFoundError` unless `path` is a file, worded as the command line's.
pub(crate) fn require_file(path: &Path, what: &str) -> PyResult<()> {
    if path.is_file() {
        Ok(())
    } else {
        Err(PyFileNotFoundError::new_err(format!(
            "{what} `{}` does not exist or is not a file",
            path.display()
        )))
    }
}

/// The path `obj` names, when it is a `str` or an `os.PathLike`.
fn as_path(obj: &Bound<'_, PyAny>) -> Option<PathBuf> {
    let path_like = obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__").unwrap_or(false);
    path_like.then(|| obj.extract::<PathBuf>().ok()).flatten()
}

/// The Python type name of `obj`, for messages.
fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string())
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
        // Python objects: numbers (and None, read as NaN) pass, anything else is an error.
        "O" => {
            let list = array.call_method0("tolist")?;
            let mut values = Vec::new();
            for item in list.try_iter()? {
                let item = item?;
                if item.is_none() {
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
        let missing = item.is_none() || item.extract::<f64>().is_ok_and(f64::is_nan);
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

/// A GeoJSON document given from Python.
pub(crate) enum Document {
    /// A file (it exists).
    File(PathBuf),
    /// GeoJSON text, named in messages.
    Text {
        /// The JSON text.
        text: String,
        /// Its name in messages (`plan`, `maps[2]`).
        name: String,
    },
}

impl Document {
    /// The file's path or the document's name, as messages name it.
    pub(crate) fn label(&self) -> String {
        match self {
            Document::File(path) => path.display().to_string(),
            Document::Text { name, .. } => name.clone(),
        }
    }

    /// The floor plan it holds and its frame (`origin` overrides the document's).
    pub(crate) fn floor_plan(
        &self,
        origin: Option<LocalFrame>,
    ) -> footslam::Result<(FloorPlan, LocalFrame)> {
        match self {
            Document::File(path) => read_floor_plan(path, origin),
            Document::Text { text, name } => floor_plan_from_str(text, name, origin),
        }
    }

    /// The learned map it holds.
    pub(crate) fn stored_map(&self) -> footslam::Result<StoredMap> {
        match self {
            Document::File(path) => read_stored_map(path),
            Document::Text { text, name } => stored_map_from_str(text, name),
        }
    }

    /// The radio map it holds and its frame (`origin` overrides the document's).
    pub(crate) fn radio_map(
        &self,
        origin: Option<LocalFrame>,
    ) -> footslam::Result<(RadioMap, LocalFrame)> {
        match self {
            Document::File(path) => read_radio_map_geojson(path, origin),
            Document::Text { text, name } => radio_map_from_str(text, name, origin),
        }
    }

    /// The building outline it holds, in `frame`.
    pub(crate) fn outline(&self, frame: &LocalFrame) -> footslam::Result<geo::Polygon<f64>> {
        match self {
            Document::File(path) => footslam::io::read_outline(path, frame),
            Document::Text { text, name } => outline_geojson::outline_from_str(text, name, frame),
        }
    }
}

/// The GeoJSON document `obj` gives, a `what` (in a missing file's message) called `name`:
/// a path (which must exist), a dict, an object with `__geo_interface__` (a GeoDataFrame)
/// or JSON text.
pub(crate) fn document(obj: &Bound<'_, PyAny>, what: &str, name: &str) -> PyResult<Document> {
    if let Ok(s) = obj.cast::<PyString>() {
        let s: String = s.extract()?;
        if s.trim_start().starts_with('{') {
            return Ok(Document::Text {
                text: s,
                name: name.to_owned(),
            });
        }
    }
    if let Some(path) = as_path(obj) {
        require_file(&path, what)?;
        return Ok(Document::File(path));
    }
    let value = if !obj.is_instance_of::<PyDict>() && obj.hasattr("__geo_interface__")? {
        obj.getattr("__geo_interface__")?
    } else {
        obj.clone()
    };
    if !value.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a path, a GeoJSON dict or an object with __geo_interface__, got {}",
            type_name(obj)
        )));
    }
    Ok(Document::Text {
        text: json_text(&value, name)?,
        name: name.to_owned(),
    })
}

/// `value` as JSON text (numpy numbers as plain numbers; NaN is not JSON: an error).
pub(crate) fn json_text(value: &Bound<'_, PyAny>, name: &str) -> PyResult<String> {
    let py = value.py();
    let json = py.import("json")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("allow_nan", false)?;
    // numpy scalars and arrays become Python numbers and lists.
    let tolist = py
        .import("operator")?
        .call_method1("methodcaller", ("tolist",))?;
    kwargs.set_item("default", tolist)?;
    json.call_method("dumps", (value,), Some(&kwargs))
        .and_then(|t| t.extract::<String>())
        .map_err(|e| {
            let message = format!("{name}: cannot be written as JSON: {}", e.value(py));
            if e.is_instance_of::<PyValueError>(py) {
                PyValueError::new_err(message)
            } else {
                PyTypeError::new_err(message)
            }
        })
}

/// A configuration: `None` the defaults, a dict (the keys of the command line's config
/// file) or a TOML/JSON file; unknown keys are errors with serde's message.
pub(crate) fn config<T: DeserializeOwned + Default>(obj: Option<&Bound<'_, PyAny>>) -> PyResult<T> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(T::default());
    };
    if let Some(path) = as_path(obj) {
        require_file(&path, "configuration")?;
        let text =
            std::fs::read_to_string(&path).map_err(|e| py_error(footslam::Error::io(&path, e)))?;
        let text = text.trim_start_matches('\u{feff}');
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let parsed = if is_json {
            serde_json::from_str(text).map_err(|e| e.to_string())
        } else {
            toml::from_str(text).map_err(|e| e.to_string())
        };
        return parsed.map_err(|e| fail(format!("{}: invalid configuration: {e}", path.display())));
    }
    if !obj.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "config: expected a dict or the path of a TOML or JSON file, got {}",
            type_name(obj)
        )));
    }
    let text = json_text(obj, "config")?;
    serde_json::from_str(&text).map_err(|e| fail(format!("config: invalid configuration: {e}")))
}

/// A known start: `None`, `"X,Y[,HEADING[,LEVEL]]"` (as the command line's `--start`), a
/// tuple `(x, y[, heading[, level]])` or a dict with `x`, `y` and optionally `heading`,
/// `level` (`None` entries: unknown). Checked by the command line's parser.
pub(crate) fn start(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<StartPose>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let text =
        if let Ok(s) = obj.cast::<PyString>() {
            s.extract::<String>()?
        } else {
            let get = |key: &str, i: usize| -> PyResult<Option<Bound<'_, PyAny>>> {
                let item = if let Ok(d) = obj.cast::<PyDict>() {
                    d.get_item(key)?
                } else if obj.is_instance_of::<PyTuple>() || obj.is_instance_of::<PyList>() {
                    obj.get_item(i).ok()
                } else {
                    return Err(PyTypeError::new_err(format!(
                        "{name}: expected \"X,Y[,HEADING[,LEVEL]]\", a tuple (x, y[, heading[, \
                     level]]) or a dict, got {}",
                        type_name(obj)
                    )));
                };
                Ok(item.filter(|v| !v.is_none()))
            };
            let number = |key: &str, i: usize| -> PyResult<String> {
                match get(key, i)? {
                    None => Ok(String::new()),
                    Some(v) => v.extract::<f64>().map(|v| v.to_string()).map_err(|_| {
                        PyTypeError::new_err(format!("{name}: {key} is not a number"))
                    }),
                }
            };
            let level = match get("level", 3)? {
                None => String::new(),
                Some(v) => v.extract::<i64>().map(|l| l.to_string()).map_err(|_| {
                    PyTypeError::new_err(format!("{name}: level is not an integer"))
                })?,
            };
            let len = obj.len().unwrap_or(0);
            if !obj.is_instance_of::<PyDict>() && !(2..=4).contains(&len) {
                return Err(PyValueError::new_err(format!(
                    "{name}: expected (x, y[, heading[, level]]), got {len} values"
                )));
            }
            let heading = number("heading", 2)?;
            let mut fields = vec![number("x", 0)?, number("y", 1)?, heading, level];
            // `X,Y`, `X,Y,HEADING`, `X,Y,,LEVEL`: no trailing empty fields.
            while fields.len() > 2 && fields.last().is_some_and(String::is_empty) {
                fields.pop();
            }
            fields.join(",")
        };
    text.parse::<StartPose>()
        .map(Some)
        .map_err(|m| fail(format!("{name}: {m}")))
}

/// The local frame of `origin = (lat, lon)` in degrees.
pub(crate) fn origin(origin: Option<(f64, f64)>) -> PyResult<Option<LocalFrame>> {
    origin
        .map(|(lat, lon)| {
            LocalFrame::new(lat, lon).ok_or_else(|| {
                fail(format!(
                    "origin ({lat}, {lon}) is not a valid latitude,longitude"
                ))
            })
        })
        .transpose()
}

/// `obj` as a list of items when it is a list or tuple (a batch), else `None`.
pub(crate) fn as_list<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Option<Vec<Bound<'py, PyAny>>>> {
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        Ok(Some(obj.try_iter()?.collect::<PyResult<Vec<_>>>()?))
    } else {
        Ok(None)
    }
}

/// One entry per walk of an optional per-walk input: `None` for none; for a batch a list of
/// one entry per walk (entries may be `None`), for one walk the entry itself.
pub(crate) fn per_walk<'py>(
    obj: Option<&Bound<'py, PyAny>>,
    walks: usize,
    batch: bool,
    what: &str,
) -> PyResult<Vec<Option<Bound<'py, PyAny>>>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(vec![None; walks]);
    };
    if !batch {
        return Ok(vec![Some(obj.clone())]);
    }
    let Some(list) = as_list(obj)? else {
        return Err(PyTypeError::new_err(format!(
            "{what}: the steps are a batch of {walks} walks: give a list of one {what} per walk \
             (None for a walk without)"
        )));
    };
    if list.len() != walks {
        return Err(fail(format!(
            "{} {what} entries for {walks} walks: give one per walk, in the order of the walks",
            list.len()
        )));
    }
    Ok(list
        .into_iter()
        .map(|o| (!o.is_none()).then_some(o))
        .collect())
}
