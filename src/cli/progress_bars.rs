//! The command line's face of [`footslam::pipeline::Progress`]: on stderr, a bar for the
//! stage (a walk's steps, or a batch's walks in total) and one bar per walk in progress
//! beside it; shown once the stage has lasted a second (at once with `--verbose`, never
//! with `--quiet`); warnings as `warning:` lines.
//!
//! The time left is the bar's average pace so far times the work left (a walk's bar starts
//! with its filter, after the set-up): a filter whose steps cost alike gets a steady
//! estimate, where an exponentially weighted rate swung with every slow step (it said
//! "eta 2m" for a run of 2 s).

use footslam::pipeline::Progress;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Progress bars on stderr.
#[derive(Debug, Default)]
pub struct Bars {
    current: Mutex<Option<Stage>>,
}

/// The stage being shown.
#[derive(Debug)]
struct Stage {
    multi: MultiProgress,
    bar: ProgressBar,
    /// The bars of items in progress, by item.
    items: BTreeMap<usize, ProgressBar>,
    started: Instant,
    shown: bool,
}

/// A bar style whose `{eta}` is the linear estimate: the bar's average pace so far times
/// the work left.
fn style(template: &str) -> ProgressStyle {
    let Ok(style) = ProgressStyle::with_template(template) else {
        return ProgressStyle::default_bar();
    };
    style.with_key(
        "eta",
        |state: &ProgressState, w: &mut dyn std::fmt::Write| {
            let (pos, len) = (state.pos(), state.len().unwrap_or(0));
            let spent = state.elapsed().as_secs_f64();
            if pos == 0 || spent < 0.5 {
                let _ = w.write_str("?");
            } else {
                let left = spent / pos as f64 * len.saturating_sub(pos) as f64;
                let _ = w.write_str(&human_duration(left));
            }
        },
    )
}

/// `75.0` → `1m15s`.
fn human_duration(seconds: f64) -> String {
    let s = seconds.round() as u64;
    let mut out = String::new();
    if s >= 3600 {
        let _ = write!(out, "{}h", s / 3600);
    }
    if s >= 60 {
        let _ = write!(out, "{}m", s / 60 % 60);
    }
    let _ = write!(out, "{}s", s % 60);
    out
}

impl Bars {
    fn with_stage(&self, f: impl FnOnce(&mut Option<Stage>)) {
        if let Ok(mut current) = self.current.lock() {
            f(&mut current);
        }
    }
}

impl Stage {
    /// Draws on stderr once the stage has lasted a second (at once with `--verbose`).
    fn maybe_show(&mut self) {
        let due = super::verbosity::verbose() || self.started.elapsed() > Duration::from_secs(1);
        if !self.shown && due && !super::verbosity::quiet() {
            self.multi.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
    }
}

impl Progress for Bars {
    fn start(&self, stage: &str, total: u64) {
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::hidden());
        let bar = multi.add(ProgressBar::new(total));
        bar.set_style(style(
            "{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} ({per_sec}, eta {eta})",
        ));
        bar.set_message(stage.to_string());
        self.with_stage(|current| {
            if let Some(old) = current.take() {
                old.bar.finish_and_clear();
            }
            let mut stage = Stage {
                multi,
                bar,
                items: BTreeMap::new(),
                started: Instant::now(),
                shown: false,
            };
            stage.maybe_show();
            *current = Some(stage);
        });
    }

    fn advance(&self, units: u64) {
        self.with_stage(|current| {
            if let Some(stage) = current {
                stage.maybe_show();
                stage.bar.inc(units);
            }
        });
    }

    fn finish(&self) {
        self.with_stage(|current| {
            if let Some(stage) = current.take() {
                for item in stage.items.values() {
                    item.finish_and_clear();
                }
                stage.bar.finish_and_clear();
            }
        });
    }

    fn warn(&self, message: &str) {
        self.with_stage(|current| match current {
            // Above the bars, not through them.
            Some(stage) if stage.shown => stage.multi.suspend(|| super::common::warn(message)),
            _ => super::common::warn(message),
        });
    }

    fn item_start(&self, item: usize, label: &str, total: u64) {
        self.with_stage(|current| {
            if let Some(stage) = current {
                let bar = stage.multi.add(ProgressBar::new(total));
                bar.set_style(style("  {msg:>8} {wide_bar} {pos}/{len} steps (eta {eta})"));
                bar.set_message(label.to_string());
                if let Some(old) = stage.items.insert(item, bar) {
                    old.finish_and_clear();
                }
            }
        });
    }

    fn item_advance(&self, item: usize, units: u64) {
        self.with_stage(|current| {
            if let Some(stage) = current {
                stage.maybe_show();
                if let Some(bar) = stage.items.get(&item) {
                    bar.inc(units);
                }
            }
        });
    }

    fn item_finish(&self, item: usize) {
        self.with_stage(|current| {
            if let Some(bar) = current.as_mut().and_then(|s| s.items.remove(&item)) {
                bar.finish_and_clear();
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_as_people_say_them() {
        assert_eq!(human_duration(0.4), "0s");
        assert_eq!(human_duration(75.0), "1m15s");
        assert_eq!(human_duration(3725.0), "1h2m5s");
    }

    #[test]
    fn items_come_and_go_beside_the_stage() {
        let bars = Bars::default();
        bars.start("learning walks", 2);
        bars.item_start(0, "walk 1", 10);
        bars.item_start(1, "walk 2", 10);
        bars.item_advance(0, 3);
        bars.item_finish(0);
        bars.advance(1);
        let items = |b: &Bars| {
            b.current
                .lock()
                .expect("lock")
                .as_ref()
                .map_or(0, |s| s.items.len())
        };
        assert_eq!(items(&bars), 1);
        bars.finish();
        assert_eq!(items(&bars), 0);
        // Items without a stage are ignored.
        bars.item_start(5, "walk 6", 1);
        bars.item_advance(5, 1);
        bars.item_finish(5);
    }
}
