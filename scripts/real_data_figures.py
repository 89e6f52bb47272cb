#!/usr/bin/env python3
"""Figures on real phone recordings with sparse ground truth (waypoints).

Runs footslam end to end on a folder of imported walks, as `footslam import ilc` writes them
(one sub-folder per walk with imu.csv, wifi.csv, waypoints.csv; floor.geojson at the top):

1. `footslam steps --mount phone` on every walk;
2. PDR alone from the first waypoint (the steps' absolute heading), error at later waypoints;
3. `footslam track` on the floor plan from the first waypoint's position (heading unknown),
   error at later waypoints;
4. radio map: `footslam survey` of every other walk (known starts, manifest `start` column),
   then the remaining walks localised from an unknown start with WiFi + the radio map
   (`track --radiomap --wifi`), against the radio map alone (`footslam fingerprint`).

Errors are pooled over every waypoint after the first of every walk; the first waypoint is
the start. Prints a table and writes figures.json into OUT.

    scripts/real_data_figures.py IMPORTED_DIR OUT [--track-config FILE] [--seed N]
"""
import argparse
import json
import os
import statistics
import subprocess

from progress import Progress
import sys


def footslam(binary, *args, live=False):
    """Runs `footslam ARGS` and returns its stdout. `live`: its stderr (progress bars,
    warnings) goes to ours as it runs, for the long jobs."""
    stderr = None if live else subprocess.PIPE
    r = subprocess.run([binary, *map(str, args)], stdout=subprocess.PIPE, stderr=stderr, text=True)
    if r.returncode != 0:
        why = "its messages are above" if live else r.stderr.strip()
        raise RuntimeError(f"footslam {' '.join(map(str, args))}: {why}")
    return r.stdout


def percentile(values, p):
    """Nearest-rank percentile, as footslam eval computes it."""
    if not values:
        return float("nan")
    s = sorted(values)
    rank = max(1, -(-p * len(s) // 100))
    return s[min(rank, len(s)) - 1]


def waypoint_errors(binary, waypoints, track, steps=None, skip_first=True):
    args = ["eval", "--json", "--waypoints", waypoints, "--track", track]
    if steps:
        args += ["--steps", steps]
    v = json.loads(footslam(binary, *args))
    first_t = None
    with open(waypoints) as f:
        next(f)
        first_t = float(next(f).split(",")[0])
    keep = lambda pts: [p["error"] for p in pts or [] if not (skip_first and p["t"] == first_t)]
    return keep(v["waypoints"]), keep(v.get("dead_reckoning_waypoints"))


def summary(name, errors):
    return {
        "name": name,
        "n": len(errors),
        "median_m": percentile(errors, 50),
        "p90_m": percentile(errors, 90),
        "mean_m": statistics.fmean(errors) if errors else float("nan"),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("imported")
    ap.add_argument("out")
    ap.add_argument("--binary", default="target/release/footslam")
    ap.add_argument("--track-config")
    ap.add_argument("--seed", default="0")
    ap.add_argument("--skip-radio", action="store_true")
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
    cfg = ["--config", a.track_config] if a.track_config else []
    pdr, tracked, per_walk, failed = [], [], [], []
    bar = Progress(len(walks), "walks tracked")
    for w in walks:
        bar.start(w)
        src = os.path.join(a.imported, w)
        run = os.path.join(a.out, w)
        wps = os.path.join(src, "waypoints.csv")
        try:
            footslam(a.binary, "steps", "--imu", os.path.join(src, "imu.csv"), "--mount", "phone", "--out", os.path.join(run, "steps"))
            steps = os.path.join(run, "steps", "steps.csv")
            with open(wps) as f:
                next(f)
                t0, x0, y0 = map(float, next(f).split(",")[:3])
            footslam(a.binary, "track", "--plan", plan, "--steps", steps, "--start", f"{x0},{y0}", "--seed", a.seed, *cfg, "--out", os.path.join(run, "track"))
            trk, dr = waypoint_errors(a.binary, wps, os.path.join(run, "track", "track.csv"), steps)
        except RuntimeError as e:
            failed.append({"walk": w, "error": str(e)})
            bar.failed(w, e)
            continue
        pdr += dr
        tracked += trk
        per_walk.append({"walk": w, "pdr": summary("pdr", dr), "tracked": summary("tracked", trk)})
        bar.done(w, f"PDR median {percentile(dr, 50):.2f} m, tracked median {percentile(trk, 50):.2f} m ({len(trk)} waypoints)")
    bar.finish()
    figures = {"walks": len(walks), "failed": failed, "pdr": summary("PDR alone", pdr), "tracked": summary("tracked on the plan", tracked), "per_walk": per_walk}

    if not a.skip_radio:
        ok = [w["walk"] for w in per_walk]
        survey_walks, test_walks = ok[0::2], ok[1::2]
        manifest = os.path.join(a.out, "survey_walks.csv")
        with open(manifest, "w") as f:
            f.write("steps,wifi,start\n")
            for w in survey_walks:
                wifi = os.path.join(a.imported, w, "wifi.csv")
                if not os.path.isfile(wifi):
                    continue
                with open(os.path.join(a.imported, w, "waypoints.csv")) as g:
                    next(g)
                    _, x0, y0 = map(float, next(g).split(",")[:3])
                f.write(f"{os.path.abspath(os.path.join(a.out, w, 'steps', 'steps.csv'))},{os.path.abspath(wifi)},\"{x0},{y0}\"\n")
        radiomap = os.path.join(a.out, "survey", "radiomap.geojson")
        footslam(a.binary, "survey", "--plan", plan, "--walks", manifest, "--seed", a.seed, *cfg, "--out", os.path.join(a.out, "survey"))
        rf_tracked, rf_alone, unanswered, not_localised = [], [], 0, 0
        bar = Progress(len(test_walks), "walks placed by the radio map")
        for w in test_walks:
            bar.start(w)
            wifi = os.path.join(a.imported, w, "wifi.csv")
            if not os.path.isfile(wifi):
                bar.done(w, "no wifi.csv")
                continue
            wps = os.path.join(a.imported, w, "waypoints.csv")
            run = os.path.join(a.out, w)
            n_wps = max(0, sum(1 for _ in open(wps)) - 2)
            try:
                footslam(a.binary, "fingerprint", "--radiomap", radiomap, "--wifi", wifi, "--out", os.path.join(run, "fingerprint"))
                e, _ = waypoint_errors(a.binary, wps, os.path.join(run, "fingerprint", "track.csv"))
                rf_alone += e
                footslam(a.binary, "track", "--plan", plan, "--steps", os.path.join(run, "steps", "steps.csv"), "--radiomap", radiomap, "--wifi", wifi, "--seed", a.seed, *cfg, "--out", os.path.join(run, "rf-track"))
                with open(os.path.join(run, "rf-track", "summary.json")) as f:
                    s = json.load(f)
                # The smoothed track.csv answers where the whole walk settles the place (its
                # certain rows, which eval keeps); an online run from localisation on.
                smoothing = s.get("smoothing")
                localised = (smoothing["steps_certain"] if smoothing else s["track_rows"]) > 0
                if localised:
                    e, _ = waypoint_errors(a.binary, wps, os.path.join(run, "rf-track", "track.csv"))
                else:
                    e, not_localised = [], not_localised + 1
                rf_tracked += e
                unanswered += n_wps - len(e)
                bar.done(w, f"{len(e)} of {n_wps} waypoints answered")
            except RuntimeError as err:
                failed.append({"walk": w, "error": str(err)})
                bar.failed(w, err)
        bar.finish()
        figures["radio"] = {
            "survey_walks": len(survey_walks),
            "test_walks": len(test_walks),
            "tracked_with_radio_map": summary("WiFi + radio map, unknown start", rf_tracked),
            "waypoints_without_a_certain_estimate": unanswered,
            "walks_never_localised": not_localised,
            "radio_map_alone": summary("radio map alone (nearest fingerprints)", rf_alone),
        }
    with open(os.path.join(a.out, "figures.json"), "w") as f:
        json.dump(figures, f, indent=2)
    rows = [figures["pdr"], figures["tracked"]]
    if "radio" in figures:
        rows += [figures["radio"]["tracked_with_radio_map"], figures["radio"]["radio_map_alone"]]
    print(f"\n{'':40} {'waypoints':>9} {'median':>8} {'p90':>8}")
    for r in rows:
        print(f"{r['name']:40} {r['n']:>9} {r['median_m']:>7.2f}m {r['p90_m']:>7.2f}m")
    if "radio" in figures:
        r = figures["radio"]
        print(f"WiFi + radio map: {r['walks_never_localised']} of {r['test_walks']} walks never localised; {r['waypoints_without_a_certain_estimate']} waypoints without a certain estimate")
    if failed:
        print(f"{len(failed)} runs failed (see figures.json)")


if __name__ == "__main__":
    main()
