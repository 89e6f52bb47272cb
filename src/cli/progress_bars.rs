//! The command line's face of [`footslam::pipeline::Progress`]: a bar on stderr per stage,
//! shown only once the stage has lasted a second, and warnings as `warning:` lines.

use footslam::pipeline::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
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
    bar: ProgressBar,
    started: Instant,
    shown: bool,
}

impl Bars {
    fn with_stage(&self, f: impl FnOnce(&mut Option<Stage>)) {
        if let Ok(mut current) = self.current.lock() {
            f(&mut current);
        }
    }
}

impl Progress for Bars {
    fn start(&self, stage: &str, total: u64) {
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template(
            "{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} ({per_sec}, eta {eta})",
        ) {
            bar.set_style(style);
        }
        bar.set_message(stage.to_string());
        self.with_stage(|current| {
            if let Some(old) = current.take() {
                old.bar.finish_and_clear();
            }
            *current = Some(Stage {
                bar,
                started: Instant::now(),
                shown: false,
            });
        });
    }

    fn advance(&self, units: u64) {
        self.with_stage(|current| {
            if let Some(stage) = current {
                if !stage.shown && stage.started.elapsed() > Duration::from_secs(1) {
                    stage.bar.set_draw_target(ProgressDrawTarget::stderr());
                    stage.shown = true;
                }
                stage.bar.inc(units);
            }
        });
    }

    fn finish(&self) {
        self.with_stage(|current| {
            if let Some(stage) = current.take() {
                stage.bar.finish_and_clear();
            }
        });
    }

    fn warn(&self, message: &str) {
        super::common::warn(message);
    }
}
