#!/usr/bin/env bash
# The Python package's tests: builds the wheel (maturin, release, abi3), installs it with its
# test dependencies into a virtual environment under target/ (target/python-venv, made on
# first use from PYTHON; FOOTSLAM_VENV names another), and runs pytest on python/tests, which
# compares the package's results with the CLI's. Nothing is installed into PYTHON itself.
#
# Needs a Rust toolchain and network access to PyPI on first use. PYTHON picks the
# interpreter the environment is made from (default python3); extra arguments go to pytest
# (e.g. -k track).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
VENV="${FOOTSLAM_VENV:-target/python-venv}"
export PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_ROOT_USER_ACTION=ignore

if [[ ! -x "$VENV/bin/python" ]]; then
    "$PYTHON" -m venv "$VENV"
fi
PY="$VENV/bin/python"
"$PY" -m pip install --quiet "maturin>=1.9,<2" "pytest>=7" "numpy>=1.21" pandas "dask[distributed]" geopandas

wheels=target/python-wheels
rm -rf "$wheels"
"$PY" -m maturin build --release --quiet -m python/Cargo.toml -o "$wheels"
"$PY" -m pip install --quiet --force-reinstall --no-deps "$wheels"/footslam-*.whl

# The CLI the tests compare with (FOOTSLAM_BIN names one already built). Built with the
# workspace's features, it links the library the wheel's build just compiled, rather
# than compiling it again with the root package's narrower feature set.
if [[ -z "${FOOTSLAM_BIN:-}" ]]; then
    cargo build --release --workspace --bin footslam
fi

# From the repository root, so that python/footslam (the sources, without the compiled
# module) does not shadow the installed package.
"$PY" -m pytest -q python/tests "$@"
