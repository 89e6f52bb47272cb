//! Python bindings of footslam (`import footslam`): the library's pipelines — steps from raw
//! IMU data, FootSLAM on one walk or a batch, merging maps, plans from learned maps, tracking
//! on known floor plans and WiFi radio surveys — over numpy arrays, pandas frames or files.
//!
//! Each function reads its inputs as the command line reads its files (the same readers and
//! checks, so the same errors), runs one [`footslam::pipeline`] function with the GIL
//! released, and returns numpy arrays and GeoJSON dicts. Library errors become
//! [`FootslamError`] (a `ValueError`) with the command line's message, a missing file
//! `FileNotFoundError`, input of the wrong type `TypeError`.
//!
//! * `steps.rs`: `steps` — raw IMU recording → step events
//! * `learn.rs`, `maps.rs`: `learn`, `learn_one`, `others_map`, `feetslam_passes` — FootSLAM,
//!   and a batch fanned out walk by walk
//! * `maps.rs`: `merge`, `plan` — maps combined, a map as a floor plan
//! * `track.rs`: `track` — one walk on a known floor plan
//! * `survey.rs`: `survey` — a WiFi radio map from walks on a known plan

use pyo3::prelude::*;

mod checks;
mod inputs;
mod learn;
mod learn_inputs;
mod learn_outputs;
mod maps;
mod outputs;
mod radio;
mod report;
mod steps;
mod survey;
mod tables;
mod track;

pub(crate) use report::Reporter;

pyo3::create_exception!(
    footslam,
    FootslamError,
    pyo3::exceptions::PyValueError,
    "Bad data, a bad configuration or inputs that do not belong together, as footslam's \
     library reports them: the message is the one the command line prints."
);

pyo3::create_exception!(
    footslam,
    FootslamWarning,
    pyo3::exceptions::PyUserWarning,
    "Something a run found that may make its result wrong (the command line's `warning:` lines)."
);

/// The Python exception of a library error: `FileNotFoundError` for a file that is not
/// there, `OSError` for other I/O errors, [`FootslamError`] for the rest; the message is the
/// library's.
pub(crate) fn py_error(error: footslam::Error) -> PyErr {
    match &error {
        footslam::Error::Io { error: io, .. } if io.kind() == std::io::ErrorKind::NotFound => {
            pyo3::exceptions::PyFileNotFoundError::new_err(error.to_string())
        }
        footslam::Error::Io { .. } => pyo3::exceptions::PyOSError::new_err(error.to_string()),
        _ => FootslamError::new_err(error.to_string()),
    }
}

/// A [`FootslamError`] with `message` (a check of this crate's, worded as the command
/// line's).
pub(crate) fn fail(message: impl Into<String>) -> PyErr {
    FootslamError::new_err(message.into())
}

/// A library error with `context` before its message, as the command line's
/// `with_context` prints it (`context: message`).
pub(crate) fn with_context(context: impl std::fmt::Display) -> impl Fn(footslam::Error) -> PyErr {
    move |error| match error {
        footslam::Error::Io { .. } => py_error(error),
        other => fail(format!("{context}: {other}")),
    }
}

/// Runs `work` with the GIL released, on `threads` worker threads (`None` or 0: the global
/// pool, one thread per core). Results do not depend on the thread count.
pub(crate) fn detached<T, F>(py: Python<'_>, threads: Option<usize>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> PyResult<T> + Send,
{
    let pool = match threads {
        None | Some(0) => None,
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| fail(format!("cannot start {n} worker threads: {e}")))?,
        ),
    };
    // PyErr is Send: an error made while detached is raised once the GIL is back.
    py.detach(move || match pool {
        Some(pool) => pool.install(work),
        None => work(),
    })
}

/// The module `footslam._footslam`.
#[pymodule]
fn _footslam(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("FootslamError", py.get_type::<FootslamError>())?;
    m.add("FootslamWarning", py.get_type::<FootslamWarning>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(steps::steps, m)?)?;
    m.add_function(wrap_pyfunction!(learn::learn, m)?)?;
    m.add_function(wrap_pyfunction!(learn::learn_one, m)?)?;
    m.add_function(wrap_pyfunction!(learn::feetslam_passes, m)?)?;
    m.add_function(wrap_pyfunction!(maps::others_map, m)?)?;
    m.add_function(wrap_pyfunction!(maps::merge, m)?)?;
    m.add_function(wrap_pyfunction!(maps::plan, m)?)?;
    m.add_function(wrap_pyfunction!(radio::radio_map, m)?)?;
    m.add_function(wrap_pyfunction!(track::track, m)?)?;
    m.add_function(wrap_pyfunction!(survey::survey, m)?)?;
    Ok(())
}
