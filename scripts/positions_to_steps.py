#!/usr/bin/env python3
"""Convert a per-step position log into a footslam step trace.

Many public pedestrian datasets and foot-mounted INS tools (OpenShoe, zero-velocity-update
INS implementations, ...) give one position per stance phase (step) rather than step
lengths and heading changes. This script turns CSV rows `t,x,y[,z]` (seconds, metres in
any local east-north frame) into footslam's `t,length,dheading,dz` (heading changes
counter-clockwise, radians), the first heading change relative to east so the trace
dead-reckons back onto the input positions when started at its first position.

    scripts/positions_to_steps.py positions.csv > steps.csv

Columns are found by name; extra columns are ignored. Rows with an unchanged position are
skipped (no step). Times must increase.
"""
import csv
import math
import sys


def main(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no rows")
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["t", "length", "dheading", "dz"])
    prev = None
    heading = 0.0
    for line, row in enumerate(rows, start=2):
        try:
            t, x, y = float(row["t"]), float(row["x"]), float(row["y"])
            z = float(row.get("z") or 0.0)
        except (KeyError, ValueError) as e:
            sys.exit(f"{path}:{line}: {e}")
        if prev is not None:
            pt, px, py, pz = prev
            if t <= pt:
                sys.exit(f"{path}:{line}: time {t} is not after {pt}")
            length = math.hypot(x - px, y - py)
            if length < 1e-6:
                continue
            new_heading = math.atan2(y - py, x - px)
            d = math.remainder(new_heading - heading, math.tau)
            heading = new_heading
            out.writerow([f"{t:.3f}", f"{length:.4f}", f"{d:.6f}", f"{z - pz:.4f}"])
        prev = (t, x, y, z)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
