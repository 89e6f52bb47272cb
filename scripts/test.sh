#!/usr/bin/env bash
# The project's test command (README, CI): the Rust unit, integration and regression tests
# in release mode (the accuracy tests run real particle filters), then the Python
# package's tests (scripts/test_python.sh: builds the wheel with maturin, runs pytest,
# including the Dask batch runner on a local cluster).
set -euo pipefail
cd "$(dirname "$0")/.."
# tests/it/viewer.rs loads `footslam view`'s page in headless Chromium (FOOTSLAM_SKIP_BROWSER=1
# skips it): install Debian's package when it is missing and we may.
if ! command -v chromium >/dev/null && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    apt-get update -qq && apt-get install -y -qq chromium
fi
# --workspace: the features of the Python package's dependencies (pyo3, numpy) join the
# tests' build, so the wheel's build below reuses the compiled library (python/Cargo.toml).
cargo test --release --workspace "$@"
# The Python tests compare with the CLI binary the Rust tests just built.
FOOTSLAM_BIN="$PWD/target/release/footslam" scripts/test_python.sh
