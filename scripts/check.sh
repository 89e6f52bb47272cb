#!/usr/bin/env bash
# What a reviewer runs before merging: formatting, lints, tests, docs.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo fmt --all -- --check
cargo clippy --release --all-targets -- -D warnings
scripts/test.sh
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps
