//! Results to Python: tables as dicts of 1-D numpy arrays (one per column, ready for
//! `pandas.DataFrame`), GeoJSON as dicts (ready for `geopandas.GeoDataFrame.from_features`),
//! figures as plain dicts.

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Serialize;

/// One column of a result table.
pub(crate) enum Column {
    /// Floats (NaN: no value).
    F64(Vec<f64>),
    /// Integers.
    I64(Vec<i64>),
    /// Booleans.
    Bool(Vec<bool>),
}

/// A dict of 1-D numpy arrays, one per column, in order.
pub(crate) fn columns<'py>(
    py: Python<'py>,
    columns: Vec<(&str, Column)>,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (name, column) in columns {
        match column {
            Column::F64(v) => dict.set_item(name, PyArray1::from_vec(py, v))?,
            Column::I64(v) => dict.set_item(name, PyArray1::from_vec(py, v))?,
            Column::Bool(v) => dict.set_item(name, PyArray1::from_vec(py, v))?,
        }
    }
    Ok(dict)
}

/// An `(n, 3)` float array of points.
pub(crate) fn points3<'py>(py: Python<'py>, points: &[[f64; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    let array = PyArray1::from_vec(py, flat);
    Ok(array.reshape([points.len(), 3])?.into_any())
}

/// An `(rows, cols)` array of `i8`, row by row.
pub(crate) fn grid_i8<'py>(
    py: Python<'py>,
    values: Vec<i8>,
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'py, PyArray2<i8>>> {
    PyArray1::from_vec(py, values).reshape([rows, cols])
}

/// A serialisable value as the Python object its JSON reads as (dicts, lists, numbers,
/// strings, `None`).
pub(crate) fn json_object<'py>(
    py: Python<'py>,
    value: &impl Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| crate::fail(format!("cannot convert a result to Python: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}
