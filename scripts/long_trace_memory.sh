#!/usr/bin/env bash
# Peak memory (RSS) and outputs of `learn` and `track` on long step traces: the benchmark of
# "memory grows with the filter, not the input" (docs/robustness.md, BENCHMARKS.md).
#
#   scripts/long_trace_memory.sh [STEPS] [WORK_DIR]
#
# learn: STEPS strides round a 30 m × 15 m corridor loop (0.7 m, σ 2 cm; heading noise
#        0.01 rad), 100 particles — a long walk in one building.
# track: the office simulator's 1000-lap walk without heading drift (so that the tracker
#        follows it, as on a real walk with a good plan), repeated to STEPS/10 steps (or
#        TRACK_STEPS), on its plan, from an unknown start.
# Needs GNU time (/usr/bin/time) and python3; run after `cargo build --release`.
set -euo pipefail
steps=${1:-8800000}
work=${2:-$(mktemp -d)}
bin=$(pwd)/target/release/footslam
mkdir -p "$work"
python3 - "$steps" "$work/loop.csv" <<'PY'
import math, random, sys
n, out = int(sys.argv[1]), sys.argv[2]
random.seed(1)
side = [43, 21, 43, 21]
t, k, c = 1.7e9, 0, 0
with open(out, "w") as f:
    f.write("t,length,dheading,dz\n")
    for _ in range(n):
        turn = 0.0
        if c == side[k % 4]:
            c, k, turn = 0, k + 1, math.pi / 2
        c += 1
        t += 0.5
        f.write(f"{t:.3f},{0.7 + random.gauss(0, 0.02):.4f},{turn + random.gauss(0, 0.01):.5f},0\n")
PY
"$bin" simulate --laps 1000 --out "$work/office_drift" > /dev/null
python3 - "$work/office_drift/config.json" "$work/nodrift.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
c["noise"]["drift_total"] = 0.0
c["noise"]["drift_rate_walk_sigma"] = 0.0
json.dump(c, open(sys.argv[2], "w"), indent=1)
PY
"$bin" simulate --config "$work/nodrift.json" --out "$work/office" > /dev/null
python3 - "$work/office/steps.csv" "${TRACK_STEPS:-$((steps / 10))}" "$work/office_long.csv" <<'PY'
import sys
src, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
lines = open(src).read().splitlines()
head, rows = lines[0], [l.split(",", 1) for l in lines[1:]]
span = float(rows[-1][0]) + 0.6
with open(out, "w") as f:
    f.write(head + "\n")
    k = 0
    while k * len(rows) < n:
        for t, rest in rows[: n - k * len(rows)]:
            f.write(f"{float(t) + 1.7e9 + k * span:.3f},{rest}\n")
        k += 1
PY
measure() {
    local name=$1 trace=$2; shift 2
    /usr/bin/time -v "$@" > "$work/$name.log" 2> "$work/$name.time"
    local rss wall
    rss=$(awk -F': ' '/Maximum resident/ {print $2}' "$work/$name.time")
    wall=$(awk -F': ' '/Elapsed/ {print $2}' "$work/$name.time")
    printf '%-6s %10s steps  peak %6.0f MB  %s  outputs %s\n' "$name" \
        "$(($(wc -l < "$trace") - 1))" "$((rss / 1024))" "$wall" "$(du -sh "$work/$name" | cut -f1)"
}
measure learn "$work/loop.csv" "$bin" learn --steps "$work/loop.csv" --particles 100 --out "$work/learn"
measure track "$work/office_long.csv" "$bin" track --steps "$work/office_long.csv" \
    --plan "$work/office/floor.geojson" --out "$work/track"
