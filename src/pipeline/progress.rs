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

    /// Item `item` of the current stage (a walk of a batch; items may run in parallel)
    /// begins: `total` units of its own work (steps), described by `label`.
    fn item_start(&self, item: usize, label: &str, total: u64) {
        let _ = (item, label, total);
    }

    /// `units` more of item `item` are done.
    fn item_advance(&self, item: usize, units: u64) {
        let _ = (item, units);
    }

    /// Item `item` is over.
    fn item_finish(&self, item: usize) {
        let _ = item;
    }
}

/// One item of a stage seen as a stage of its own: what a walk's filter reports
/// ([`Progress::start`], [`Progress::advance`]) becomes its item's progress, beside the
/// batch's total.
pub struct ItemProgress<'a> {
    /// Where the item's progress goes.
    pub inner: &'a dyn Progress,
    /// The item's index.
    pub item: usize,
    /// Its label (e.g. `walk 3`).
    pub label: String,
}

impl Progress for ItemProgress<'_> {
    fn start(&self, _stage: &str, total: u64) {
        self.inner.item_start(self.item, &self.label, total);
    }
    fn advance(&self, units: u64) {
        self.inner.item_advance(self.item, units);
    }
    fn finish(&self) {
        self.inner.item_finish(self.item);
    }
    fn warn(&self, message: &str) {
        self.inner.warn(message);
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
    fn an_item_reports_as_its_own_stage() {
        #[derive(Default)]
        struct Items(Mutex<Vec<String>>);
        impl Progress for Items {
            fn item_start(&self, item: usize, label: &str, total: u64) {
                self.0
                    .lock()
                    .expect("log")
                    .push(format!("{item}:{label}/{total}"));
            }
            fn item_advance(&self, item: usize, units: u64) {
                self.0.lock().expect("log").push(format!("{item}+{units}"));
            }
            fn item_finish(&self, item: usize) {
                self.0.lock().expect("log").push(format!("{item}."));
            }
        }
        let items = Items::default();
        let walk = ItemProgress {
            inner: &items,
            item: 2,
            label: "walk 3".into(),
        };
        walk.start("learning", 10);
        walk.advance(4);
        walk.finish();
        assert_eq!(*items.0.lock().expect("log"), ["2:walk 3/10", "2+4", "2."]);
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
