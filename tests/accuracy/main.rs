//! The accuracy tier of the integration tests (docs/testing.md): real particle filters on
//! simulated walks, held to accuracy thresholds (p95 errors, steps to localise, coverage,
//! ratios to dead reckoning), and every other test that takes more than about ten seconds.
//! Most of this binary's time is here; `scripts/test.sh` runs it after the fast tier
//! (`tests/it/`), `scripts/test.sh --fast` leaves it out. Each former `tests/NAME.rs` is a
//! module; `common` is what they share.

mod common;

mod feetslam;
mod gait_events;
mod hexmap_prior;
mod learn_accuracy;
mod learned_plan;
mod learned_radio_map;
mod magnetic_slam;
mod radio_survey;
mod rf_localisation;
mod track_accuracy;
mod world_anchoring;
