//! How a pipeline reports its progress: named stages with a length, advanced as work is done,
//! and warnings a user should see while the run goes on. The library prints nothing; the
//! command line shows bars, Python may log, a cluster may count.

/// Receives a pipeline's progress. Every method has a do-nothing default; the methods take
/// `&self` and the trait is `Sync` because walks of a batch advance it from several threads.
pub trait Progress: Sync {
    /// A stage begins: `total` units of work (steps, walks) described by `stage`.
    fn start(&self, stage: &str, total: u64) {
        let _ = (stage, total);
    }

    /// `units` more of the current stage are done.
    fn advance(&self, units: u64) {
        let _ = units;
    }

    /// The current stage is over.
    fn finish(&self) {}

    /// Something the user should know now, before the run ends (a slow prior, a cap hit).
    fn warn(&self, message: &str) {
        let _ = message;
    }
}

/// Progress that goes nowhere: for callers that do not watch.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// Records what it is told.
    #[derive(Default)]
    struct Log(Mutex<Vec<String>>);

    impl Progress for Log {
        fn start(&self, stage: &str, total: u64) {
            self.0.lock().expect("log").push(format!("{stage}/{total}"));
        }
        fn advance(&self, units: u64) {
            self.0.lock().expect("log").push(format!("+{units}"));
        }
    }

    #[test]
    fn defaults_do_nothing_and_overrides_are_called() {
        let silent = Silent;
        silent.start("x", 3);
        silent.advance(1);
        silent.finish();
        silent.warn("w");
        let log = Log::default();
        log.start("tracking", 2);
        log.advance(1);
        log.finish();
        assert_eq!(*log.0.lock().expect("log"), ["tracking/2", "+1"]);
    }
}
