#!/usr/bin/env bash
# The project's test command (README, CI): the Rust unit, integration and regression tests
# in release mode (the accuracy tests run real particle filters), then the Python
# package's tests (scripts/test_python.sh: builds the wheel with maturin, runs pytest,
# including the Dask batch runner on a local cluster).
set -euo pipefail
cd "$(dirname "$0")/.."
# --workspace: the features of the Python package's dependencies (pyo3, numpy) join the
# tests' build, so the wheel's build below reuses the compiled library (python/Cargo.toml).
cargo test --release --workspace "$@"
# The Python tests compare with the CLI binary the Rust tests just built.
FOOTSLAM_BIN="$PWD/target/release/footslam" scripts/test_python.sh
