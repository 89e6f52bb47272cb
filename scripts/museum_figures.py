#!/usr/bin/env python3
"""FootSLAM on the IPIN 2023 Track 3 museum logs: each route's repetitions chained into one walk.

For every route found under LOGS (files `..._TrainingTrial<route>_repetition<k>.txt`; routes
and repetitions are discovered from the names), in WORK/route-<route>/:

1. `footslam import ipin` of every repetition into rep-<k>/ with ONE origin per route (the
   first POSI of the first repetition), so that all repetitions' waypoints share a frame;
2. `footslam steps --mount phone` on each rep-<k>/imu.csv (the imported pressure column
   gives the steps their dz) into rep-<k>/steps/;
3. the repetitions chained into one walk, chain/{steps,wifi,waypoints}.csv: each repetition's
   steps from its first to its last waypoint (inclusive), its WiFi rows in the same window
   and all its waypoints, shifted by one constant per repetition (whole milliseconds; the
   first repetition keeps its own times). Repetition k+1's first kept step comes
   max(--gap, d1 + d2 + 0.5 s) after repetition k's last, where d1 is how long repetition k's
   last waypoint follows its last kept step and d2 how long repetition k+1's first kept step
   follows its first waypoint: the walker stands at the start between them, and the chain's
   waypoints stay in time order. Repetition k+1's first kept step gets a dheading equal to
   the wrapped difference between its absolute heading and the previous kept step's (0
   without a `heading` column). Every other value is copied verbatim. A repetition with
   fewer than --min-rep-steps kept steps is left out of the chain (and said so);
4. two dead reckonings of the chain as track CSVs `t,x,y` (a start row, then one row per
   step): integrating dheading from heading 0, and following the absolute `heading` column;
5. FootSLAM, one `footslam learn` per variant: A "steps alone" (`--ignore-heading`), B
   "everything" (absolute heading and `--wifi chain/wifi.csv`);

and scores every track with `footslam eval --waypoints chain/waypoints.csv --align rigid
--json` (per-waypoint errors; median and nearest-rank p95 over the waypoints). learn's
track.csv has no row before the first step, so it is scored as track-with-start.csv: a row at
the origin (where learn starts a walk without --start) at the dead reckonings' start time,
then learn's rows; all tracks are thus scored at the same waypoints.

Prints a markdown table per route (p95/median of both dead reckonings and of each variant, the
variant's p95 over the better dead reckoning's) and the mean and median of those ratios; the
issue's target is p95 <= 0.6x the better dead reckoning and median <= 2.5 m. Writes
everything to --out (JSON).

    scripts/museum_figures.py [--logs DIR] [--routes 21,23] [--work DIR] [--out FILE.json]
        [--binary PATH] [--particles N] [--seed N] [--variants A,B] [--fresh]
        [--learn-arg=ARG ...] [--steps-arg=ARG ...] [--min-rep-steps N] [--gap S]

e.g. scripts/museum_figures.py --work /tmp/museum --out /tmp/museum/baseline.json
     scripts/museum_figures.py --variants B --learn-arg=--config --learn-arg=my.toml
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import statistics
import subprocess

from progress import Progress
import sys
import time

from real_data_figures import percentile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_LOGS = "/work/shared/data/ipin2023-museum/logs"
LOG_NAME = re.compile(r"Trial(\d+)_repetition(\d+)\.txt$")
VARIANTS = {
    "A": ("steps alone", ["--ignore-heading"], False),
    "B": ("everything (heading + WiFi)", [], True),
}


def footslam(binary, *args, warnings=None):
    """Runs footslam; raises with its stderr on failure. Lines of stderr that mention a
    warning are echoed and, with `warnings`, collected."""
    r = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"footslam {' '.join(map(str, args))}: {r.stderr.strip()}")
    for line in r.stderr.splitlines():
        if "warning" in line.lower():
            print(f"    [{args[0]}] {line}", file=sys.stderr)
            if warnings is not None:
                warnings.append(line)
    return r.stdout


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def decimals(s):
    return len(s.split(".", 1)[1]) if "." in s else 0


def shift(t_str, offset):
    """`t_str + offset`, written with t_str's decimals."""
    return f"{float(t_str) + offset:.{decimals(t_str)}f}"


def read_lines(path):
    """Header and data lines (no newline, blank lines dropped) of a CSV."""
    with open(path) as f:
        lines = [l.rstrip("\r\n") for l in f]
    return lines[0], [l for l in lines[1:] if l.strip()]


def first_posi(log):
    with open(log) as f:
        for line in f:
            if line.startswith("POSI;"):
                fields = line.split(";")
                return f"{fields[3].strip()},{fields[4].strip()}"
    raise RuntimeError(f"{log}: no POSI line")


def discover(logs_dir, routes):
    found = {}
    for name in sorted(os.listdir(logs_dir)):
        m = LOG_NAME.search(name)
        if m:
            found.setdefault(m.group(1), []).append((int(m.group(2)), os.path.join(logs_dir, name)))
    if routes:
        missing = [r for r in routes if r not in found]
        if missing:
            sys.exit(f"routes {','.join(missing)} not found under {logs_dir} (have {','.join(sorted(found, key=int))})")
        found = {r: found[r] for r in routes}
    return {r: sorted(reps) for r, reps in sorted(found.items(), key=lambda kv: int(kv[0]))}


def prepare_rep(a, log, origin, rep_dir, steps_args):
    """Imports one repetition and detects its steps (reusing earlier results when they were
    made with the same origin and steps arguments, unless --fresh)."""
    summary = os.path.join(rep_dir, "summary.json")
    reuse = False
    if not a.fresh and os.path.isfile(os.path.join(rep_dir, "imu.csv")) and os.path.isfile(summary):
        with open(summary) as f:
            o = json.load(f).get("origin", {})
        lat, lon = map(float, origin.split(","))
        reuse = abs(o.get("lat", 1e9) - lat) < 1e-12 and abs(o.get("lon", 1e9) - lon) < 1e-12
    if not reuse:
        shutil.rmtree(rep_dir, ignore_errors=True)
        footslam(a.binary, "import", "ipin", "--log", log, "--origin", origin, "--out", rep_dir)
    steps_dir = os.path.join(rep_dir, "steps")
    marker = os.path.join(steps_dir, "museum_figures_steps_args.json")
    warnings = []
    if reuse and os.path.isfile(marker):
        with open(marker) as f:
            m = json.load(f)
        if m.get("args") == steps_args:
            return m.get("warnings", [])
    shutil.rmtree(steps_dir, ignore_errors=True)
    footslam(a.binary, "steps", "--imu", os.path.join(rep_dir, "imu.csv"), "--mount", "phone", *steps_args, "--out", steps_dir, warnings=warnings)
    with open(marker, "w") as f:
        json.dump({"args": steps_args, "warnings": warnings}, f)
    return warnings


def chain(a, rep_dirs, out_dir):
    """Chains the repetitions (see the docstring); returns per-repetition statistics."""
    os.makedirs(out_dir, exist_ok=True)
    steps_header = wifi_header = wp_header = None
    steps_out, wifi_out, wp_out, reps = [], [], [], []
    prev = None  # (last kept step's shifted t, its heading, last waypoint's shifted t)
    for k, d in rep_dirs:
        if not os.path.isfile(os.path.join(d, "waypoints.csv")):
            reps.append({"repetition": k, "left_out": "no waypoints.csv (no POSI line in the log)"})
            print(f"  WARNING rep {k}: left out of the chain: no waypoints.csv", file=sys.stderr)
            continue
        sh, srows = read_lines(os.path.join(d, "steps", "steps.csv"))
        wh, wprows = read_lines(os.path.join(d, "waypoints.csv"))
        wifi_path = os.path.join(d, "wifi.csv")
        fh, frows = read_lines(wifi_path) if os.path.isfile(wifi_path) else (None, [])
        steps_header = steps_header or sh
        wp_header = wp_header or wh
        wifi_header = wifi_header or fh
        if sh != steps_header or wh != wp_header or (fh and fh != wifi_header):
            raise RuntimeError(f"{d}: headers differ from the first repetition's")
        cols = sh.split(",")
        hcol = cols.index("heading") if "heading" in cols else None
        dcol = cols.index("dheading")
        lcol = cols.index("length")
        w0, w1 = float(wprows[0].split(",", 1)[0]), float(wprows[-1].split(",", 1)[0])
        kept = [r.split(",") for r in srows if w0 <= float(r.split(",", 1)[0]) <= w1]
        all_steps = len(srows)
        wp_xy = [tuple(map(float, r.split(",")[1:3])) for r in wprows]
        wp_path = sum(math.dist(p, q) for p, q in zip(wp_xy, wp_xy[1:]))
        info = {
            "repetition": k,
            "steps_in_log": all_steps,
            "steps_kept": len(kept),
            "kept_length_m": sum(float(r[lcol]) for r in kept),
            "waypoints": len(wprows),
            "waypoint_polyline_m": wp_path,
            "window_s": [w0, w1],
            "wifi_scans_kept": len({r.split(",", 1)[0] for r in frows if w0 <= float(r.split(",", 1)[0]) <= w1}),
        }
        reps.append(info)
        if len(kept) < a.min_rep_steps:
            info["left_out"] = f"{len(kept)} steps between its first and last waypoint (fewer than --min-rep-steps {a.min_rep_steps})"
            print(f"  WARNING rep {k}: left out of the chain: {info['left_out']} ({all_steps} steps in the whole log)", file=sys.stderr)
            continue
        if info["kept_length_m"] < 0.7 * wp_path:
            info["suspect"] = f"kept steps walk {info['kept_length_m']:.1f} m, the waypoints' polyline alone {wp_path:.1f} m"
            print(f"  WARNING rep {k}: {info['suspect']} (steps missed?)", file=sys.stderr)
        t_first = float(kept[0][0])
        if prev is None:
            offset = 0.0
        else:
            prev_t, prev_heading, prev_wp_t = prev
            d1 = prev_wp_t - prev_t
            d2 = t_first - w0
            offset = round(prev_t + max(a.gap, d1 + d2 + 0.5) - t_first, 3)
            h = kept[0][hcol] if hcol is not None and hcol < len(kept[0]) else ""
            if h.strip() and prev_heading is not None:
                dh = wrap(float(h) - prev_heading)
            else:
                dh = 0.0
            kept[0][dcol] = f"{dh:.{decimals(kept[0][dcol])}f}"
        info["offset_s"] = offset
        for r in kept:
            r[0] = shift(r[0], offset)
            steps_out.append(",".join(r))
        wps = [shift(r.split(",", 1)[0], offset) + "," + r.split(",", 1)[1] for r in wprows]
        if a.dedup_start and wp_out and wps and wps[0].split(",")[1:3] == wp_out[-1].split(",")[1:3]:
            wps = wps[1:]
        wp_out += wps
        for r in frows:
            t_str, rest = r.split(",", 1)
            if w0 <= float(t_str) <= w1:
                wifi_out.append((float(t_str) + offset, shift(t_str, offset) + "," + rest))
        last = kept[-1]
        last_heading = float(last[hcol]) if hcol is not None and hcol < len(last) and last[hcol].strip() else None
        prev = (float(last[0]), last_heading, float(wps[-1].split(",", 1)[0]) if wps else float(last[0]))
    if not steps_out:
        raise RuntimeError("no repetition left in the chain")
    wifi_out.sort(key=lambda x: x[0])  # stable
    with open(os.path.join(out_dir, "steps.csv"), "w") as f:
        f.write("\n".join([steps_header, *steps_out]) + "\n")
    with open(os.path.join(out_dir, "waypoints.csv"), "w") as f:
        f.write("\n".join([wp_header, *wp_out]) + "\n")
    if wifi_header:
        with open(os.path.join(out_dir, "wifi.csv"), "w") as f:
            f.write("\n".join([wifi_header, *(r for _, r in wifi_out)]) + "\n")
    return reps, len({t for t, _ in wifi_out}), len(wifi_out)


def read_steps(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def dead_reckon(steps, t0, absolute):
    """Track rows (t, x, y): a start row at t0, then one per step."""
    x = y = 0.0
    heading = 0.0
    if absolute and steps[0].get("heading", "").strip():
        heading = float(steps[0]["heading"]) - float(steps[0]["dheading"])
    rows = [(t0, 0.0, 0.0)]
    for s in steps:
        h = s.get("heading", "").strip() if absolute else ""
        heading = float(h) if h else heading + float(s["dheading"])
        x += float(s["length"]) * math.cos(heading)
        y += float(s["length"]) * math.sin(heading)
        rows.append((float(s["t"]), x, y))
    return rows


def write_track(path, rows):
    with open(path, "w") as f:
        f.write("t,x,y\n")
        for t, x, y in rows:
            f.write(f"{t:.3f},{x:.4f},{y:.4f}\n")


def evaluate(binary, waypoints, track):
    v = json.loads(footslam(binary, "eval", "--waypoints", waypoints, "--track", track, "--align", "rigid", "--json"))
    errors = [p["error"] for p in v["waypoints"]]
    return {
        "n": len(errors),
        "skipped": v["track"].get("skipped", 0),
        "held": v.get("held", 0),
        "median_m": percentile(errors, 50),
        "p95_m": percentile(errors, 95),
        "eval_p95_m": v["track"]["p95"],
        "mean_m": statistics.fmean(errors) if errors else float("nan"),
        "max_m": max(errors) if errors else float("nan"),
        "transform": v["track"].get("transform"),
        "errors": [{"t": p["t"], "error": p["error"]} for p in v["waypoints"]],
    }


def run_route(a, route, reps):
    base = os.path.join(a.work, f"route-{route}")
    origin = first_posi(reps[0][1])
    print(f"route {route}: {len(reps)} repetitions, origin {origin}", file=sys.stderr)
    rep_dirs, steps_warnings = [], {}
    for k, log in reps:
        d = os.path.join(base, f"rep-{k}")
        w = prepare_rep(a, log, origin, d, a.steps_arg)
        if w:
            steps_warnings[k] = w
        rep_dirs.append((k, d))
    chain_dir = os.path.join(base, "chain")
    shutil.rmtree(chain_dir, ignore_errors=True)
    rep_info, scans, readings = chain(a, rep_dirs, chain_dir)
    steps_csv = os.path.join(chain_dir, "steps.csv")
    wps = os.path.join(chain_dir, "waypoints.csv")
    steps = read_steps(steps_csv)
    with open(wps) as f:
        wp_t0 = float(next(csv.DictReader(f))["t"])
    t0 = min(wp_t0, float(steps[0]["t"]) - 1e-3)
    has_heading = "heading" in steps[0]
    for info in rep_info:
        flag = " LEFT OUT: " + info["left_out"] if "left_out" in info else (" SUSPECT: " + info["suspect"] if "suspect" in info else "")
        print(
            f"  rep {info['repetition']}: {info['steps_kept']} of {info['steps_in_log']} steps kept "
            f"({info['kept_length_m']:.1f} m; waypoint polyline {info['waypoint_polyline_m']:.1f} m), "
            f"{info['waypoints']} waypoints, {info['wifi_scans_kept']} WiFi scans, window "
            f"{info['window_s'][0]:.1f}-{info['window_s'][1]:.1f} s, offset {info.get('offset_s', float('nan')):+.3f} s{flag}",
            file=sys.stderr,
        )
    result = {
        "route": route,
        "origin": origin,
        "repetitions": rep_info,
        "steps_warnings": steps_warnings,
        "chain": {
            "steps": len(steps),
            "length_m": sum(float(s["length"]) for s in steps),
            "t": [float(steps[0]["t"]), float(steps[-1]["t"])],
            "waypoints": sum(1 for _ in open(wps)) - 1,
            "wifi_scans": scans,
            "wifi_readings": readings,
            "heading_column": has_heading,
        },
        "dr": {},
        "variants": {},
    }
    c = result["chain"]
    print(f"  chain: {c['steps']} steps, {c['length_m']:.1f} m, t {c['t'][0]:.3f}-{c['t'][1]:.3f} s, {c['waypoints']} waypoints, {scans} WiFi scans ({readings} readings)", file=sys.stderr)
    dr_kinds = [("dheading", False)] + ([("heading", True)] if has_heading else [])
    for name, absolute in dr_kinds:
        track = os.path.join(chain_dir, f"dr-{name}.csv")
        write_track(track, dead_reckon(steps, t0, absolute))
        result["dr"][name] = evaluate(a.binary, wps, track)
        r = result["dr"][name]
        print(f"  DR {name}: p95 {r['p95_m']:.2f} m, median {r['median_m']:.2f} m ({r['n']} waypoints, {r['skipped']} skipped)", file=sys.stderr)
    # the first listed (dheading) wins a tie (to the cm): with a heading column the two are one path
    better = min(result["dr"], key=lambda n: round(result["dr"][n]["p95_m"], 2))
    result["better_dr"] = better
    for v in a.variants:
        label, extra, wifi = VARIANTS[v]
        out = os.path.join(base, f"learn-{v}")
        shutil.rmtree(out, ignore_errors=True)
        args = ["learn", "--steps", steps_csv, *extra]
        wifi_csv = os.path.join(chain_dir, "wifi.csv")
        if wifi and os.path.isfile(wifi_csv):
            args += ["--wifi", wifi_csv]
        args += ["--particles", a.particles, "--seed", a.seed, *a.learn_arg, "--out", out]
        warnings = []
        start = time.monotonic()
        footslam(a.binary, *args, warnings=warnings)
        wall = time.monotonic() - start
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        # learn's track.csv starts after the first step; its walk starts at the origin.
        with open(os.path.join(out, "track.csv")) as f:
            rows = [(float(r["t"]), float(r["x"]), float(r["y"])) for r in csv.DictReader(f)]
        first_step_m = math.hypot(rows[0][1], rows[0][2])
        track = os.path.join(out, "track-with-start.csv")
        write_track(track, [(t0, 0.0, 0.0), *rows])
        r = evaluate(a.binary, wps, track)
        r["as_written"] = {k: v2 for k, v2 in evaluate(a.binary, wps, os.path.join(out, "track.csv")).items() if k != "errors"}
        r.update({
            "label": label,
            "command": args,
            "wall_s": wall,
            "warnings": warnings + [w for w in summary.get("warnings", []) if w not in warnings],
            "first_row_from_origin_m": first_step_m,
            "first_step_length_m": float(steps[0]["length"]),
            "ratio_p95": r["p95_m"] / result["dr"][better]["p95_m"],
            "learn_summary": {k: summary[k] for k in (
                "heading", "headings_used", "runtime_s", "min_effective_sample_size", "final_effective_sample_size",
                "resamplings", "hexagons", "map_area_m2", "path_length_m", "radio") if k in summary},
        })
        result["variants"][v] = r
        print(f"  {v} ({label}): p95 {r['p95_m']:.2f} m, median {r['median_m']:.2f} m, ratio {r['ratio_p95']:.2f} ({wall:.0f} s)", file=sys.stderr)
    return result


def table(results, variants):
    head = ["route", "DR dheading p95/med", "DR heading p95/med", "better DR p95"]
    head += [f"{v} p95/med (÷DR)" for v in variants]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    fmt = lambda r: f"{r['p95_m']:.2f} / {r['median_m']:.2f}" if r else "—"
    for res in results:
        if "error" in res:
            lines.append(f"| {res['route']} | FAILED: {res['error'][:80]} |")
            continue
        dr = res["dr"]
        row = [res["route"], fmt(dr.get("dheading")), fmt(dr.get("heading")), f"{dr[res['better_dr']]['p95_m']:.2f} ({res['better_dr']})"]
        for v in variants:
            r = res["variants"].get(v)
            row.append(f"{fmt(r)} ({r['ratio_p95']:.2f})" if r else "—")
        lines.append("| " + " | ".join(row) + " |")
    ok = [r for r in results if "error" not in r]
    for v in variants:
        ratios = [r["variants"][v]["ratio_p95"] for r in ok if v in r["variants"]]
        meds = [r["variants"][v]["median_m"] for r in ok if v in r["variants"]]
        if ratios:
            lines.append(
                f"\n{v}: p95 ratio to the better DR mean {statistics.fmean(ratios):.2f}, median {statistics.median(ratios):.2f}; "
                f"routes meeting p95 <= 0.6x DR: {sum(x <= 0.6 for x in ratios)}/{len(ratios)}, median <= 2.5 m: {sum(m <= 2.5 for m in meds)}/{len(meds)}"
            )
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--logs", default=DEFAULT_LOGS, help="folder of IPIN logs (default: %(default)s)")
    ap.add_argument("--routes", help="comma-separated route numbers (default: every route found)")
    ap.add_argument("--work", default="outputs/museum", help="imports, steps, chains and runs (default: %(default)s)")
    ap.add_argument("--out", help="results JSON (default: WORK/museum_figures.json)")
    ap.add_argument("--binary", help="footslam binary (default: target/release/footslam, else /tmp/footslam-base)")
    ap.add_argument("--particles", default="20000")
    ap.add_argument("--seed", default="0")
    ap.add_argument("--variants", default="A,B", help="A (steps alone), B (heading + WiFi); default %(default)s")
    ap.add_argument("--learn-arg", action="append", default=[], help="passed to every learn call (repeatable, --learn-arg=--config)")
    ap.add_argument("--steps-arg", action="append", default=[], help="passed to every steps call (repeatable); steps are redone when these change")
    ap.add_argument("--min-rep-steps", type=int, default=1, help="repetitions with fewer kept steps are left out of the chain (default %(default)s)")
    ap.add_argument("--gap", type=float, default=1.0, help="least time between repetitions' kept steps in the chain, s (default %(default)s)")
    ap.add_argument("--dedup-start", action="store_true", help="drop a repetition's first waypoint when it is the previous one's last point")
    ap.add_argument("--fresh", action="store_true", help="re-import and redo the steps even when present")
    a = ap.parse_args()
    if not a.binary:
        a.binary = os.path.join(REPO, "target", "release", "footslam")
        if not os.access(a.binary, os.X_OK):
            a.binary = "/tmp/footslam-base"
    a.variants = [v.strip().upper() for v in a.variants.split(",") if v.strip()]
    bad = [v for v in a.variants if v not in VARIANTS]
    if bad:
        sys.exit(f"unknown variants {bad} (have {', '.join(VARIANTS)})")
    a.out = a.out or os.path.join(a.work, "museum_figures.json")
    routes = discover(a.logs, [r.strip() for r in a.routes.split(",")] if a.routes else None)
    if not routes:
        sys.exit(f"no logs named ...Trial<route>_repetition<k>.txt under {a.logs}")
    os.makedirs(a.work, exist_ok=True)
    results = []
    bar = Progress(len(routes), "routes")
    for route, reps in routes.items():
        bar.start(f"route {route}")
        try:
            results.append(run_route(a, route, reps))
            bar.done(f"route {route}")
        except RuntimeError as e:
            bar.failed(f"route {route}", e)
            results.append({"route": route, "error": str(e)})
    bar.finish()
    text = table(results, a.variants)
    print(text)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump({
            "binary": a.binary,
            "logs": a.logs,
            "particles": a.particles,
            "seed": a.seed,
            "variants": a.variants,
            "learn_args": a.learn_arg,
            "steps_args": a.steps_arg,
            "min_rep_steps": a.min_rep_steps,
            "gap_s": a.gap,
            "routes": results,
            "table": text,
        }, f, indent=2)
    print(f"\nwrote {a.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
