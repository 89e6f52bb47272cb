#!/usr/bin/env python3
"""Is the magnetic field's magnitude a place signature on the IPIN 2023 museum logs?

For every route under LOGS (files `..._TrainingTrial<route>_repetition<k>.txt`), every pair
of consecutive surveyed points (POSI ids a -> b) that several repetitions walk is cut out of
each repetition's magnetometer stream (MAGN, calibrated µT) and resampled to N points by
time between the two points (so walking speed adds error). Printed: the median RMS
difference of the magnitude profiles of the same segment in two repetitions, against a
random other segment's, and the median spread of the magnitude within a segment. A field
that is a place signature repeats much more closely than it differs between places
(MagSLAM, Robertson et al., IPIN 2013).

    scripts/museum_magnetic.py [--logs DIR] [--points N] [--seed S]
"""
import argparse
import glob
import math
import random
import statistics


def load(path):
    """(t, |m|) of every MAGN line and (t, id) of every POSI line."""
    field, points = [], []
    with open(path) as f:
        for line in f:
            p = line.strip().split(";")
            if p[0] == "MAGN":
                field.append((float(p[1]), math.sqrt(sum(float(v) ** 2 for v in p[3:6]))))
            elif p[0] == "POSI":
                points.append((float(p[1]), int(p[2])))
    return field, points


def profile(field, t0, t1, n):
    """The mean magnitude in each of n equal time slices of [t0, t1]; None if one is empty."""
    out = []
    for i in range(n):
        lo, hi = t0 + (t1 - t0) * i / n, t0 + (t1 - t0) * (i + 1) / n
        w = [m for t, m in field if lo <= t < hi]
        if not w:
            return None
        out.append(sum(w) / len(w))
    return out


def rms(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)) / len(a))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--logs", default="../shared/data/ipin2023-museum/logs")
    ap.add_argument("--points", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    files = sorted(glob.glob(f"{a.logs}/*_TrainingTrial*_repetition*.txt"))
    routes = sorted({f.split("TrainingTrial")[1].split("_")[0] for f in files})
    same, other, spread = [], [], []
    for route in routes:
        segments = {}
        for r, f in enumerate(sorted(g for g in files if f"TrainingTrial{route}_" in g)):
            field, points = load(f)
            for (t0, i0), (t1, i1) in zip(points, points[1:]):
                p = profile(field, t0, t1, a.points)
                if p:
                    segments.setdefault((i0, i1), {})[r] = p
        every = [p for d in segments.values() for p in d.values()]
        for d in segments.values():
            reps = sorted(d)
            for i, ri in enumerate(reps):
                spread.append(statistics.pstdev(d[ri]))
                for rj in reps[i + 1:]:
                    same.append(rms(d[ri], d[rj]))
                    other.append(rms(d[ri], rng.choice(every)))
    print(f"routes {', '.join(routes)}; segment pairs compared: {len(same)}")
    print(f"same segment, another repetition: median RMS difference {statistics.median(same):.1f} µT")
    print(f"a random other segment:           median RMS difference {statistics.median(other):.1f} µT")
    print(f"spread of the magnitude within a segment: median {statistics.median(spread):.1f} µT")


if __name__ == "__main__":
    main()
