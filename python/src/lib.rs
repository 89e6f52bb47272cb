//! Python bindings of footslam (`import footslam`): the library's pipelines — steps from raw
//! IMU data, FootSLAM on one walk or a batch, merging maps, plans from learned maps, tracking
//! on known floor plans and WiFi radio surveys — over numpy arrays, pandas frames or files.
//!
//! Each function reads its inputs into the job's request as the command line reads its
//! files (the same readers), runs the job of [`footslam::pipeline`] — its prepare stage
//! makes the same checks, so the same errors — with the GIL released, and returns numpy
//! arrays, GeoJSON dicts and the job's report (`summary.json`) as a dict. Library errors become
//! [`FootslamError`] (a `ValueError`) with the command line's message, a missing file
//! `FileNotFoundError`, input of the wrong type `TypeError`.
//!
//! * `steps.rs`: `steps` — raw IMU recording → step events
//! * `learn.rs`, `maps.rs`: `learn`, `learn_one`, `others_map`, `feetslam_passes` — FootSLAM,
//!   and a batch fanned out walk by walk
//! * `maps.rs`: `merge`, `plan` — maps combined, a map as a floor plan
//! * `track.rs`: `track` — one walk on a known floor plan
//! * `survey.rs`: `survey` — a WiFi radio map from walks on a known plan

// The doc comments on the Python functions are their docstrings, written in reST (``x`` for
// code, `x:` for a parameter), not rustdoc's Markdown.
#![allow(clippy::doc_markdown)]

use pyo3::prelude::*;

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
        // The option that fixes it, as a keyword argument.
        footslam::Error::Remedied { problem, remedy } => {
            use footslam::error::RemedyValue;
            let keyword = match remedy.value {
                RemedyValue::Flag => format!("{}=True", remedy.option),
                RemedyValue::Number(v) => format!("{}={v}", remedy.option),
                RemedyValue::LatLon(lat, lon) => format!("{}=({lat}, {lon})", remedy.option),
                RemedyValue::Described(what) => format!("{}=<{what}>", remedy.option),
            };
            FootslamError::new_err(format!("{problem}, or pass {keyword}"))
        }
        _ => FootslamError::new_err(error.to_string()),
    }
}

/// An optional integer argument `value` named `name` as a `u64` no larger than `max`: a
/// negative or too large integer is a `ValueError` naming the argument and its range (not
/// Python's bare `OverflowError`); a non-integer a `TypeError`.
pub(crate) fn int_arg(
    name: &str,
    value: Option<&Bound<'_, PyAny>>,
    max: u64,
) -> PyResult<Option<u64>> {
    let Some(v) = value else {
        return Ok(None);
    };
    if v.is_instance_of::<pyo3::types::PyBool>() || !v.is_instance_of::<pyo3::types::PyInt>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "{name} must be an integer, got {}",
            v.repr()?
        )));
    }
    match v.extract::<u64>() {
        Ok(n) if n <= max => Ok(Some(n)),
        _ => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{name} = {} is out of range: it must be an integer from 0 to {max}",
            v.repr()?
        ))),
    }
}

/// A [`FootslamError`] with `message` (a check of this crate's, worded as the command
/// line's).
pub(crate) fn fail(message: impl Into<String>) -> PyErr {
    FootslamError::new_err(message.into())
}

/// Most worker threads per core (as the command line's `--threads`).
const THREADS_PER_CORE: usize = 4;

/// Runs `work` with the GIL released, on `threads` worker threads (`None` or 0: the global
/// pool, one thread per core; more than [`THREADS_PER_CORE`] a core are capped with a
/// warning). Results do not depend on the thread count.
pub(crate) fn detached<T, F>(py: Python<'_>, threads: Option<usize>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> PyResult<T> + Send,
{
    let pool = match threads {
        None | Some(0) => None,
        Some(wanted) => Some(
            // As the command line does: beyond a few threads per core, scheduling alone takes
            // minutes, and the results do not depend on the count.
            {
                let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
                let cap = THREADS_PER_CORE * cores;
                let n = wanted.min(cap);
                if wanted > cap {
                    py.import("warnings")?.call_method1(
                        "warn",
                        (
                            format!(
                                "threads={wanted} capped at {cap} ({THREADS_PER_CORE} per core on {cores} cores); results do not depend on the thread count"
                            ),
                            py.get_type::<FootslamWarning>(),
                            1,
                        ),
                    )?;
                }
                n
            },
        ),
    };
    let pool = match pool {
        None => None,
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
    m.add_function(wrap_pyfunction!(radio::fingerprint, m)?)?;
    m.add_function(wrap_pyfunction!(track::track, m)?)?;
    m.add_function(wrap_pyfunction!(survey::survey, m)?)?;
    Ok(())
}
