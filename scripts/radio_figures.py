#!/usr/bin/env python3
"""Radio maps from ordinary walks, placing later walks (issue 33's experiment).

On an imported ILC floor (`footslam import ilc`: IMPORTED/floor.geojson and one folder per
walk with imu.csv, wifi.csv and waypoints.csv):

1. `footslam steps --mount phone` for every walk (WORK/<walk>/steps, reused unless --fresh);
2. survey: the first SHARE of the walks by folder name (default 60 %), each from its first
   waypoint (`survey --walks`, manifest `start`), into WORK/survey/radiomap.geojson;
3. the peer: nearest-k fingerprints (k = 3, plain Euclidean over every access point the
   survey heard, −100 dBm where not heard, the mean of the k nearest scans' positions) on a
   database of the survey walks' scans at their *true* positions (linear between the
   walk's waypoints; scans outside the waypoints' time span are left out);
4. every other walk from an unknown start: `fingerprint --walks --radiomap` (the radio map
   alone) and `track --walks --radiomap` (the tracker on the plan with the radio map), each
   one run for every test walk (WORK/fingerprints/<walk>, WORK/rf-tracks/<walk>), scored by
   `footslam eval --waypoints` at every waypoint (a waypoint the track does not answer
   counts as unanswered); the track every row (`--all-rows`: the answer a user gets at every
   step) and its certain rows alone; the peer's scan placements are written as a track.csv
   and scored the same way.

Prints and writes (WORK/radio_figures.json) median / p90 / answered share per method, the
radio map against the test walks' scans at their true positions (the share in surveyed
cells, the RMSE of their readings against the cells' means), and the per-walk table.

    scripts/radio_figures.py IMPORTED WORK [--binary PATH] [--share 0.6] [--seed 0]
        [--track-arg=--config --track-arg=FILE] [--jobs 2] [--fresh]
"""
import argparse
import bisect
import concurrent.futures as cf
import csv
import heapq
import json
import math
import os
import shutil
import subprocess

from progress import Progress
import sys


def run(binary, *args):
    p = subprocess.run([binary, *args], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"footslam {' '.join(args[:1])} failed: {p.stderr.strip()[-400:]}")
    return p.stdout


def read_waypoints(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [(float(r["t"]), float(r["x"]), float(r["y"])) for r in rows]


def read_scans(path):
    """Scans of a WiFi log: one per distinct time stamp, {bssid: rssi} (the strongest kept)."""
    scans = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            t = float(r["t"])
            s = scans.setdefault(t, {})
            v = float(r["rssi"])
            s[r["bssid"]] = max(v, s.get(r["bssid"], -200.0))
    return sorted(scans.items())


def truth_at(wps, t):
    ts = [w[0] for w in wps]
    if t < ts[0] or t > ts[-1]:
        return None
    i = bisect.bisect_right(ts, t)
    if i >= len(ts):
        return wps[-1][1:]
    a, b = wps[i - 1], wps[i]
    u = (t - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
    return (a[1] + u * (b[1] - a[1]), a[2] + u * (b[2] - a[2]))


def local_frame(origin):
    """WGS84 (lon, lat) degrees to the map's local east/north metres (the toolkit's tangent
    plane at `origin`: meridional and prime-vertical radii of curvature)."""
    a, e2 = 6_378_137.0, 6.69437999014e-3
    lat0, lon0 = origin["lat"], origin["lon"]
    s = math.sin(math.radians(lat0))
    m = a * (1 - e2) / (1 - e2 * s * s) ** 1.5
    n = a / math.sqrt(1 - e2 * s * s)
    c = math.cos(math.radians(lat0))
    return lambda lon, lat: (math.radians(lon - lon0) * n * c, math.radians(lat - lat0) * m)


def inside(pt, ring):
    x, y = pt
    hit = False
    for (x1, y1), (x2, y2) in zip(ring, ring[1:] + ring[:1]):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            hit = not hit
    return hit


def radiomap_accuracy(radiomap, imported, tests):
    """The radio map against the test walks' scans at their true positions (linear between
    waypoints): coverage = share of the scans whose cell holds a survey scan; RMSE of the
    readings heard both in the scan and in that cell (scan RSSI − the cell's mean), and the
    shares of the scan's readings the cell never heard and of the cell's access points the
    scan did not hear."""
    with open(radiomap) as f:
        g = json.load(f)
    to_local = local_frame(g["origin"])
    cells = []
    for feat in g["features"]:
        pr = feat["properties"]
        if pr.get("scans", 0) <= 0:
            continue
        geom = feat["geometry"]
        polygons = geom["coordinates"] if geom["type"] == "MultiPolygon" else [geom["coordinates"]]
        aps = {b: v["mean"] for b, v in pr["aps"].items()}
        for polygon in polygons:
            ring = [to_local(c[0], c[1]) for c in polygon[0]]
            xs, ys = [p[0] for p in ring], [p[1] for p in ring]
            cells.append(((min(xs), min(ys), max(xs), max(ys)), ring, aps))
    scans = covered = 0
    sq, both, scan_only, cell_only = [], 0, 0, 0
    for w in tests:
        wps = read_waypoints(os.path.join(imported, w, "waypoints.csv"))
        for t, fp in read_scans(os.path.join(imported, w, "wifi.csv")):
            pos = truth_at(wps, t)
            if pos is None:
                continue
            scans += 1
            cell = next((c for c in cells if c[0][0] <= pos[0] <= c[0][2] and c[0][1] <= pos[1] <= c[0][3]
                         and inside(pos, c[1])), None)
            if cell is None:
                continue
            covered += 1
            aps = cell[2]
            for b, r in fp.items():
                if b in aps:
                    sq.append((r - aps[b]) ** 2)
                    both += 1
                else:
                    scan_only += 1
            cell_only += sum(1 for b in aps if b not in fp)
    return {"held_out_scans": scans, "scans_in_surveyed_cells": covered,
            "coverage": covered / scans if scans else float("nan"),
            "rmse_db": math.sqrt(sum(sq) / len(sq)) if sq else float("nan"),
            "readings_compared": both,
            "scan_readings_unknown_to_cell": scan_only / max(1, both + scan_only),
            "cell_aps_unheard_by_scan": cell_only / max(1, both + cell_only)}


def percentile(xs, q):
    if not xs:
        return float("nan")
    s = sorted(xs)
    return s[min(len(s) - 1, max(0, math.ceil(q / 100 * len(s)) - 1))]


def waypoint_errors(binary, wps, track, all_rows=False):
    extra = ["--all-rows"] if all_rows else []
    p = subprocess.run([binary, "eval", "--json", "--waypoints", wps, "--track", track, *extra], capture_output=True, text=True)
    if p.returncode != 0:
        # A track certain nowhere, or only between waypoints, answers none of them.
        if "no certain rows" in p.stderr or "within the track's time span" in p.stderr:
            return []
        raise RuntimeError(f"footslam eval failed: {p.stderr.strip()[-400:]}")
    out = json.loads(p.stdout)
    return [w["error"] for w in out["waypoints"]]


MISSING_DBM = -100.0


def peer_index(db, missing=MISSING_DBM):
    """The peer's database indexed for `peer_track`: each access point's readings
    `(fingerprint, dBm)`, each fingerprint's `S_v` (the sum of `(v_b - missing)^2` over its
    readings) and position."""
    index = {}
    for i, (_, fp, _) in enumerate(db):
        for b, r in fp.items():
            index.setdefault(b, []).append((i, r))
    base = [sum((r - missing) ** 2 for r in fp.values()) for _, fp, _ in db]
    return index, base, [pos for _, _, pos in db]


def peer_track(peer, scans, path, k=3, missing=MISSING_DBM):
    """Writes the nearest-k placements of `scans` as a track.csv (t,x,y): plain Euclidean
    over every access point the database heard, `missing` where not heard. With the index of
    `peer_index` and `Q` the scan's sum of `(q_b - missing)^2`, `d(q, v) = S_v + Q + sum over
    the access points both heard of (q_b - v_b)^2 - (v_b - missing)^2 - (q_b - missing)^2`:
    the dense vectors' distance (access points neither heard add nothing)."""
    index, base, positions = peer
    with open(path, "w") as f:
        f.write("t,x,y\n")
        for t, fp in scans:
            q = {b: r for b, r in fp.items() if b in index}
            if not q:
                continue
            d = list(base)
            both = 0.0
            for b, qb in q.items():
                both += (qb - missing) ** 2
                for i, vb in index[b]:
                    d[i] += (qb - vb) ** 2 - (vb - missing) ** 2 - (qb - missing) ** 2
            near = heapq.nsmallest(k, ((di + both, positions[i]) for i, di in enumerate(d)))
            x = sum(p[0] for _, p in near) / len(near)
            y = sum(p[1] for _, p in near) / len(near)
            f.write(f"{t:.3f},{x:.3f},{y:.3f}\n")


def steps_of(binary, imported, work, w, fresh):
    out = os.path.join(work, w, "steps")
    if fresh or not os.path.isfile(os.path.join(out, "steps.csv")):
        shutil.rmtree(out, ignore_errors=True)
        run(binary, "steps", "--imu", os.path.join(imported, w, "imu.csv"), "--mount", "phone", "--out", out)
    return os.path.join(out, "steps.csv")


def track_walks(a, tests, radiomap, plan):
    """Every test walk from an unknown start, in one `track --walks` run (the plan and the
    radio map prepared once), into WORK/rf-tracks/<walk>; and their scans placed by the radio
    map alone, in one `fingerprint --walks` run, into WORK/fingerprints/<walk>."""
    manifest = os.path.join(a.work, "test_walks.csv")
    with open(manifest, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["steps", "wifi", "name"])
        for w in tests:
            out.writerow([os.path.abspath(os.path.join(a.work, w, "steps", "steps.csv")),
                          os.path.abspath(os.path.join(a.imported, w, "wifi.csv")), w])
    run(a.binary, "track", "--plan", plan, "--walks", manifest, "--radiomap", radiomap,
        "--seed", str(a.seed), *a.track_arg, "--out", os.path.join(a.work, "rf-tracks"))
    run(a.binary, "fingerprint", "--radiomap", radiomap, "--walks", manifest,
        "--out", os.path.join(a.work, "fingerprints"))


def test_walk(a, w, radiomap, plan, peer_db):
    src = os.path.join(a.imported, w)
    wps = os.path.join(src, "waypoints.csv")
    n_wps = len(read_waypoints(wps))
    run_dir = os.path.join(a.work, w)
    res = {"walk": w, "waypoints": n_wps}
    fp = os.path.join(a.work, "fingerprints", w)
    res["fingerprint"] = waypoint_errors(a.binary, wps, os.path.join(fp, "track.csv"))
    peer = os.path.join(run_dir, "peer")
    os.makedirs(peer, exist_ok=True)
    peer_track(peer_db, read_scans(os.path.join(src, "wifi.csv")), os.path.join(peer, "track.csv"))
    res["peer"] = waypoint_errors(a.binary, wps, os.path.join(peer, "track.csv"))
    tr = os.path.join(a.work, "rf-tracks", w)
    res["track"] = waypoint_errors(a.binary, wps, os.path.join(tr, "track.csv"), all_rows=True)
    res["track_certain"] = waypoint_errors(a.binary, wps, os.path.join(tr, "track.csv"))
    with open(os.path.join(tr, "summary.json")) as f:
        res["track_summary"] = json.load(f)
    return res


def summary(name, errors, expected):
    return {"name": name, "n": len(errors), "answered": len(errors) / expected if expected else float("nan"),
            "median_m": percentile(errors, 50), "p90_m": percentile(errors, 90)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("imported")
    ap.add_argument("work")
    ap.add_argument("--binary", default="target/release/footslam")
    ap.add_argument("--share", type=float, default=0.6)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--track-arg", action="append", default=[])
    ap.add_argument("--survey-arg", action="append", default=[])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--fresh", action="store_true")
    a = ap.parse_args()
    a.binary = os.path.abspath(a.binary)
    os.makedirs(a.work, exist_ok=True)
    plan = os.path.join(a.imported, "floor.geojson")
    walks = sorted(d for d in os.listdir(a.imported)
                   if all(os.path.isfile(os.path.join(a.imported, d, f)) for f in ("imu.csv", "wifi.csv", "waypoints.csv")))
    if not walks:
        sys.exit(f"no walks under {a.imported}")
    bar = Progress(len(walks), "walks' steps")
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        list(ex.map(bar.wrap(lambda w: steps_of(a.binary, a.imported, a.work, w, a.fresh)), walks))
    bar.finish()
    n_survey = round(a.share * len(walks))
    survey, tests = walks[:n_survey], walks[n_survey:]
    manifest = os.path.join(a.work, "survey_walks.csv")
    db = []
    with open(manifest, "w") as f:
        f.write("steps,wifi,start\n")
        for w in survey:
            wps = read_waypoints(os.path.join(a.imported, w, "waypoints.csv"))
            steps = os.path.abspath(os.path.join(a.work, w, "steps", "steps.csv"))
            f.write(f"{steps},{os.path.abspath(os.path.join(a.imported, w, 'wifi.csv'))},\"{wps[0][1]},{wps[0][2]}\"\n")
            for t, fp in read_scans(os.path.join(a.imported, w, "wifi.csv")):
                pos = truth_at(wps, t)
                if pos is not None:
                    db.append((t, fp, pos))
    sv = os.path.join(a.work, "survey")
    shutil.rmtree(sv, ignore_errors=True)
    bar = Progress(1, f"survey of {len(survey)} walks")
    bar.start("survey")
    run(a.binary, "survey", "--plan", plan, "--walks", manifest, "--seed", str(a.seed), *a.survey_arg, "--out", sv)
    bar.done("survey")
    radiomap = os.path.join(sv, "radiomap.geojson")
    with open(os.path.join(sv, "summary.json")) as f:
        survey_summary = json.load(f)
    bar = Progress(1, f"track and fingerprint of {len(tests)} walks")
    bar.start("track --walks, fingerprint --walks")
    track_walks(a, tests, radiomap, plan)
    bar.done("track --walks, fingerprint --walks")
    bar = Progress(len(tests), "test walks")
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        peer_db = peer_index(db)
        results = list(ex.map(bar.wrap(lambda w: test_walk(a, w, radiomap, plan, peer_db)), tests))
    bar.finish()
    expected = sum(r["waypoints"] for r in results)
    figures = {"survey_walks": len(survey), "test_walks": len(tests), "peer_database_scans": len(db),
               "radiomap_vs_held_out_scans": radiomap_accuracy(radiomap, a.imported, tests),
               "survey_summary": survey_summary, "methods": {}, "per_walk": []}
    for key, name in (("track", "track --wifi --radiomap, unknown start, every row"),
                      ("track_certain", "the same, certain rows only"),
                      ("fingerprint", "fingerprint (radio map alone)"),
                      ("peer", "nearest-3 at true positions (peer)")):
        errs = [e for r in results for e in r[key]]
        figures["methods"][key] = summary(name, errs, expected)
    for r in results:
        figures["per_walk"].append({"walk": r["walk"], "waypoints": r["waypoints"],
                                    **{k: percentile(r[k], 50) for k in ("track", "fingerprint", "peer")},
                                    "answered": len(r["track"])})
    with open(os.path.join(a.work, "radio_figures.json"), "w") as f:
        json.dump(figures, f, indent=2)
    print(f"{len(survey)} survey walks, {len(tests)} test walks, {expected} waypoints, peer database {len(db)} scans")
    acc = figures["radiomap_vs_held_out_scans"]
    print(f"radio map against the test walks' {acc['held_out_scans']} scans at their true positions: "
          f"{acc['coverage']:.0%} in surveyed cells, RMSE {acc['rmse_db']:.1f} dB over {acc['readings_compared']} readings "
          f"({acc['scan_readings_unknown_to_cell']:.0%} of those cells' scan readings unknown to the cell, "
          f"{acc['cell_aps_unheard_by_scan']:.0%} of the cells' access points unheard)")
    for r in figures["per_walk"]:
        print(f"{r['walk']}: {r['waypoints']:3} wps, track {r['track']:6.1f} m ({r['answered']} answered), fingerprint {r['fingerprint']:6.1f}, peer {r['peer']:6.1f}")
    print(f"\n{'':42} {'waypoints':>9} {'answered':>8} {'median':>8} {'p90':>8}")
    for m in figures["methods"].values():
        print(f"{m['name']:42} {m['n']:>9} {m['answered']:>7.0%} {m['median_m']:>7.2f}m {m['p90_m']:>7.2f}m")


if __name__ == "__main__":
    main()
