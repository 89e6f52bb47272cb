#!/usr/bin/env bash
# Time and peak memory of FootSLAM runs, one size per process (for BENCHMARKS.md).
# Usage: scripts/scaling.sh [SEED]
set -euo pipefail
cd "$(dirname "$0")/.."
seed="${1:-1}"
cargo build --release --example scaling >/dev/null 2>&1
echo "particles,steps,seconds,particle_steps_per_s,peak_rss_bytes,bytes_per_particle"
for n in 10000 30000 100000 300000 1000000; do ./target/release/examples/scaling "$n" 700 "$seed"; done
for s in 100 300 700 1400; do ./target/release/examples/scaling 30000 "$s" "$seed"; done
