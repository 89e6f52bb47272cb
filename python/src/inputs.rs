//! Inputs from Python besides tables ([`crate::tables`]): GeoJSON documents (a file, a
//! dict, an object with `__geo_interface__`, or JSON text), configurations (a dict or a
//! TOML/JSON file), start poses and origins, and per-walk lists.

use crate::{fail, py_error};
use footslam::filter::StartPose;
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::{floor_plan_from_str, read_floor_plan};
use footslam::io::map_geojson::{StoredMap, read_stored_map, stored_map_from_str};
use footslam::io::outline_geojson;
use footslam::io::radio_map_geojson::{radio_map_from_str, read_radio_map_geojson};
use footslam::map::{FloorPlan, RadioMap};
use pyo3::exceptions::{PyFileNotFoundError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

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
pub(crate) fn as_path(obj: &Bound<'_, PyAny>) -> Option<PathBuf> {
    let path_like = obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__").unwrap_or(false);
    path_like.then(|| obj.extract::<PathBuf>().ok()).flatten()
}

/// The Python type name of `obj`, for messages.
pub(crate) fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string())
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
    pub(crate) fn world_outline(&self) -> footslam::Result<footslam::io::WorldOutline> {
        match self {
            Document::File(path) => footslam::io::read_world_outline(path),
            Document::Text { text, name } => outline_geojson::world_outline_from_str(text, name),
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
