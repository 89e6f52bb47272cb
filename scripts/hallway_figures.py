#!/usr/bin/env python3
"""FootSLAM against dead reckoning on foot-mounted IMU walks with per-stride truth.

For every walk folder found under DATA (any depth: a folder holding both imu.csv and
strides.csv, as /work/shared/data/foot-imu/{hallway,vicon}/* do), in WORK/<walk>/:

1. `footslam steps --mount foot` (steps/; reused when steps/steps.csv exists, unless --fresh);
2. truth.csv (`t,x,y`) from strides.csv (`t,x,y,z`, the foot's position at the last sample of
   each stance; the last row is the end of the recording), see --truth-mode;
3. `footslam learn` once per seed (learn-<seed>/, default configuration and 20,000
   particles unless --particles / --learn-arg say otherwise), then
   `footslam eval --align rigid --steps steps/steps.csv --json` of its track.csv: the learned
   path's p95 and dead reckoning's p95 (the same steps integrated from the origin), both
   after their own best rigid alignment to the truth.

Ratio = learned p95 / dead reckoning p95 per seed (below 1: FootSLAM helps). Prints the
table of docs/footslam.md ("Foot hallway walks": walk | DR p95 | learned p95 mean of seeds |
ratio (mean) | ratio (worst seed)), the median over walks of the mean ratios and the worst
ratio of any run, then one row per run with the learn summary.json fields that could flag a
bad run (heading.final_sigma_deg, ESS, best path log-likelihood, ...), and their rank
correlation with the ratio. Everything goes to --out (JSON).

Truth modes (`footslam eval` interpolates the truth linearly at each track row's time and
skips rows outside the truth's time span):
- `strides` (default, as docs/footslam.md's figures were made): strides.csv's rows as they
  are. Step times are the detector's stance ends (0.04-0.1 s after the truth's, median), so
  the truth is read a little into the next swing; and steps.csv / track.csv round times to
  the millisecond, so a final stride ending on the recording's last sample (t = 25.99398 ->
  25.994) lies past the truth's end and is skipped on four of the six hallway walks
  (own-37 and own-43 round down and keep it).
- `held`: each footprint held over a window around its time (+-0.3 s, at most 45 % of the gap
  to each neighbour; the last one 0.3 s past the end), so that every step within the window
  of a stance is compared with that footprint, as the foot_imu example matches strides to
  stances (+-0.3 s), and the final stride is kept. The last row (the end of the recording)
  is held back to a median stride duration after the previous stance: where the walker
  stands at the end, the detector's last stride may end seconds before the recording does
  (four of the Vicon walks), and interpolating would put its truth mid-stride.

    scripts/hallway_figures.py [--data DIR] [--work DIR] [--out FILE.json] [--binary PATH]
        [--seeds 0,1,2,3] [--particles 20000] [--learn-arg=--config --learn-arg=FILE ...]
        [--walks own-31,own-40] [--truth-mode strides|held] [--fresh]

e.g. the hallway baseline, then the Vicon walks with the measured foot parameter set:

    scripts/hallway_figures.py --binary /tmp/footslam-base --work /tmp/hallway --out /tmp/hallway/baseline.json
    scripts/hallway_figures.py --data /work/shared/data/foot-imu/vicon --work /tmp/vicon \\
        --out /tmp/vicon/foot-set.json --learn-arg=--config --learn-arg=datasets/configs/learn-foot.toml
"""
import argparse
import csv
import json
import math
import os
import shutil
import statistics
import subprocess

from progress import Progress
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_DATA = "/work/shared/data/foot-imu/hallway"
FALLBACK_BINARY = "/tmp/footslam-base"
HOLD_S = 0.3


def footslam(binary, *args):
    r = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"footslam {' '.join(map(str, args))}: {r.stderr.strip()}")
    return r.stdout, r.stderr


def default_binary():
    built = os.path.join(REPO, "target", "release", "footslam")
    return built if os.path.isfile(built) and os.access(built, os.X_OK) else FALLBACK_BINARY


def parse_seeds(text):
    """`0,1,2,3`, `0-3` or a mix (`0-2,7`)."""
    seeds = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        if "-" in part:
            lo, hi = part.split("-", 1)
            seeds += range(int(lo), int(hi) + 1)
        else:
            seeds.append(int(part))
    if not seeds:
        raise argparse.ArgumentTypeError(f"no seeds in {text!r}")
    return seeds


def discover_walks(data):
    """Folders under `data` (itself included) holding imu.csv and strides.csv, by relative
    path ('.' for `data` itself)."""
    found = []
    for root, dirs, files in os.walk(data):
        dirs.sort()
        if "imu.csv" in files and "strides.csv" in files:
            found.append(os.path.relpath(root, data))
    return sorted(found)


def select_walks(walks, names):
    if not names:
        return walks
    wanted = [n.strip().strip("/") for arg in names for n in arg.split(",") if n.strip()]
    chosen = []
    for n in wanted:
        hits = [w for w in walks if w == n or os.path.basename(w) == n]
        if not hits:
            sys.exit(f"no walk {n!r} under the data folder (found: {', '.join(walks)})")
        chosen += [w for w in hits if w not in chosen]
    return chosen


def read_strides(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [(float(r["t"]), float(r["x"]), float(r["y"])) for r in rows]


def write_truth(strides, path, mode):
    """truth.csv `t,x,y` for `footslam eval --truth` (see the module doc for the modes)."""
    if mode == "strides":
        rows = strides
    else:
        rows = []
        n = len(strides)
        gaps = [b[0] - a[0] for a, b in zip(strides, strides[1:])]
        typical = statistics.median(gaps) if gaps else 0.0
        for i, (t, x, y) in enumerate(strides):
            before = HOLD_S if i == 0 else min(HOLD_S, 0.45 * gaps[i - 1])
            if i == n - 1 and i > 0:
                # The end of the recording: the foot landed about a typical stride after the
                # previous stance and stood there since.
                before = max(before, gaps[i - 1] - typical)
            after = HOLD_S if i == n - 1 else min(HOLD_S, 0.45 * (strides[i + 1][0] - t))
            rows += [(t - before, x, y), (t, x, y), (t + after, x, y)]
    with open(path, "w") as f:
        f.write("t,x,y\n")
        for t, x, y in rows:
            f.write(f"{t:.6f},{x:.6f},{y:.6f}\n")


def flags(summary):
    """The learn summary.json fields that could flag a bad run: every top-level number, the
    `heading` block's numbers (final_sigma_deg: how unsure the map's orientation stayed), and
    any warnings. Fields a later build adds are picked up too."""
    out = {}
    for k, v in summary.items():
        if isinstance(v, bool) or k in ("seed", "best_particle", "threads", "version"):
            continue
        if isinstance(v, (int, float)) and not k.endswith("runtime_s") and k != "particle_steps_per_s":
            out[k] = v
    for k, v in (summary.get("heading") or {}).items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out[f"heading.{k}"] = v
        elif isinstance(v, str):
            out[f"heading.{k}"] = v
    for k in ("warnings", "warning"):
        if summary.get(k):
            out[k] = summary[k]
    return out


def error_figures(report):
    return {k: report[k] for k in ("n", "skipped", "p50", "p95", "max", "rmse")}


def ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    r = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return r


def spearman(xs, ys):
    if len(xs) < 3:
        return None
    rx, ry = ranks(xs), ranks(ys)
    mx, my = statistics.fmean(rx), statistics.fmean(ry)
    sxy = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    sxx = sum((a - mx) ** 2 for a in rx)
    syy = sum((b - my) ** 2 for b in ry)
    return sxy / math.sqrt(sxx * syy) if sxx > 0 and syy > 0 else None


def run_walk(a, walk):
    src = os.path.normpath(os.path.join(a.data, walk))
    run = os.path.normpath(os.path.join(a.work, walk))
    os.makedirs(run, exist_ok=True)
    steps_dir = os.path.join(run, "steps")
    steps = os.path.join(steps_dir, "steps.csv")
    reused = os.path.isfile(steps) and not a.fresh
    if not reused:
        if os.path.isdir(steps_dir):
            shutil.rmtree(steps_dir)
        footslam(a.binary, "steps", "--imu", os.path.join(src, "imu.csv"), "--mount", "foot", "--out", steps_dir)
    with open(os.path.join(steps_dir, "summary.json")) as f:
        steps_summary = json.load(f)
    strides = read_strides(os.path.join(src, "strides.csv"))
    truth = os.path.join(run, "truth.csv")
    write_truth(strides, truth, a.truth_mode)
    result = {
        "walk": walk,
        "steps_reused": reused,
        "steps": steps_summary.get("steps"),
        "truth_strides": len(strides) - 1,
        "truth_distance_m": sum(math.hypot(b[1] - a_[1], b[2] - a_[2]) for a_, b in zip(strides, strides[1:])),
        "steps_total_length_m": steps_summary.get("total_length_m"),
        "steps_warnings": steps_summary.get("warnings", []),
        "steps_detector": {k: steps_summary.get("detector", {}).get(k) for k in ("gated_stances", "merged_strides", "split_strides", "gaps_skipped", "strides_lost_to_gaps")},
        "runs": [],
        "failed": [],
    }
    dr = None
    for seed in a.seeds:
        out = os.path.join(run, f"learn-{seed}")
        try:
            if os.path.isdir(out):
                shutil.rmtree(out)
            _, err = footslam(a.binary, "learn", "--steps", steps, "--seed", seed, "--particles", a.particles, *a.learn_arg, "--out", out)
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            stdout, _ = footslam(a.binary, "eval", "--truth", truth, "--track", os.path.join(out, "track.csv"), "--align", "rigid", "--steps", steps, "--json")
            v = json.loads(stdout)
        except RuntimeError as e:
            result["failed"].append({"seed": seed, "error": str(e)})
            print(f"{walk} seed {seed}: FAILED {e}", file=sys.stderr)
            continue
        this_dr = error_figures(v["dead_reckoning"])
        if dr is None:
            dr = this_dr
        elif abs(this_dr["p95"] - dr["p95"]) > 1e-9:
            raise RuntimeError(f"{walk}: dead reckoning's p95 differs between seeds ({dr['p95']} vs {this_dr['p95']})")
        learned = error_figures(v["track"])
        warn_lines = [l for l in err.splitlines() if "warn" in l.lower()]
        result["runs"].append({
            "seed": seed,
            "learned": learned,
            "ratio": learned["p95"] / this_dr["p95"],
            "flags": flags(summary),
            "stderr_warnings": warn_lines,
        })
    result["dead_reckoning"] = dr
    if result["runs"]:
        p95s = [r["learned"]["p95"] for r in result["runs"]]
        ratios = [r["ratio"] for r in result["runs"]]
        result["learned_p95_mean"] = statistics.fmean(p95s)
        result["ratio_mean"] = statistics.fmean(ratios)
        result["ratio_worst"] = max(ratios)
        result["ratio_best"] = min(ratios)
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=DEFAULT_DATA, help=f"folder of walk folders (default {DEFAULT_DATA})")
    ap.add_argument("--work", default=os.path.join("outputs", "hallway-figures"), help="working folder (default outputs/hallway-figures)")
    ap.add_argument("--out", help="figures JSON (default WORK/figures.json)")
    ap.add_argument("--binary", default=None, help=f"footslam binary (default target/release/footslam under the repo, else {FALLBACK_BINARY})")
    ap.add_argument("--seeds", type=parse_seeds, default=[0, 1, 2, 3], help="filter seeds, e.g. 0,1,2,3 or 0-3 (default 0-3)")
    ap.add_argument("--particles", type=int, default=20000)
    ap.add_argument("--learn-arg", action="append", default=[], help="extra argument for every `footslam learn`, repeatable: --learn-arg=--config --learn-arg=FILE")
    ap.add_argument("--walks", action="append", help="walk names (relative path or folder name), comma-separated or repeated (default: all found)")
    ap.add_argument("--truth-mode", choices=("strides", "held"), default="strides", help="how truth.csv is made from strides.csv (see above; default strides)")
    ap.add_argument("--fresh", action="store_true", help="recompute steps even where WORK/<walk>/steps/steps.csv exists")
    a = ap.parse_args()
    a.binary = a.binary or default_binary()
    if not (os.path.isfile(a.binary) and os.access(a.binary, os.X_OK)):
        sys.exit(f"no footslam binary at {a.binary}")
    a.out = a.out or os.path.join(a.work, "figures.json")
    walks = select_walks(discover_walks(a.data), a.walks)
    if not walks:
        sys.exit(f"no walks (folders with imu.csv and strides.csv) under {a.data}")
    os.makedirs(a.work, exist_ok=True)
    version = footslam(a.binary, "--version")[0].strip()

    per_walk, failed = [], []
    bar = Progress(len(walks), f"walks × {len(a.seeds)} seeds")
    for w in walks:
        bar.start(w)
        try:
            r = run_walk(a, w)
        except RuntimeError as e:
            failed.append({"walk": w, "error": str(e)})
            bar.failed(w, e)
            continue
        failed += [{"walk": w, **f} for f in r["failed"]]
        per_walk.append(r)
        note = ""
        if r["runs"]:
            ratios = " ".join(f"{x['ratio']:.2f}" for x in r["runs"])
            note = (f"DR p95 {r['dead_reckoning']['p95']:.2f} m, learned p95 {r['learned_p95_mean']:.2f} m "
                    f"(ratios {ratios})")
        bar.done(w, note)
    bar.finish()

    done = [r for r in per_walk if r["runs"]]
    runs = [(r["walk"], x) for r in done for x in r["runs"]]
    worst = max(runs, key=lambda wx: wx[1]["ratio"]) if runs else None
    numeric = sorted({k for _, x in runs for k, v in x["flags"].items() if isinstance(v, (int, float))})
    correlations = {}
    for k in numeric:
        pairs = [(x["flags"][k], x["ratio"]) for _, x in runs if isinstance(x["flags"].get(k), (int, float))]
        rho = spearman([p[0] for p in pairs], [p[1] for p in pairs])
        if rho is not None:
            correlations[k] = rho
    # Across runs the walks' sizes dominate (steps, path length); within a walk only the seed
    # differs, so the mean of the per-walk rank correlations says whether a field flags the
    # bad seed of a walk.
    within = {}
    for k in numeric:
        rhos = []
        for r in done:
            pairs = [(x["flags"][k], x["ratio"]) for x in r["runs"] if isinstance(x["flags"].get(k), (int, float))]
            rho = spearman([p[0] for p in pairs], [p[1] for p in pairs])
            if rho is not None:
                rhos.append(rho)
        if rhos:
            within[k] = statistics.fmean(rhos)
    figures = {
        "data": os.path.abspath(a.data),
        "binary": os.path.abspath(a.binary),
        "version": version,
        "seeds": a.seeds,
        "particles": a.particles,
        "learn_args": a.learn_arg,
        "truth_mode": a.truth_mode,
        "walks": len(walks),
        "failed": failed,
        "median_of_mean_ratios": statistics.median([r["ratio_mean"] for r in done]) if done else None,
        "worst_ratio": {"walk": worst[0], "seed": worst[1]["seed"], "ratio": worst[1]["ratio"]} if worst else None,
        "walks_mean_ratio_above_1": sum(r["ratio_mean"] > 1 for r in done),
        "flag_ratio_spearman": correlations,
        "flag_ratio_spearman_within_walks": within,
        "per_walk": per_walk,
    }
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(figures, f, indent=2)

    n_seeds = len(a.seeds)
    print(f"| walk | DR p95 | learned p95 (mean of {n_seeds} seeds) | ratio (mean) | ratio (worst seed) |")
    print("|---|---|---|---|---|")
    for r in done:
        partial = "" if len(r["runs"]) == n_seeds else f" ({len(r['runs'])} seeds)"
        print(f"| {r['walk']} | {r['dead_reckoning']['p95']:.2f} m | {r['learned_p95_mean']:.2f} m{partial} | "
              f"{r['ratio_mean']:.2f} | {r['ratio_worst']:.2f} |")
    if done:
        print(f"\nmedian of the walks' mean ratios {figures['median_of_mean_ratios']:.2f}; worst ratio "
              f"{worst[1]['ratio']:.2f} ({worst[0]}, seed {worst[1]['seed']}); "
              f"{figures['walks_mean_ratio_above_1']} of {len(done)} walks worse than dead reckoning on average")
        print(f"truth mode {a.truth_mode}; points compared per walk (learned/skipped): "
              + ", ".join(f"{r['walk']} {r['runs'][0]['learned']['n']}/{r['runs'][0]['learned']['skipped']}" for r in done))
        shown = [k for k in ("heading.final_sigma_deg", "min_effective_sample_size", "final_effective_sample_size",
                             "resamplings", "best_path_log_likelihood", "hexagons") if k in numeric]
        print(f"\n| walk | seed | ratio | {' | '.join(shown)} |")
        print("|---|---|---|" + "---|" * len(shown))
        for w, x in runs:
            vals = " | ".join(f"{x['flags'][k]:.4g}" if isinstance(x["flags"].get(k), (int, float)) else "-" for k in shown)
            warn = " (warnings)" if x["flags"].get("warnings") or x["stderr_warnings"] else ""
            print(f"| {w} | {x['seed']} | {x['ratio']:.2f}{warn} | {vals} |")
        for label, c in (("over all runs", correlations), ("within walks (mean over walks)", within)):
            if c:
                print(f"\nSpearman rank correlation with the run's ratio, {label}: "
                      + ", ".join(f"{k} {v:+.2f}" for k, v in sorted(c.items(), key=lambda kv: -abs(kv[1]))))
    print(f"\nwrote {a.out}")
    if failed:
        print(f"{len(failed)} runs failed (see {a.out})", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
