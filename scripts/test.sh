#!/usr/bin/env bash
# The project's test command (README, CI): unit, integration and regression tests in
# release mode (the accuracy tests run real particle filters).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release "$@"
