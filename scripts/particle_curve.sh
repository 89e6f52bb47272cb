#!/usr/bin/env bash
# Accuracy against particle count: p95 error (rigid alignment) of `footslam learn` on
# simulated 3-lap office walks, several seeds per count (for BENCHMARKS.md).
# Usage: scripts/particle_curve.sh [SEEDS...]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release >/dev/null 2>&1
bin=./target/release/footslam
seeds=("${@:-11 12 13 14 15}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "particles,seed,p95_m,dead_reckoning_p95_m,seconds"
for seed in ${seeds[@]}; do
  $bin simulate --seed "$seed" --out "$tmp/sim$seed" >/dev/null
done
for n in 1000 3000 10000 20000 50000 100000; do
  for seed in ${seeds[@]}; do
    $bin learn --steps "$tmp/sim$seed/steps.csv" --particles "$n" --out "$tmp/l" >/dev/null
    p95=$($bin eval --json --align rigid --truth "$tmp/sim$seed/truth.csv" --track "$tmp/l/track.csv" \
      --steps "$tmp/sim$seed/steps.csv" | python3 -c 'import json,sys; d=json.load(sys.stdin); print("%.3f,%.3f" % (d["track"]["p95"], d["dead_reckoning"]["p95"]))')
    secs=$(python3 -c 'import json,sys; print("%.2f" % json.load(open(sys.argv[1]))["filter_runtime_s"])' "$tmp/l/summary.json")
    echo "$n,$seed,$p95,$secs"
  done
done
