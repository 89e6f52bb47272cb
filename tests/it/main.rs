//! The fast tier of the integration tests (`scripts/test.sh --fast`, docs/testing.md): the
//! command line end to end, bad and silently wrong input, golden outputs and regressions,
//! file formats, the source tree's layout, the viewer. One test binary, as ripgrep has it:
//! each former `tests/NAME.rs` is a module here, and the library is linked once, not once
//! per file. The statistical accuracy tests, which run real particle filters for minutes,
//! are the second tier, `tests/accuracy/`.
//!
//! Paths are taken from `env!("CARGO_MANIFEST_DIR")` (the repository root), so a module
//! reads `tests/data/` and `tests/golden/` wherever it lies.

mod cli_cases;

mod anchors_cli;
mod bad_input;
mod bundled_data;
mod cli;
mod eval_waypoints;
mod fingerprint;
mod foot_ins;
mod fuzz_replay;
mod import;
mod layout;
mod mount_configs;
mod outputs_unchanged;
mod phone_pdr;
mod pipeline;
mod properties;
mod quality;
mod regression;
mod rfc7946;
mod shards;
mod silent_wrongs;
mod steps_cli;
mod track;
mod track_outputs_unchanged;
mod track_walks;
mod valid_geometry;
mod viewer;
