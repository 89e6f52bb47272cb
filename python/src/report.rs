//! What a pipeline reports while it runs with the GIL released: its warnings, kept and issued
//! as Python warnings once the run is over, and its progress, passed to the caller's
//! ``progress(stage, done, total)`` callable (a tqdm bar, a log line) as it goes.

use crate::FootslamWarning;
use footslam::pipeline::Progress;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use std::sync::Mutex;

/// Progress calls per stage at most (beside its start and end): enough for a smooth bar,
/// few enough that taking the GIL for them costs nothing beside the filter.
const CALLS_PER_STAGE: u64 = 200;

/// The stage being run.
#[derive(Default)]
struct Stage {
    name: String,
    done: u64,
    total: u64,
    /// `done` when the callable was last called.
    reported: u64,
}

/// A [`Progress`] for the Python functions: keeps warnings, forwards progress.
#[derive(Default)]
pub(crate) struct Reporter {
    warnings: Mutex<Vec<String>>,
    callback: Option<Py<PyAny>>,
    stage: Mutex<Stage>,
    /// The first exception the callable raised: it is not called again, and the exception
    /// is raised when the run is over.
    error: Mutex<Option<PyErr>>,
}

impl Reporter {
    /// A reporter calling `progress` (``None``: none), which must be callable.
    pub(crate) fn new(progress: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let callback = match progress {
            Some(p) if !p.is_none() => {
                if !p.is_callable() {
                    return Err(PyTypeError::new_err(
                        "progress must be a callable progress(stage, done, total) or None",
                    ));
                }
                Some(p.clone().unbind())
            }
            _ => None,
        };
        Ok(Self {
            callback,
            ..Self::default()
        })
    }

    /// Adds a warning of this crate's own checks.
    pub(crate) fn push(&self, message: String) {
        self.warn(&message);
    }

    /// Ends the run: issues the warnings kept as [`FootslamWarning`]s, then raises the
    /// exception the progress callable raised, if it did.
    pub(crate) fn emit(&self, py: Python<'_>) -> PyResult<()> {
        let list = match self.warnings.lock() {
            Ok(mut list) => std::mem::take(&mut *list),
            Err(_) => Vec::new(),
        };
        let warnings = py.import("warnings")?;
        let category = py.get_type::<FootslamWarning>();
        for message in list {
            // stacklevel 1: called from native code, the nearest Python frame is the caller of
            // the footslam function.
            warnings.call_method1("warn", (message, &category, 1))?;
        }
        match self.error.lock().ok().and_then(|mut e| e.take()) {
            Some(error) => Err(error),
            None => Ok(()),
        }
    }

    /// Calls the callable with the GIL taken (from whichever thread the pipeline reports).
    fn call(&self, stage: &str, done: u64, total: u64) {
        let Some(callback) = &self.callback else {
            return;
        };
        if self.error.lock().map_or(true, |e| e.is_some()) {
            return;
        }
        let result = Python::attach(|py| callback.call1(py, (stage, done, total)).map(drop));
        if let (Err(error), Ok(mut slot)) = (result, self.error.lock()) {
            slot.get_or_insert(error);
        }
    }

    /// Updates the stage with `update`, and calls the callable when `update` says a call is
    /// due (the stage's lock released first: the callable may take its time).
    fn update(&self, update: impl FnOnce(&mut Stage) -> bool) {
        if self.callback.is_none() {
            return;
        }
        let due = self.stage.lock().ok().and_then(|mut stage| {
            update(&mut stage).then(|| {
                stage.reported = stage.done;
                (stage.name.clone(), stage.done, stage.total)
            })
        });
        if let Some((name, done, total)) = due {
            self.call(&name, done, total);
        }
    }
}

impl Progress for Reporter {
    fn start(&self, stage: &str, total: u64) {
        self.update(|s| {
            *s = Stage {
                name: stage.to_owned(),
                total,
                ..Stage::default()
            };
            true
        });
    }

    fn advance(&self, units: u64) {
        self.update(|s| {
            s.done = (s.done + units).min(s.total);
            let every = (s.total / CALLS_PER_STAGE).max(1);
            s.done > s.reported && (s.done == s.total || s.done - s.reported >= every)
        });
    }

    fn finish(&self) {
        self.update(|s| {
            let late = s.reported < s.total;
            s.done = s.total;
            late
        });
    }

    fn warn(&self, message: &str) {
        if let Ok(mut list) = self.warnings.lock() {
            list.push(message.to_owned());
        }
    }
}
