"""Shared fixtures: the command-line binary, small simulated walks, and CLI runs.

The suite compares ``footslam`` (Python) with ``footslam`` (the command line) on the same
inputs and seeds. The binary is ``$FOOTSLAM_BIN``, else ``target/release/footslam`` of this
checkout (built with ``cargo build --release`` when missing).
"""

import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"


def _binary():
    given = os.environ.get("FOOTSLAM_BIN")
    if given:
        return Path(given).resolve()
    path = ROOT / "target" / "release" / "footslam"
    if not path.is_file():
        if shutil.which("cargo") is None:
            pytest.skip("no footslam binary and no cargo to build it")
        subprocess.run(
            ["cargo", "build", "--release", "--bin", "footslam"], cwd=ROOT, check=True
        )
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs ``footslam ARGS`` in the repository root; returns the completed process
    (``check=False``: errors are the caller's to read)."""
    binary = _binary()

    def run(*args, check=True):
        done = subprocess.run(
            [str(binary), *map(str, args)], cwd=ROOT, capture_output=True, text=True
        )
        if check and done.returncode != 0:
            raise AssertionError(f"footslam {' '.join(map(str, args))}: {done.stderr}")
        return done

    return run


@pytest.fixture(scope="session")
def sim(cli, tmp_path_factory):
    """Small simulated walks: two of an office floor (one lap each), one of a three-floor
    tower with WiFi (two minutes) and one of a campus with GPS fixes and an outline."""
    root = tmp_path_factory.mktemp("sim")
    cli("simulate", "--building", "office", "--laps", 1, "--seed", 3, "--out", root / "office")
    cli("simulate", "--building", "office", "--laps", 1, "--seed", 8, "--out", root / "office2")
    cli("simulate", "--building", "tower", "--minutes", 2, "--seed", 4, "--out", root / "tower")
    cli("simulate", "--building", "campus", "--seed", 1, "--origin", "48.15,11.57",
        "--out", root / "campus")
    return root


def read_csv(path):
    """A CSV file as a dict of float arrays, one per column."""
    table = np.genfromtxt(path, delimiter=",", names=True, dtype=float, ndmin=1)
    return {name: table[name] for name in table.dtype.names}


def read_json(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def cli_error(done):
    """The message of a failed command (its ``error: `` line, without the prefix)."""
    assert done.returncode != 0, done.stdout
    lines = [l for l in done.stderr.splitlines() if l.startswith("error: ")]
    assert lines, done.stderr
    return lines[-1][len("error: ") :]


# What may differ between two runs of one job: how long they took and the memory held.
VARYING = {"runtime_s", "filter_runtime_s", "particle_steps_per_s", "peak_memory_bytes",
           "speed_vs_real_time"}


def same_report(got, expected, path="summary"):
    """The dict Python returns and the summary.json the CLI writes hold the same keys and
    values (one report struct), all but runtimes; a difference names its key."""
    if isinstance(expected, dict):
        assert isinstance(got, dict) and sorted(got) == sorted(expected), \
            f"{path}: keys {sorted(got)} vs {sorted(expected)}"
        for k, v in expected.items():
            if k not in VARYING:
                same_report(got[k], v, f"{path}.{k}")
    elif isinstance(expected, list):
        assert isinstance(got, list) and len(got) == len(expected), \
            f"{path}: {len(got)} items vs {len(expected)}"
        for i, (g, e) in enumerate(zip(got, expected)):
            same_report(g, e, f"{path}[{i}]")
    else:
        assert got == expected, f"{path}: {got!r} vs {expected!r}"
    return True
