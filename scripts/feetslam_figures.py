#!/usr/bin/env python3
"""FootSLAM on many short real walks with known starts (FeetSLAM), against PDR alone.

Runs footslam end to end on a folder of imported walks, as `footslam import ilc` writes them
(one sub-folder per walk with imu.csv and waypoints.csv; floor.geojson at the top):

1. `footslam steps --mount phone` on every walk (skipped when OUT/WALK/steps/steps.csv exists);
2. `footslam learn --walks` on all of them at once, each from its first waypoint (heading
   from the steps' absolute heading): one map in one frame, with the configured FeetSLAM
   iterations (each walk against the merged map of the others);
3. the error at every later waypoint of every walk, of the learned track and of PDR alone
   from the same start (`footslam eval --waypoints --steps`);
4. the learned walkable plan (merged_plan.geojson) against the floor's walkable area
   (outline minus shops): precision by area (`footslam eval --learned-plan --plan`).

Prints a table and writes figures.json into OUT.

    scripts/feetslam_figures.py IMPORTED_DIR OUT [--particles N] [--seed N] [--config FILE] [--wifi]
"""
import argparse
import json
import os
import sys

from progress import Progress
from real_data_figures import footslam, percentile


def first_waypoint(path):
    with open(path) as f:
        next(f)
        t, x, y = map(float, next(f).split(",")[:3])
    return t, x, y


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("imported")
    ap.add_argument("out")
    ap.add_argument("--binary", default="target/release/footslam")
    ap.add_argument("--particles", default="5000")
    ap.add_argument("--seed", default="0")
    ap.add_argument("--config", help="FootSLAM configuration for learn (TOML)")
    ap.add_argument("--wifi", action="store_true",
                    help="give learn each walk's wifi.csv (its scans weigh inside the filter)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    plan = os.path.join(a.imported, "floor.geojson")
    walks = sorted(
        d for d in os.listdir(a.imported)
        if os.path.isfile(os.path.join(a.imported, d, "imu.csv"))
        and os.path.isfile(os.path.join(a.imported, d, "waypoints.csv"))
    )
    if not walks:
        sys.exit(f"no walks (folders with imu.csv and waypoints.csv) under {a.imported}")
    manifest = os.path.join(a.out, "walks.csv")
    with open(manifest, "w") as m:
        m.write("steps,wifi,start\n" if a.wifi else "steps,start\n")
        bar = Progress(len(walks), "walks' steps")
        for w in walks:
            bar.start(w)
            steps = os.path.join(a.out, w, "steps", "steps.csv")
            if not os.path.isfile(steps):
                footslam(a.binary, "steps", "--imu", os.path.join(a.imported, w, "imu.csv"),
                         "--mount", "phone", "--out", os.path.dirname(steps))
            bar.done(w)
            _, x0, y0 = first_waypoint(os.path.join(a.imported, w, "waypoints.csv"))
            wifi = os.path.abspath(os.path.join(a.imported, w, "wifi.csv"))
            wifi = (f"{wifi}," if os.path.isfile(wifi) else ",") if a.wifi else ""
            m.write(f"{os.path.abspath(steps)},{wifi}\"{x0},{y0}\"\n")
        bar.finish()
    learned = os.path.join(a.out, "learn")
    cfg = ["--config", a.config] if a.config else []
    footslam(a.binary, "learn", "--walks", manifest, "--particles", a.particles, "--seed", a.seed,
             *cfg, "--out", learned, live=True)
    with open(os.path.join(learned, "summary.json")) as f:
        summary = json.load(f)

    slam, pdr, per_walk = [], [], []
    bar = Progress(len(walks), "walks scored")
    for i, w in enumerate(walks, start=1):
        bar.start(w)
        wps = os.path.join(a.imported, w, "waypoints.csv")
        t0, _, _ = first_waypoint(wps)
        v = json.loads(footslam(a.binary, "eval", "--json", "--waypoints", wps, "--track",
                                os.path.join(learned, f"walk-{i}", "track.csv"), "--steps",
                                os.path.join(a.out, w, "steps", "steps.csv")))
        keep = lambda pts: [p["error"] for p in pts or [] if p["t"] != t0]
        s, d = keep(v["waypoints"]), keep(v.get("dead_reckoning_waypoints"))
        slam += s
        pdr += d
        per_walk.append({"walk": w, "waypoints": len(s),
                         "footslam_median_m": percentile(s, 50), "pdr_median_m": percentile(d, 50)})
        bar.done(w, f"FootSLAM median {percentile(s, 50):.2f} m, PDR median {percentile(d, 50):.2f} m ({len(s)} waypoints)")
    bar.finish()

    # Precision of the learned walkable area against the floor's (outline minus shops). The
    # walks' own waypoints stand in for the truth track (recall needs a dense truth).
    merged_plan = os.path.join(learned, "merged_plan.geojson")
    first = walks[0]
    v = json.loads(footslam(a.binary, "eval", "--json", "--truth",
                            os.path.join(a.imported, first, "waypoints.csv"), "--track",
                            os.path.join(learned, "walk-1", "track.csv"), "--learned-plan",
                            merged_plan, "--plan", plan))
    overlap = v.get("plan_overlap") or {}
    figures = {
        "walks": len(walks),
        "particles": int(a.particles),
        "iterations": summary.get("iterations"),
        "runtime_s": summary.get("runtime_s"),
        "footslam": {"n": len(slam), "median_m": percentile(slam, 50), "p90_m": percentile(slam, 90)},
        "pdr": {"n": len(pdr), "median_m": percentile(pdr, 50), "p90_m": percentile(pdr, 90)},
        "learned_plan_precision": overlap.get("precision"),
        "learned_plan_m2": overlap.get("learned_m2"),
        "per_walk": per_walk,
    }
    with open(os.path.join(a.out, "figures.json"), "w") as f:
        json.dump(figures, f, indent=2)
    print()
    print(f"| {len(walks)} walks, {a.particles} particles, {figures['iterations']} iterations | median | p90 | n |")
    print("|---|---|---|---|")
    for name, key in [("FootSLAM (one map of all walks)", "footslam"), ("PDR alone, same starts", "pdr")]:
        r = figures[key]
        print(f"| {name} | {r['median_m']:.2f} m | {r['p90_m']:.2f} m | {r['n']} |")
    print(f"learned walkable plan: precision {overlap.get('precision')} over {overlap.get('learned_m2')} m²")


if __name__ == "__main__":
    main()
