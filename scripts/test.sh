#!/usr/bin/env bash
# The project's test command (README, CI: .ci/run). The tests come in tiers
# (docs/testing.md):
#
#   scripts/test.sh          everything CI runs: the lints (scripts/lint.sh), the fast tier,
#                            the accuracy tier, then the Python package's tests
#   scripts/test.sh --fast   the fast tier only: the unit tests, the doc tests and the
#                            integration tests of tests/it/ (the command line end to end, bad
#                            input, golden outputs, formats, layout, viewer)
#
# The accuracy tier is tests/accuracy/: real particle filters held to accuracy thresholds,
# most of the time. The Python tests (scripts/test_python.sh) build the wheel with maturin
# and run pytest, including the Dask batch runner on a local cluster.
#
# Other arguments go to every `cargo test` run, e.g. a test-name filter (`scripts/test.sh
# --fast viewer`) or the test binaries' options (`-- --nocapture`). One binary alone:
# `cargo test --release --workspace --test accuracy NAME`.
set -euo pipefail
cd "$(dirname "$0")/.."

fast=false
args=()
while (($#)); do
    case $1 in
        --fast) fast=true ;;
        --) args+=("$@") && break ;;
        *) args+=("$1") ;;
    esac
    shift
done

# Each step is announced, timed, and named in the summary (or when it fails).
times=()
step=""
begin() { # SHORT-NAME DESCRIPTION
    finish
    step=$1
    started=$SECONDS
    printf '\n==== %s\n' "$2" >&2
}
finish() {
    if [[ -n $step ]]; then
        times+=("$step $((SECONDS - started)) s")
    fi
    step=""
}
summary() { # WHAT-RAN
    finish
    local joined
    joined=$(printf '%s, ' "${times[@]}")
    printf '\n==== passed, %s: %s\n' "$1" "${joined%, }" >&2
}
trap 'printf "\n==== failed: %s\n" "$step" >&2' ERR

# tests/it/viewer.rs loads `footslam view`'s page in headless Chromium
# (FOOTSLAM_SKIP_BROWSER=1 skips it): install Debian's package when it is missing and we may.
if ! command -v chromium >/dev/null && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    apt-get update -qq && apt-get install -y -qq chromium
fi

# --workspace everywhere: the features of the Python package's dependencies (pyo3, numpy)
# join the tests' build, so the wheel's build below reuses the compiled library
# (python/Cargo.toml), and every run below resolves the same features, so none of them
# compiles the library again.
if $fast; then
    begin "fast tier: unit+it" "fast tier: unit tests and tests/it (cargo test --lib --bins --test it)"
    cargo test --release --workspace --lib --bins --test it "${args[@]}"
    begin "fast tier: doc" "fast tier: doc tests (cargo test --doc)"
    cargo test --release --workspace --doc "${args[@]}"
    summary "the fast tier only (no lints, no accuracy tier, no Python tests)"
    exit 0
fi

begin lints "lints (scripts/lint.sh)"
scripts/lint.sh
# Everything `cargo test` builds, the examples too (built, not run), before the tiers run.
begin build "build (cargo test --no-run)"
cargo test --release --workspace --no-run "${args[@]}"
begin "fast tier: unit+it" "fast tier: unit tests and tests/it (cargo test --lib --bins --test it)"
cargo test --release --workspace --lib --bins --test it "${args[@]}"
begin "fast tier: doc" "fast tier: doc tests (cargo test --doc)"
cargo test --release --workspace --doc "${args[@]}"
begin "accuracy tier" "accuracy tier: tests/accuracy (cargo test --test accuracy)"
cargo test --release --workspace --test accuracy "${args[@]}"
# The Python tests compare with the CLI binary the Rust tests just built.
begin Python "Python tests (scripts/test_python.sh)"
FOOTSLAM_BIN="$PWD/target/release/footslam" scripts/test_python.sh
summary "lints and all tiers"
