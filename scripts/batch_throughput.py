#!/usr/bin/env python3
"""Throughput of the Dask batch runner with 1 and 2 workers (BENCHMARKS.md).

Simulates 5 office buildings × 20 one-lap walks with the CLI (target/release/footslam),
then runs footslam.batch.run_batch on a LocalCluster of 1 and of 2 single-thread worker
processes and prints walks per second; the maps of both runs must be equal.

Usage: python3 scripts/batch_throughput.py [PARTICLES]   (default 5000)

5,000 particles (a quarter of FootSLAM's default) make each walk-learning task about half a
second on one core, small beside a real walk's, yet large enough that the runner's own work
per task (Dask's scheduling, the tasks' Python) does not dominate; with 1,000 it shows
(BENCHMARKS.md gives both).
"""

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from dask.distributed import Client, LocalCluster

import footslam.batch

ROOT = Path(__file__).resolve().parents[1]
BIN = ROOT / "target" / "release" / "footslam"


def make(root: Path) -> Path:
    rows = ["building,steps,start"]
    for b in range(5):
        config = root / f"office-{b}.toml"
        config.write_text(
            f"[office]\nloop_width = {30 + 3 * b}\nloop_height = {18 + 2 * b}\n"
            f"rooms_per_long_side = {3 + b % 2}\n[walk]\nlaps = 1\n"
        )
        for w in range(20):
            out = root / f"b{b}" / f"w{w}"
            subprocess.run([BIN, "simulate", "--building", "office", "--config", config,
                            "--seed", str(1000 * b + w), "--out", out],
                           check=True, capture_output=True)
            rows.append(f'office-{b},b{b}/w{w}/steps.csv,"0,0,0"')
    manifest = root / "buildings.csv"
    manifest.write_text("\n".join(rows) + "\n")
    return manifest


def main() -> None:
    particles = int(sys.argv[1]) if len(sys.argv) > 1 else 5000
    with tempfile.TemporaryDirectory() as tmp:
        manifest = make(Path(tmp))
        merged = {}
        times = {}
        for workers in (1, 2):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1,
                                   processes=True, dashboard_address=None)
            with Client(cluster) as client:
                started = time.perf_counter()
                results = footslam.batch.run_batch(manifest, client, particles=particles, seed=1)
                times[workers] = time.perf_counter() - started
            cluster.close()
            merged[workers] = {b: r["merged"] for b, r in results.items()}
            tasks = sum(len(r["walks"]) * (r["passes"] + 1) for r in results.values())
            print(f"{workers} worker(s): {times[workers]:.1f} s, {tasks} walk-learning tasks, "
                  f"{tasks / times[workers]:.2f} tasks/s", flush=True)
        assert merged[1] == merged[2], "maps differ between 1 and 2 workers"
        print(f"speed-up with 2 workers: {times[1] / times[2]:.2f}x; maps identical")


if __name__ == "__main__":
    main()
