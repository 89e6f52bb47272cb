#!/usr/bin/env python3
"""Error models of footslam's step sensors, measured on real recordings (issue 17, item 1).

Runs `footslam steps` on the shared recordings and compares the step events with the truth:

* foot (`--mount foot`): the foot-imu walks (PyShoe Vicon room, hallway footprints), one truth
  footprint per stride: stride-length error, heading-change error (the steps' `dheading`, the
  change of the stride's direction, against the change of the chord between footprints),
  cumulative heading error (drift), their tails, autocorrelation and dependence on pace and
  turns;
* phone (`--mount phone`): the ILC 2.0 site-1 F1 traces, sparse waypoints: per-segment stride
  scale, absolute heading (rotation vector) error per step and per segment, relative heading
  drift of the gyroscope-only heading.

Fits the FootSLAM `[motion]` / `[heading]`, tracker and simulator (`StepNoiseConfig`,
`CompassSimConfig`) parameters per mount, checks them by simulating the same statistics with
a port of the simulator's noise model, prints a table, writes `error_models.json` into OUT
and the figures `error-models-*.png` into FIGDIR. The method and the results are in
docs/error-models.md.

    scripts/error_models.py [--foot-data DIR] [--ilc-data DIR] [--footslam BIN]
                            [--out OUT] [--fig-dir FIGDIR] [--reuse]

Needs numpy and matplotlib; scipy, where installed, is used for the maximum-likelihood fit of
the heading state-space model (a coarse grid search otherwise).
"""
import argparse
import glob
import json
import math
import os
import shutil
import subprocess

from progress import Progress
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

try:
    from scipy.optimize import minimize as _minimize
except ImportError:  # pragma: no cover - optional
    _minimize = None

DEG = 180.0 / math.pi
WALKING_STRIDE_M = 0.5  # strides shorter than this have an ill-defined direction
MATCH_TOLERANCE_S = 0.5

# ----------------------------------------------------------------------------------------
# small statistics helpers


def wrap(a):
    """Angle(s) wrapped to [-pi, pi)."""
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def robust_sigma(x):
    """1.4826 x median absolute deviation from the median."""
    x = np.asarray(x, float)
    if len(x) == 0:
        return float("nan")
    return float(1.4826 * np.median(np.abs(x - np.median(x))))


def excess_kurtosis(x):
    x = np.asarray(x, float)
    if len(x) < 4:
        return float("nan")
    m = x - x.mean()
    return float(np.mean(m**4) / np.mean(m**2) ** 2 - 3.0)


def summary(x, scale=1.0):
    """Distribution figures of x (multiplied by scale for display units)."""
    x = np.asarray(x, float) * scale
    if len(x) == 0:
        return {"n": 0}
    a = np.abs(x - np.median(x))
    rs = robust_sigma(x)
    return {
        "n": int(len(x)),
        "mean": float(x.mean()),
        "sigma": float(x.std(ddof=1)) if len(x) > 1 else float("nan"),
        "robust_sigma": rs,
        "p50_abs": float(np.percentile(np.abs(x), 50)),
        "p95_abs": float(np.percentile(np.abs(x), 95)),
        "p99_abs": float(np.percentile(np.abs(x), 99)),
        "max_abs": float(np.abs(x).max()),
        "excess_kurtosis": excess_kurtosis(x),
        "share_beyond_3_robust_sigma": float(np.mean(a > 3 * rs)) if rs > 0 else float("nan"),
    }


def fit_student_t(x, nus=(1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10, 15, 20, 30, 50, 1e6)):
    """Maximum-likelihood Student-t (location 0 fixed; scale by EM for each nu on a grid)."""
    x = np.asarray(x, float)
    best = None
    from math import lgamma

    for nu in nus:
        s2 = np.var(x) if np.var(x) > 0 else 1e-12
        for _ in range(200):
            w = (nu + 1) / (nu + x * x / s2)
            s2_new = np.mean(w * x * x)
            if abs(s2_new - s2) < 1e-12 * s2:
                break
            s2 = s2_new
        s = math.sqrt(s2)
        ll = np.sum(
            lgamma((nu + 1) / 2)
            - lgamma(nu / 2)
            - 0.5 * math.log(nu * math.pi)
            - math.log(s)
            - (nu + 1) / 2 * np.log1p(x * x / (nu * s2))
        )
        if best is None or ll > best["loglik"]:
            best = {"nu": float(nu), "scale": s, "loglik": float(ll)}
    g = np.var(x)
    best["gauss_loglik"] = float(np.sum(-0.5 * math.log(2 * math.pi * g) - x * x / (2 * g)))
    return best


def fit_gauss_uniform(x, width=2 * math.pi, iters=300):
    """EM fit of (1 - eps) N(0, sigma) + eps U(width): the form of the heading likelihood."""
    x = np.asarray(x, float)
    sigma, eps = max(robust_sigma(x), 1e-3), 0.05
    for _ in range(iters):
        pin = (1 - eps) * np.exp(-0.5 * (x / sigma) ** 2) / (sigma * math.sqrt(2 * math.pi))
        pout = eps / width
        r = pin / (pin + pout)
        sigma_new = math.sqrt(np.sum(r * x * x) / max(np.sum(r), 1e-9))
        eps_new = 1 - np.mean(r)
        if abs(sigma_new - sigma) < 1e-9 and abs(eps_new - eps) < 1e-9:
            break
        sigma, eps = sigma_new, eps_new
    return {"sigma": float(sigma), "outlier_probability": float(eps)}


def binned(x, y, edges, fn=robust_sigma):
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (x >= lo) & (x < hi)
        out.append({"lo": float(lo), "hi": float(hi), "n": int(m.sum()),
                    "value": float(fn(y[m])) if m.sum() >= 5 else float("nan")})
    return out


def acf_by_lag(series_list, max_lag):
    """Autocorrelation pooled over several series (each demeaned), lags 1..max_lag."""
    num = np.zeros(max_lag + 1)
    cnt = np.zeros(max_lag + 1)
    var = 0.0
    nvar = 0
    for s in series_list:
        s = np.asarray(s, float)
        if len(s) < 3:
            continue
        s = s - s.mean()
        var += np.sum(s * s)
        nvar += len(s)
        for lag in range(1, min(max_lag, len(s) - 1) + 1):
            num[lag] += np.sum(s[:-lag] * s[lag:])
            cnt[lag] += len(s) - lag
    v = var / max(nvar, 1)
    return [float(num[k] / cnt[k] / v) if cnt[k] > 0 else float("nan") for k in range(1, max_lag + 1)], \
        [int(c) for c in cnt[1:]]


def footslam(binary, *args):
    r = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"footslam {' '.join(map(str, args))}: {r.stderr.strip()}")
    return r.stdout


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {h: data[:, i] for i, h in enumerate(header)}


def run_steps(binary, imu, mount, out, reuse, config=None):
    if reuse and os.path.exists(os.path.join(out, "steps.csv")):
        return read_csv(os.path.join(out, "steps.csv"))
    if os.path.exists(out):
        shutil.rmtree(out)
    args = ["steps", "--imu", imu, "--mount", mount, "--out", out]
    if config:
        args += ["--config", config]
    footslam(binary, *args)
    return read_csv(os.path.join(out, "steps.csv"))


# ----------------------------------------------------------------------------------------
# the heading state-space model: e_k = c + b_k + w_k, b_{k+1} = b_k + r_k + s_k,
# r_{k+1} = r_k + q_k, r_0 ~ N(0, sigma_r0), c diffuse (the unknown initial heading)


def kf_loglik(series, sigma_s, sigma_w, sigma_r0, sigma_q):
    """Marginal log-likelihood of the cumulative heading errors of several walks.

    Each series is (index, e): stride index (integers; gaps where strides were merged or left
    out) and cumulative heading error. State: heading error b (offset diffuse: the first
    observation sets it) and drift rate r ~ N(0, sigma_r0) at the start. Scalar arithmetic
    (fast enough for a few hundred strides per evaluation)."""
    total = 0.0
    R = sigma_w * sigma_w
    qs, qq = sigma_s * sigma_s, sigma_q * sigma_q
    for idx, e in series:
        b, r = float(e[0]), 0.0
        p00, p01, p11 = R, 0.0, sigma_r0 * sigma_r0
        for i in range(1, len(e)):
            for _ in range(int(idx[i] - idx[i - 1])):
                b += r
                p00, p01, p11 = p00 + 2 * p01 + p11 + qs, p01 + p11, p11 + qq
            S = p00 + R
            v = float(e[i]) - b
            total += -0.5 * (math.log(2 * math.pi * S) + v * v / S)
            k0, k1 = p00 / S, p01 / S
            b += k0 * v
            r += k1 * v
            p00, p01, p11 = p00 - k0 * p00, p01 - k0 * p01, p11 - k1 * p01
    return total


def fit_heading_model(series, fixed=None):
    """ML fit of (sigma_s, sigma_w, sigma_r0, sigma_q), radians per stride; `fixed` pins some
    of them by name (for a profile likelihood)."""
    names = ("sigma_s", "sigma_w", "sigma_r0", "sigma_q")
    fixed = fixed or {}
    free = [n for n in names if n not in fixed]

    def params(p):
        d = dict(fixed)
        d.update({n: math.exp(v) for n, v in zip(free, p)})
        return d

    def nll(p):
        d = params(p)
        return -kf_loglik(series, d["sigma_s"], d["sigma_w"], d["sigma_r0"], d["sigma_q"])

    starts = [np.log([{"sigma_s": a, "sigma_w": b, "sigma_r0": c, "sigma_q": q}[n] for n in free])
              for a, b, c, q in ((0.02, 0.1, 0.003, 1e-4), (0.05, 0.05, 0.001, 1e-5),
                                 (0.005, 0.15, 0.01, 1e-3))]
    if _minimize is not None:
        best = None
        for st in starts:
            r = _minimize(nll, st, method="Nelder-Mead",
                          options={"maxiter": 3000, "xatol": 1e-3, "fatol": 1e-3})
            if best is None or r.fun < best.fun:
                best = r
        p, ll = best.x, -best.fun
    else:  # coarse grid
        axes = {"sigma_s": (0.003, 0.01, 0.03, 0.1), "sigma_w": (0.03, 0.1, 0.3),
                "sigma_r0": (0.0003, 0.001, 0.003, 0.01), "sigma_q": (1e-5, 1e-4, 1e-3)}
        import itertools
        grid = [np.log(g) for g in itertools.product(*[axes[n] for n in free])]
        vals = [nll(g) for g in grid]
        p, ll = grid[int(np.argmin(vals))], -min(vals)
    out = params(p)
    out["loglik"] = float(ll)
    return out


def clean_series(series, k=4.0):
    """Drops points whose error departs from the median of its 5 neighbours by more than k
    robust sigmas (pooled): the Gaussian state-space model is not robust to the tails."""
    devs = []
    for idx, e in series:
        for i in range(len(e)):
            lo, hi = max(0, i - 2), min(len(e), i + 3)
            devs.append(e[i] - np.median(e[lo:hi]))
    s = robust_sigma(np.array(devs))
    out, dropped, j = [], 0, 0
    for idx, e in series:
        keep = []
        for i in range(len(e)):
            keep.append(abs(devs[j]) <= k * s)
            j += 1
        keep = np.array(keep)
        dropped += int((~keep).sum())
        if keep.sum() >= 3:
            out.append((idx[keep], e[keep]))
    return out, dropped


def huber_line(x, y, c=1.5, iters=50):
    """Huber-robust straight line: slope, its standard error (from the weighted fit), residuals."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    w = np.ones_like(x)
    for _ in range(iters):
        W = np.sqrt(w)
        A = np.c_[np.ones_like(x), x] * W[:, None]
        coef, *_ = np.linalg.lstsq(A, y * W, rcond=None)
        r = y - coef[0] - coef[1] * x
        s = max(robust_sigma(r), 1e-9)
        w_new = np.minimum(1.0, c * s / np.maximum(np.abs(r), 1e-12))
        if np.allclose(w_new, w, atol=1e-6):
            break
        w = w_new
    A = np.c_[np.ones_like(x), x]
    cov = s * s * np.linalg.inv((A * w[:, None]).T @ A)
    return float(coef[1]), float(math.sqrt(cov[1, 1])), r, float(coef[0])


# ----------------------------------------------------------------------------------------
# foot


def foot_units(steps, truth):
    """Pairs step events with truth strides by time.

    Returns (units, info). A unit is the run of steps that ends at a step matched to a truth
    row (nearest row within MATCH_TOLERANCE_S; the last row, the end of the recording, takes
    the last step when that is later than the row before). Steps matched to no row, or to a
    row already taken, join the next unit, so that the units' lengths and heading changes add
    up to the trace's; so do split strides (a stride longer than the step-trace limit, cut in
    equal parts with the whole turn on the first part: dheading exactly 0 and the same length
    as the step before)."""
    ts, tt = steps["t"], truth["t"]
    n, N = len(ts), len(tt)
    P = np.c_[truth["x"], truth["y"]]
    Z = truth["z"]
    j = np.full(n, -1)
    for k, t in enumerate(ts):
        i = int(np.argmin(np.abs(tt[: N - 1] - t)))
        if abs(tt[i] - t) < MATCH_TOLERANCE_S:
            j[k] = i
    if n and j[-1] < 0 and ts[-1] > tt[N - 2]:
        j[-1] = N - 1
    split = np.zeros(n, bool)
    split[1:] = (steps["dheading"][1:] == 0.0) & (steps["length"][1:] == steps["length"][:-1])
    H = np.cumsum(steps["dheading"])
    units, cur, jprev = [], [], 0
    pre_steps = dropped = extra = 0
    for k in range(n):
        cur.append(k)
        if j[k] < 0 or (k + 1 < n and split[k + 1]):
            continue
        if j[k] == 0:  # before the first stance
            pre_steps += len(cur)
            cur = []
            continue
        if j[k] <= jprev:  # a second step on one stance (a spurious stance): joins the next
            extra += 1
            continue
        j0, j1 = jprev, int(j[k])
        seg = np.diff(P[j0: j1 + 1], axis=0)
        d = P[j1] - P[j0]
        units.append({
            "steps": list(cur), "j0": j0, "j1": j1, "t": float(tt[j1]),
            "dur": float(tt[j1] - tt[j0]),
            "length": float(steps["length"][cur].sum()),
            "dheading": float(steps["dheading"][cur].sum()),
            "dz": float(steps["dz"][cur].sum()),
            "H": float(H[cur[-1]]),
            "truth_length": float(np.hypot(seg[:, 0], seg[:, 1]).sum()),
            "chord": float(math.atan2(d[1], d[0])),
            "truth_dz": float(Z[j1] - Z[j0]),
            "single": len(cur) == 1 and j1 - j0 == 1,
            "split": any(split[c] for c in cur),
        })
        jprev = j1
        cur = []
    dropped += len(cur)
    info = {"steps": int(n), "truth_strides": int(N - 1), "units": len(units),
            "matched_steps": int(sum(len(u["steps"]) for u in units)),
            "single_units": int(sum(u["single"] for u in units)),
            "split_steps": int(split.sum()), "pre_steps": int(pre_steps),
            "extra_steps": int(extra), "unmatched_steps": int(dropped)}
    return units, info


def foot_walk_arrays(units):
    """Arrays of one walk. The step model moves stride k along H_k, the sum of the `dheading`
    up to and including it (`dheading` is the change of the direction of the stride's INS
    displacement, so H_k is that direction less the first stance's yaw). Errors against the
    truth: x_k = dheading_k - truth turn_k (the change of the chord between footprints) per
    stride, and the cumulative e_k = H_k - truth chord_k, from the first walking stride."""
    U = len(units)
    a = {k: np.array([u[k] for u in units], float) for k in
         ("t", "dur", "length", "dheading", "dz", "H", "truth_length", "chord", "truth_dz", "j1")}
    a["j1"] = a["j1"].astype(int)
    a["single"] = np.array([u["single"] for u in units])
    turn = np.full(U, np.nan)
    turn[1:] = wrap(np.diff(a["chord"]))
    a["turn"] = turn
    x = np.full(U, np.nan)
    x[1:] = wrap(a["dheading"][1:] - turn[1:])
    a["x"] = x
    walking = (a["truth_length"] >= WALKING_STRIDE_M) & a["single"]
    # the first stride starts from standing: it takes no part in the heading statistics (its
    # direction is the reference of the cumulative error)
    good = np.zeros(U, bool)
    good[2:] = walking[2:] & walking[1:-1]
    a["good"], a["walking"] = good, walking
    w = np.where(walking & (np.arange(U) >= 1))[0]
    e = np.full(U, np.nan)
    if len(w):
        raw = np.unwrap(wrap(a["H"][w] - a["chord"][w]))
        e[w] = raw - raw[0]
    a["e"] = e
    a["cum_turn"] = np.cumsum(np.nan_to_num(turn))
    return a


def linear_fit(x, y):
    """Least-squares slope with its standard error."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    A = np.c_[np.ones_like(x), x]
    coef, res, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ coef
    dof = max(len(x) - 2, 1)
    s2 = np.sum(r * r) / dof
    cov = s2 * np.linalg.inv(A.T @ A)
    return float(coef[1]), float(math.sqrt(cov[1, 1])), r, float(coef[0])


def spread_beyond_noise(values, ses):
    """Between-walk standard deviation of values beyond their estimation errors (moments)."""
    v = np.asarray(values, float)
    s = np.asarray(ses, float)
    return float(math.sqrt(max(0.0, np.var(v, ddof=1) - np.mean(s * s))))


def analyse_foot(data_dir, binary, work, reuse):
    walks = []
    found = [d for d in sorted(glob.glob(os.path.join(data_dir, "*", "*")))
             if os.path.exists(os.path.join(d, "strides.csv"))]
    bar = Progress(len(found), "foot walks")
    for d in found:
        kind, name = d.rstrip("/").split("/")[-2:]
        bar.start(f"{kind}/{name}")
        steps = run_steps(binary, os.path.join(d, "imu.csv"), "foot",
                          os.path.join(work, "foot", f"{kind}_{name}"), reuse)
        truth = read_csv(os.path.join(d, "strides.csv"))
        units, info = foot_units(steps, truth)
        a = foot_walk_arrays(units)
        walks.append({"kind": kind, "name": name, "info": info, "a": a})
        bar.done(f"{kind}/{name}")
    bar.finish()
    return walks


def foot_statistics(walks):
    out = {"walks": []}
    pooled = {k: [] for k in ("x", "turn", "kind", "dur_h", "lres", "lrel", "dur", "lturn", "dz",
                              "lres_kind")}
    series, acf_h, acf_len = [], [], []
    scales, paces = [], []
    for w in walks:
        a = w["a"]
        g, wk = a["good"], a["walking"]
        # per-walk scale over every unit (sums stay consistent for merged and split units)
        scale = a["length"].sum() / a["truth_length"].sum()
        scales.append(scale)
        r = a["length"] - scale * a["truth_length"]
        single = a["single"] & (a["truth_length"] >= WALKING_STRIDE_M)
        paces.append(float(np.median(a["dur"][single])))
        pooled["lres"].append(r[single])
        pooled["lrel"].append(r[single] / a["truth_length"][single])
        pooled["dur"].append(a["dur"][single])
        pooled["lturn"].append(np.abs(np.nan_to_num(a["turn"]))[single])
        pooled["lres_kind"].append(np.full(int(single.sum()), w["kind"] == "hallway"))
        pooled["dz"].append((a["dz"] - a["truth_dz"])[a["single"]])
        pooled["x"].append(a["x"][g])
        pooled["turn"].append(np.abs(a["turn"][g]))
        pooled["kind"].append(np.full(int(g.sum()), w["kind"] == "hallway"))
        pooled["dur_h"].append(a["dur"][g])
        acf_h.append(a["x"][g])
        acf_len.append(r[single])
        wk = wk & (np.arange(len(wk)) >= 1)
        idx, e = a["j1"][wk], a["e"][wk]
        series.append((idx, e))
        slope, se, resid, _ = huber_line(idx, e)
        slope_t, se_t, _, _ = huber_line(a["t"][wk], e)
        out["walks"].append({
            "walk": f"{w['kind']}/{w['name']}", **w["info"],
            "duration_s": float(a["t"][-1] - (a["t"][0] - a["dur"][0])),
            "truth_distance_m": float(a["truth_length"].sum()), "scale": float(scale),
            "median_stride_s": paces[-1],
            "length_residual_robust_sigma_m": robust_sigma(r[single]),
            "drift_deg_per_stride": slope * DEG, "drift_se_deg_per_stride": se * DEG,
            "drift_deg_per_s": slope_t * DEG, "drift_se_deg_per_s": se_t * DEG,
            "final_cum_error_deg": float(e[-1] * DEG),
            "residual_robust_sigma_deg": robust_sigma(resid) * DEG,
            "heading_change_robust_sigma_deg": robust_sigma(a["x"][g]) * DEG})
    P = {k: np.concatenate(v) for k, v in pooled.items()}
    hall = P["kind"]
    T = P["turn"]
    X = P["x"]
    out["matching"] = {k: int(sum(w["info"][k] for w in walks))
                       for k in ("steps", "truth_strides", "matched_steps", "units", "single_units",
                                 "split_steps", "extra_steps", "pre_steps")}
    out["matching"]["walking_pairs"] = int(len(T))
    t = fit_student_t(X)
    gu = fit_gauss_uniform(X)
    hc = {"all": summary(X, DEG), "hallway": summary(X[hall], DEG), "vicon": summary(X[~hall], DEG),
          "straight_lt_10deg": summary(X[T < math.radians(10)], DEG),
          "student_t": {"nu": t["nu"], "scale_deg": t["scale"] * DEG,
                        "loglik": t["loglik"], "gauss_loglik": t["gauss_loglik"]},
          "gauss_uniform": {"sigma_deg": gu["sigma"] * DEG,
                            "outlier_probability": gu["outlier_probability"]},
          "by_turn": binned(T * DEG, X * DEG, [0, 10, 30, 60, 90, 180]),
          "by_duration_s": binned(P["dur_h"], X * DEG, [0.0, 0.8, 0.95, 1.1, 1.25, 1.45, 3.0]),
          "lookahead_check": _lookahead(walks),
          "beyond_10deg": [{"walk": f"{w['kind']}/{w['name']}", "stride": int(k),
                            "error_deg": float(w["a"]["x"][k] * DEG), "turn_deg": float(w["a"]["turn"][k] * DEG),
                            "length_m": float(w["a"]["length"][k]), "truth_length_m": float(w["a"]["truth_length"][k]),
                            "cum_error_deg": float(w["a"]["e"][k] * DEG)}
                           for w in walks for k in np.where(w["a"]["good"] & (np.abs(w["a"]["x"]) > math.radians(10)))[0]]}
    # truth noise: the hallway footprints' error bounded by the hallway length residual (a
    # footprint error sigma_fp gives at least sqrt(2) sigma_fp on a stride length), then its
    # share of the heading-change error: a shared footprint enters two chords, sqrt(6) sigma_fp / L
    lres_h = robust_sigma(P["lres"][P["lres_kind"]])
    fp = lres_h / math.sqrt(2)
    L_h = float(np.median(np.concatenate([w["a"]["truth_length"][w["a"]["walking"]] for w in walks
                                          if w["kind"] == "hallway"])))
    rs_h, rs_v = hc["hallway"]["robust_sigma"], hc["vicon"]["robust_sigma"]
    hc["truth_noise"] = {
        "hallway_footprint_sigma_upper_m": fp,
        "hallway_median_stride_m": L_h,
        "heading_change_noise_upper_deg": math.sqrt(6) * fp / L_h * DEG,
        "hallway_excess_over_vicon_deg": math.sqrt(max(rs_h**2 - rs_v**2, 0)),
        "vicon": "millimetre markers: below 0.1 deg per stride",
    }
    out["heading_change"] = hc
    # heading state-space fit (with profiles of sigma_s and sigma_q), variogram, per-walk drift
    clean, dropped = clean_series(series)
    fit = fit_heading_model(clean)
    prof_q = [(q, fit_heading_model(clean, fixed={"sigma_q": q})["loglik"])
              for q in (1e-5, 3e-5, 1e-4, 3e-4, 1e-3, 3e-3)]
    upper_q = _profile_interval(prof_q, fit["sigma_q"], fit["loglik"])[1]
    prof_s = [(sv, fit_heading_model(clean, fixed={"sigma_s": math.radians(sv)})["loglik"])
              for sv in (0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.4, 1.7, 2.0, 3.0)]
    ml = {**{k: v * DEG for k, v in fit.items() if k.startswith("sigma")},
          "loglik": fit["loglik"], "points": int(sum(len(e) for _, e in series)),
          "points_dropped_as_outliers": dropped,
          "sigma_q_upper95_deg": upper_q * DEG,
          "sigma_s_interval95_deg": _profile_interval(prof_s, fit["sigma_s"] * DEG, fit["loglik"]),
          "profile_sigma_s": prof_s,
          "profile_sigma_q": [[q * DEG, ll] for q, ll in prof_q]}
    # how the fit depends on the outlier cut, and per site
    ml["by_outlier_cut"] = {}
    for k in (6.0, 8.0):
        c, d = clean_series(series, k)
        f = fit_heading_model(c)
        ml["by_outlier_cut"][f"{k:g}"] = {**{n: v * DEG for n, v in f.items() if n.startswith("sigma")},
                                          "points_dropped_as_outliers": d}
    kinds = np.array([w["kind"] == "hallway" for w in walks])
    for site, m in (("hallway", kinds), ("vicon", ~kinds)):
        c, d = clean_series([s for s, h in zip(series, m) if h])
        f = fit_heading_model(c)
        ml[site] = {**{n: v * DEG for n, v in f.items() if n.startswith("sigma")},
                    "points_dropped_as_outliers": d}
    out["heading_model_ml"] = ml
    out["variogram"] = _variogram(series, 12)
    ws = out["walks"]
    rates = np.array([w["drift_deg_per_stride"] for w in ws]) / DEG
    ses = np.array([w["drift_se_deg_per_stride"] for w in ws]) / DEG
    rates_t = np.array([w["drift_deg_per_s"] for w in ws]) / DEG
    ses_t = np.array([w["drift_se_deg_per_s"] for w in ws]) / DEG
    hallw = np.array([w["walk"].startswith("hallway") for w in ws])
    out["drift"] = {
        "rate_deg_per_stride": summary(rates, DEG),
        "rate_deg_per_s": summary(rates_t, DEG),
        "spread_beyond_noise_deg_per_stride": spread_beyond_noise(rates, ses) * DEG,
        "spread_beyond_noise_deg_per_s": spread_beyond_noise(rates_t, ses_t) * DEG,
        "hallway_spread_beyond_noise_deg_per_stride": spread_beyond_noise(rates[hallw], ses[hallw]) * DEG,
        "vicon_spread_beyond_noise_deg_per_stride": spread_beyond_noise(rates[~hallw], ses[~hallw]) * DEG,
        "hallway_spread_beyond_noise_deg_per_s": spread_beyond_noise(rates_t[hallw], ses_t[hallw]) * DEG,
        "vicon_spread_beyond_noise_deg_per_s": spread_beyond_noise(rates_t[~hallw], ses_t[~hallw]) * DEG,
        "rms_se_deg_per_stride": float(np.sqrt(np.mean(ses**2)) * DEG),
    }
    out["turn_scale_factor"] = {
        "all": _turn_scale_factor(walks),
        "hallway": _turn_scale_factor([w for w in walks if w["kind"] == "hallway"]),
        "vicon": _turn_scale_factor([w for w in walks if w["kind"] != "hallway"])}
    sc = np.array(scales)
    hs = P["lres_kind"]
    R, RR, D, LT = P["lres"], P["lrel"], P["dur"], P["lturn"]
    tl = fit_student_t(R - np.median(R))
    out["length"] = {
        "scale": {"mean": float(sc.mean()), "sd": float(sc.std(ddof=1)), "min": float(sc.min()),
                  "max": float(sc.max()), "rms_about_1": float(np.sqrt(np.mean((sc - 1) ** 2))),
                  "corr_with_median_stride_s": float(np.corrcoef(sc, paces)[0, 1])},
        "residual_m": summary(R), "residual_m_hallway": summary(R[hs]),
        "residual_m_vicon": summary(R[~hs]), "relative_residual": summary(RR),
        "student_t": {"nu": tl["nu"], "scale_m": tl["scale"]},
        "gauss_outlier_m": fit_gauss_uniform(R - np.median(R), width=1.0),
        "by_duration_s": binned(D, R, [0.0, 0.8, 0.95, 1.1, 1.25, 1.45, 3.0]),
        "mean_relative_by_duration_s": binned(D, RR, [0.0, 0.8, 0.95, 1.1, 1.25, 1.45, 3.0], fn=np.median),
        "by_turn_deg": binned(LT * DEG, R, [0, 10, 30, 60, 90, 180]),
        "mean_relative_by_turn_deg": binned(LT * DEG, RR, [0, 10, 30, 60, 90, 180], fn=np.median),
    }
    acf_x, n_x = acf_by_lag(acf_h, 8)
    acf_l, n_l = acf_by_lag(acf_len, 8)
    mean_len = float(np.mean(np.concatenate([w["a"]["truth_length"][w["a"]["walking"]] for w in walks])))
    out["autocorrelation"] = {"mean_stride_m": mean_len, "heading_change": acf_x,
                              "length_residual": acf_l, "pairs_lag1": [n_x[0], n_l[0]]}
    out["dz_error_m"] = summary(P["dz"])
    out["_arrays"] = {"X": X, "T": T, "hall": hall, "R": R, "RR": RR, "D": D, "LT": LT,
                      "series": series, "scales": sc, "paces": np.array(paces),
                      "kinds": [w["kind"] for w in walks]}
    return out


def _profile_interval(profile, best_x, best_ll, drop=1.92):
    """95 % interval of a parameter from its profile log-likelihood (points (x, loglik) on a
    grid, plus the maximum): where the profile falls `drop` below the maximum, interpolated
    linearly; an end that the grid does not reach is given as the grid's end."""
    pts = sorted(list(profile) + [(best_x, best_ll)])
    xs = np.array([p[0] for p in pts])
    ls = np.array([p[1] for p in pts]) - (best_ll - drop)
    i = int(np.argmax(xs == best_x))
    lo, hi = xs[0], xs[-1]
    for j in range(i, 0, -1):
        if ls[j - 1] < 0:
            lo = xs[j - 1] + (xs[j] - xs[j - 1]) * (0 - ls[j - 1]) / (ls[j] - ls[j - 1])
            break
    for j in range(i, len(xs) - 1):
        if ls[j + 1] < 0:
            hi = xs[j] + (xs[j + 1] - xs[j]) * ls[j] / (ls[j] - ls[j + 1])
            break
    return [float(lo), float(hi)]


def _turn_scale_factor(walks):
    """Pooled gyro scale-factor error: e = c_w + r_w k + s * (cumulative truth turn), with an
    offset and a drift rate per walk and one s for all."""
    rows, ys, nw = [], [], len(walks)
    for i, w in enumerate(walks):
        a = w["a"]
        wk = a["walking"] & np.isfinite(a["e"])
        for k in np.where(wk)[0]:
            row = np.zeros(2 * nw + 1)
            row[2 * i] = 1.0
            row[2 * i + 1] = a["j1"][k]
            row[-1] = a["cum_turn"][k]
            rows.append(row)
            ys.append(a["e"][k])
    A, y = np.array(rows), np.array(ys)
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ coef
    s2 = np.sum(r * r) / max(len(y) - A.shape[1], 1)
    cov = s2 * np.linalg.pinv(A.T @ A)
    return {"scale_factor": float(coef[-1]), "se": float(math.sqrt(cov[-1, -1])),
            "model": "e = c_walk + r_walk * stride + s * cumulative truth turn"}


def _lookahead(walks):
    """Regression of the heading-change error on the change of turn between this stride and
    the next, x_k ~ g (turn_{k+1} - turn_k). A heading that leads the stride (the foot's yaw
    at a stance, which points between the strides before and after it) gives g near 1/2;
    the stride's own direction gives g near 0."""
    d, ys = [], []
    for w in walks:
        a = w["a"]
        for k in range(1, len(a["turn"]) - 1):
            if a["good"][k] and a["good"][k + 1]:
                d.append(a["turn"][k + 1] - a["turn"][k])
                ys.append(a["x"][k])
    d, y = np.array(d), np.array(ys)
    gain = float(np.sum(d * y) / np.sum(d * d))
    return {"n": int(len(y)), "gain": gain, "robust_sigma_before_deg": robust_sigma(y) * DEG,
            "robust_sigma_after_deg": robust_sigma(y - gain * d) * DEG}


def _variogram(series, max_lag):
    """Robust variogram of the detrended cumulative heading error: for each lag, the median of
    the squared changes / 0.455 (the median of a chi-square with one degree of freedom), so a
    few outlying strides do not dominate. Fit over lags 2..8: V = 2 sigma_w^2 + lag sigma_s^2."""
    sq = {lag: [] for lag in range(1, max_lag + 1)}
    for idx, e in series:
        if len(e) < 5:
            continue
        _, _, r, _ = huber_line(idx, e)
        pos = {int(i): v for i, v in zip(idx, r)}
        for i, v in pos.items():
            for lag in range(1, max_lag + 1):
                if i + lag in pos:
                    sq[lag].append((pos[i + lag] - v) ** 2)
    lags = np.arange(1, max_lag + 1)
    v = np.array([np.median(sq[k]) / 0.4549 if sq[k] else np.nan for k in lags])
    vm = np.array([np.mean(sq[k]) if sq[k] else np.nan for k in lags])
    m = (lags >= 2) & (lags <= 8)
    slope, _, _, icpt = linear_fit(lags[m], v[m])
    return {"lag": lags.tolist(), "v_deg2": (v * DEG * DEG).tolist(), "mean_sq_deg2": (vm * DEG * DEG).tolist(),
            "pairs": [len(sq[k]) for k in lags],
            "fit_lag2_8": {"intercept_deg2": icpt * DEG * DEG, "slope_deg2_per_stride": slope * DEG * DEG,
                           "white_sigma_deg": math.sqrt(max(icpt, 0) / 2) * DEG,
                           "walk_sigma_deg_per_stride": math.sqrt(max(slope, 0)) * DEG}}



# ----------------------------------------------------------------------------------------
# phone


def step_intervals(t):
    """Each step covers (t_{k-1}, t_k]; the first step the median period before it."""
    dt = np.diff(t)
    first = t[0] - (np.median(dt) if len(dt) else 0.6)
    return np.r_[first, t[:-1]], t


def overlap(a0, a1, b0, b1):
    return np.clip(np.minimum(a1, b1) - np.maximum(a0, b0), 0, None) / np.maximum(a1 - a0, 1e-9)


def phone_walk(name, wp, rv, gy):
    t0, t1 = step_intervals(rv["t"])
    L = rv["length"]
    h = rv["heading"]
    hg = np.cumsum(gy["dheading"])  # gyroscope-only heading, from 0 at the start
    assert len(gy["t"]) == len(rv["t"]) and np.allclose(gy["t"], rv["t"])
    cum = np.cumsum(L)
    segs = []
    seg_of_step = np.full(len(L), -1)
    for i in range(len(wp["t"]) - 1):
        ta, tb = wp["t"][i], wp["t"][i + 1]
        w = overlap(t0, t1, ta, tb)
        W = np.array([wp["x"][i + 1] - wp["x"][i], wp["y"][i + 1] - wp["y"][i]])
        Lw = float(np.hypot(*W))
        R = np.array([np.sum(w * L * np.cos(h)), np.sum(w * L * np.sin(h))])
        Rg = np.array([np.sum(w * L * np.cos(hg)), np.sum(w * L * np.sin(hg))])
        S = float(np.sum(w * L))
        n = float(np.sum(w))
        inside = w > 0.5
        seg_of_step[inside] = i
        per = np.diff(t1[inside])
        segs.append({
            "i": i, "ta": float(ta), "tb": float(tb), "Lw": Lw,
            "bearing": float(math.atan2(W[1], W[0])) if Lw > 0 else float("nan"),
            "S": S, "n": n, "R": R, "Rg": Rg,
            "dir_rv": float(math.atan2(R[1], R[0])), "dir_gyro": float(math.atan2(Rg[1], Rg[0])),
            "straight_gyro": float(np.hypot(*Rg) / S) if S > 0 else 0.0,
            "straight_rv": float(np.hypot(*R) / S) if S > 0 else 0.0,
            "period": float(np.median(per)) if len(per) else float("nan"),
            "turn_gyro": float(np.sum(np.abs(gy["dheading"][inside]))) if inside.any() else 0.0,
        })
    return {"name": name, "segs": segs, "seg_of_step": seg_of_step, "h": h, "hg": hg, "L": L,
            "cum": cum, "t": t1, "dh_rv": rv["dheading"], "dh_gyro": gy["dheading"],
            "wp_length": float(sum(s["Lw"] for s in segs)), "S_total": float(sum(s["S"] for s in segs))}


def analyse_phone(ilc_dir, binary, work, reuse):
    imported = os.path.join(work, "phone", "imported")
    if not (reuse and os.path.exists(imported)):
        if os.path.exists(imported):
            shutil.rmtree(imported)
        footslam(binary, "import", "ilc", "--trace", os.path.join(ilc_dir, "path_data_files"),
                 "--floor", ilc_dir, "--out", imported)
    gyro_cfg = os.path.join(work, "phone", "gyro-only.toml")
    with open(gyro_cfg, "w") as f:
        f.write("[phone]\nuse_rotation_vector = false\nuse_magnetometer = false\n")
    walks = []
    found = [d for d in sorted(glob.glob(os.path.join(imported, "*", "")))
             if os.path.exists(os.path.join(d, "waypoints.csv"))]
    bar = Progress(len(found), "phone walks")
    for d in found:
        name = os.path.basename(d.rstrip("/"))
        bar.start(name)
        rv = run_steps(binary, os.path.join(d, "imu.csv"), "phone",
                       os.path.join(work, "phone", "steps", name + "_rv"), reuse)
        gy = run_steps(binary, os.path.join(d, "imu.csv"), "phone",
                       os.path.join(work, "phone", "steps", name + "_gyro"), reuse, gyro_cfg)
        wp = read_csv(os.path.join(d, "waypoints.csv"))
        if len(rv["t"]) < 3 or len(wp["t"]) < 2 or "heading" not in rv:
            bar.done(name, "too short, left out")
            continue
        walks.append(phone_walk(name, wp, rv, gy))
        bar.done(name)
    bar.finish()
    return walks


def phone_statistics(walks, min_seg_m=3.0, straight=0.9, very_straight=0.95):
    out = {"walks": []}
    allseg = [s for w in walks for s in w["segs"]]
    valid = [s for s in allseg if s["Lw"] >= min_seg_m and s["n"] >= 3 and s["straight_gyro"] >= straight]
    # fixed rotation between the map frame and the phone headings (length-weighted circular mean
    # over the valid segments, iterated on the inliers within 45 deg)
    d = np.array([wrap(s["dir_rv"] - s["bearing"]) for s in valid])
    wts = np.array([s["Lw"] for s in valid])
    off = float(math.atan2(np.sum(wts * np.sin(d)), np.sum(wts * np.cos(d))))
    for _ in range(5):
        m = np.abs(wrap(d - off)) < math.radians(45)
        off = float(math.atan2(np.sum(wts[m] * np.sin(d[m])), np.sum(wts[m] * np.cos(d[m]))))
    offset = -off  # added to measured headings (the [heading] offset convention)
    seg_err = wrap(d + offset)
    out["segments"] = {"all": len(allseg), "valid": len(valid),
                       "rule": f"waypoint leg >= {min_seg_m} m, >= 3 steps, gyro straightness >= {straight}"}
    out["rotation_offset_deg"] = offset * DEG
    out["segment_heading_error"] = summary(seg_err, DEG)
    out["segment_heading_error"]["share_beyond_45deg"] = float(np.mean(np.abs(seg_err) > math.radians(45)))
    # chord-noise check: var of segment error vs 1/Lw^2 (waypoint placement error sigma_wp)
    inl = np.abs(seg_err) < math.radians(45)
    Lw = np.array([s["Lw"] for s in valid])
    A = np.c_[np.ones(inl.sum()), 2.0 / Lw[inl] ** 2]
    coef, *_ = np.linalg.lstsq(A, seg_err[inl] ** 2, rcond=None)
    chord = math.sqrt(2 * max(coef[1], 0)) / float(np.median(Lw))
    out["segment_error_vs_length"] = {
        "intrinsic_sigma_deg": float(math.sqrt(max(coef[0], 0)) * DEG),
        "waypoint_sigma_m": float(math.sqrt(max(coef[1], 0))),
        "median_leg_m": float(np.median(Lw)),
        "chord_noise_at_median_leg_deg": chord * DEG,
        "model": "err^2 = sigma_h^2 + 2 sigma_wp^2 / Lw^2 (inliers within 45 deg)"}
    # per-step absolute heading error on very straight valid segments
    errs, dists, per_walk_series, dh_rv, dh_gy, walk_ids, leg_ids = [], [], [], [], [], [], []
    hg_series = []
    for wi, w in enumerate(walks):
        ser = []
        for s in w["segs"]:
            if not (s["Lw"] >= min_seg_m and s["n"] >= 3 and s["straight_gyro"] >= very_straight):
                continue
            k = np.where(w["seg_of_step"] == s["i"])[0]
            if len(k) < 3:
                continue
            e = wrap(w["h"][k] + offset - s["bearing"])
            errs.append(e)
            dists.append(w["cum"][k])
            walk_ids.append(np.full(len(k), wi))
            leg_ids.append(np.full(len(k), wi * 1000 + s["i"]))
            ser.append((w["cum"][k], e))
            dh_rv.append(w["dh_rv"][k[1:]])
            dh_gy.append(w["dh_gyro"][k[1:]])
            hg_series.append(w["hg"][k])
        per_walk_series.append(ser)
    E = np.concatenate(errs)
    DI = np.concatenate(dists)
    WI = np.concatenate(walk_ids)
    gu = fit_gauss_uniform(E)
    st = fit_student_t(E)
    out["step_heading_error"] = summary(E, DEG)
    out["step_heading_error"]["share_beyond_45deg"] = float(np.mean(np.abs(E) > math.radians(45)))
    out["step_heading_error"]["share_beyond_90deg"] = float(np.mean(np.abs(E) > math.radians(90)))
    out["step_heading_error"]["robust_sigma_less_chord_noise_deg"] = math.sqrt(max(
        robust_sigma(E) ** 2 - chord**2, 0)) * DEG
    out["step_heading_error"]["gauss_uniform"] = {"sigma_deg": gu["sigma"] * DEG,
                                                   "outlier_probability": gu["outlier_probability"]}
    out["step_heading_error"]["student_t"] = {"nu": st["nu"], "scale_deg": st["scale"] * DEG,
                                              "loglik": st["loglik"], "gauss_loglik": st["gauss_loglik"]}
    # correlation over distance walked (pairs within a walk; inliers within 45 deg)
    corr = _distance_correlation(E, DI, WI, np.abs(E) < math.radians(45))
    LI = np.concatenate(leg_ids)
    corr["same_leg"] = _distance_correlation(E, DI, WI, np.abs(E) < math.radians(45), legs=LI, same=True)
    corr["other_legs"] = _distance_correlation(E, DI, WI, np.abs(E) < math.radians(45), legs=LI, same=False)
    per_walk_mean = [float(np.mean(np.concatenate([e for _, e in ser]))) for ser in per_walk_series if ser]
    corr["per_walk_mean_error_sd_deg"] = float(np.std(per_walk_mean, ddof=1) * DEG)
    out["step_heading_correlation"] = corr
    # per-step heading-change noise on straight legs (rotation vector and gyroscope only)
    DR = np.concatenate(dh_rv)
    DG = np.concatenate(dh_gy)
    out["dheading_on_straight_legs"] = {"rotation_vector": summary(DR, DEG), "gyro_only": summary(DG, DEG)}
    acf_rv, _ = acf_by_lag(dh_rv, 6)
    acf_gy, _ = acf_by_lag(dh_gy, 6)
    out["dheading_acf"] = {"rotation_vector": acf_rv, "gyro_only": acf_gy}
    out["gyro_heading_variogram_on_straight_legs"] = _plain_variogram(hg_series, 10)
    out["leg_variogram"] = {"gyro_only": _leg_variogram(walks, "dir_gyro", 0.0, min_seg_m, straight),
                            "rotation_vector": _leg_variogram(walks, "dir_rv", offset, min_seg_m, straight)}
    # gyro-only: the accumulating part is below detection; bound it by the largest growth the
    # legs 25+ steps apart allow (a random walk of sigma^2 per step over the spanned steps)
    lvg = out["leg_variogram"]["gyro_only"]
    far = [(n, v) for n, v in zip(lvg["steps"], lvg["v_deg2"]) if n >= 25]
    out["gyro_walk_upper_deg_per_step"] = float(math.sqrt(max(
        (max(v for _, v in far) - min(v for _, v in far)) / (far[-1][0] - far[0][0]), 0.0)))
    # the bounded wander of the gyro heading within a leg: plateau of the within-leg variogram
    pv = out["gyro_heading_variogram_on_straight_legs"]["v_deg2"]
    plateau = float(np.mean(pv[6:10]))
    out["gyro_wander_sigma_deg"] = math.sqrt(plateau / 2)
    out["gyro_wander_bound_deg"] = math.sqrt(3 * plateau / 2)  # uniform on +-B has variance B^2/3
    # relative drift of the gyroscope-only heading: per walk, segment direction error vs time
    rates, ses, rates_step = [], [], []
    abs_rates = []
    for w in walks:
        vs = [s for s in w["segs"] if s["Lw"] >= min_seg_m and s["n"] >= 3 and s["straight_gyro"] >= straight]
        if len(vs) < 3:
            continue
        tm = np.array([(s["ta"] + s["tb"]) / 2 for s in vs])
        eg = np.unwrap(np.array([wrap(s["dir_gyro"] - s["bearing"]) for s in vs]))
        er = np.unwrap(np.array([wrap(s["dir_rv"] + offset - s["bearing"]) for s in vs]))
        slope, se, resid, _ = linear_fit(tm - tm[0], eg)
        slope_r, se_r, _, _ = linear_fit(tm - tm[0], er)
        period = float(np.median(np.diff(w["t"])))
        rates.append(slope)
        ses.append(se)
        rates_step.append(slope * period)
        abs_rates.append(slope_r)
        out["walks"].append({"walk": w["name"], "segments": len(vs), "duration_s": float(tm[-1] - tm[0]),
                             "gyro_drift_deg_per_s": slope * DEG, "gyro_drift_se_deg_per_s": se * DEG,
                             "rv_drift_deg_per_s": slope_r * DEG, "step_period_s": period,
                             "scale": float(sum(s["S"] for s in vs) / sum(s["Lw"] for s in vs)),
                             "leg_error_mean_deg": float(np.mean(wrap(er)) * DEG),
                             "leg_error_rms_deg": float(np.sqrt(np.mean(wrap(er) ** 2)) * DEG),
                             "gyro_residual_rms_deg": float(np.sqrt(np.mean(resid**2)) * DEG)})
    rates, ses = np.array(rates), np.array(ses)
    out["gyro_drift"] = {"walks": int(len(rates)), "rate_deg_per_s": summary(rates, DEG),
                         "rate_deg_per_step": summary(np.array(rates_step), DEG),
                         "spread_beyond_noise_deg_per_s": spread_beyond_noise(rates, ses) * DEG,
                         "robust_spread_beyond_noise_deg_per_s": float(math.sqrt(max(
                             0.0, robust_sigma(rates) ** 2 - np.median(ses) ** 2)) * DEG),
                         "median_se_deg_per_s": float(np.median(ses) * DEG),
                         "mean_se_deg_per_s": float(np.sqrt(np.mean(ses**2)) * DEG),
                         "rv_rate_deg_per_s": summary(np.array(abs_rates), DEG)}
    # stride scale: per segment and per walk
    ratios, periods, seg_len, seg_walk, seg_n = [], [], [], [], []
    walk_scale, walk_scale_all, walk_pace = [], [], []
    for wi, w in enumerate(walks):
        vs = [s for s in w["segs"] if s["Lw"] >= min_seg_m and s["n"] >= 3 and s["straight_gyro"] >= straight]
        if w["wp_length"] > 0:
            walk_scale_all.append(w["S_total"] / w["wp_length"])
        if not vs:
            continue
        walk_scale.append(sum(s["S"] for s in vs) / sum(s["Lw"] for s in vs))
        walk_pace.append(float(np.median(np.diff(w["t"]))))
        for s in vs:
            ratios.append(s["S"] / s["Lw"])
            periods.append(s["period"])
            seg_len.append(s["Lw"])
            seg_walk.append(walk_scale[-1])
            seg_n.append(s["n"])
    ratios, periods, seg_len, seg_walk, seg_n = map(np.array, (ratios, periods, seg_len, seg_walk, seg_n))
    ws = np.array(walk_scale)
    dev = ratios / seg_walk - 1
    mean_step = float(np.median(np.concatenate([w["L"] for w in walks])))
    out["length"] = {
        "walk_scale_straight_legs": {"n": int(len(ws)), "mean": float(ws.mean()), "sd": float(ws.std(ddof=1)),
                                     "p10": float(np.percentile(ws, 10)), "p90": float(np.percentile(ws, 90))},
        "walk_scale_polyline": summary(np.array(walk_scale_all)),
        "segment_ratio": summary(ratios),
        "segment_ratio_within_walk_sd": float(np.std(dev, ddof=1)),
        "segment_ratio_within_walk_robust_sd": robust_sigma(dev),
        "corr_walk_scale_pace": float(np.corrcoef(ws, walk_pace)[0, 1]),
        "segment_ratio_by_period_s": binned(periods, ratios, [0.0, 0.52, 0.56, 0.6, 0.65, 2.0], fn=np.mean),
        "corr_ratio_period": float(np.corrcoef(periods[np.isfinite(periods)], ratios[np.isfinite(periods)])[0, 1]),
        "median_step_m": mean_step,
        "length_sigma_upper_bound_m": float(robust_sigma(dev * np.sqrt(seg_n)) * mean_step),
        "bound_rule": "all of the within-walk leg-to-leg scale scatter (robust) taken as white "
                      "per-step noise: sigma_l <= rsd(dev * sqrt(n)) * step",
        "assumed_length_sigma_m": 0.1,
    }
    out["_arrays"] = {"E": E, "DI": DI, "WI": WI, "seg_err": seg_err, "Lw": Lw, "rates": rates,
                      "ratios": ratios, "periods": periods, "walk_scale": ws, "walks": walks, "offset": offset,
                      "per_walk_series": per_walk_series}
    return out


def _plain_variogram(series, max_lag):
    """Robust variogram (median of squared changes / 0.455) of headings along straight legs."""
    sq = {lag: [] for lag in range(1, max_lag + 1)}
    for s in series:
        s = np.asarray(s)
        for lag in range(1, min(max_lag, len(s) - 1) + 1):
            sq[lag] += list((s[lag:] - s[:-lag]) ** 2)
    lags = np.arange(1, max_lag + 1)
    v = np.array([np.median(sq[k]) / 0.4549 * DEG * DEG if sq[k] else np.nan for k in lags])
    ok = np.isfinite(v)
    slope, _, _, icpt = linear_fit(lags[ok][:8], v[ok][:8])
    return {"lag_steps": lags.tolist(), "v_deg2": v.tolist(), "pairs": [len(sq[k]) for k in lags],
            "white_sigma_deg": math.sqrt(max(icpt, 0) / 2), "walk_sigma_deg_per_step": math.sqrt(max(slope, 0))}


def _leg_variogram(walks, key, offset, min_seg_m, straight):
    """Change of a leg's direction error between two legs of one walk against the steps walked
    between their middles (robust: median of squares / 0.455, binned); fit V = A + B n."""
    dn, sq = [], []
    for w in walks:
        vs = [s for s in w["segs"] if s["Lw"] >= min_seg_m and s["n"] >= 3 and s["straight_gyro"] >= straight]
        if len(vs) < 2:
            continue
        err = [wrap(s[key] + offset - s["bearing"]) for s in vs]
        mid = [np.searchsorted(w["t"], 0.5 * (s["ta"] + s["tb"])) for s in vs]
        for i in range(len(vs)):
            for j in range(i + 1, len(vs)):
                dn.append(mid[j] - mid[i])
                sq.append(float(wrap(err[j] - err[i])) ** 2)
    dn, sq = np.array(dn, float), np.array(sq)
    edges = [0, 15, 25, 35, 50, 70, 100, 200]
    n_mid, v, cnt = [], [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (dn >= lo) & (dn < hi)
        if m.sum() >= 8:
            n_mid.append(float(np.median(dn[m])))
            v.append(float(np.median(sq[m]) / 0.4549))
            cnt.append(int(m.sum()))
    slope, se, _, icpt = linear_fit(np.array(n_mid), np.array(v))
    return {"steps": n_mid, "v_deg2": [x * DEG * DEG for x in v], "pairs": cnt,
            "leg_sigma_deg": math.sqrt(max(icpt, 0) / 2) * DEG,
            "walk_sigma_deg_per_step": math.sqrt(max(slope, 0)) * DEG,
            "slope_deg2_per_step": slope * DEG * DEG, "slope_se_deg2_per_step": se * DEG * DEG}


def _distance_correlation(E, DI, WI, inlier, edges=None, legs=None, same=None):
    """Correlation of the heading errors of two steps of one walk against the distance walked
    between them; with `legs`, only pairs on the same leg (same=True) or on different legs."""
    if edges is None:
        edges = np.array([0.3, 1.0, 2.0, 3.0, 4.5, 6.0, 8.0, 11.0, 15.0, 20.0, 30.0])
    e = E[inlier] - np.mean(E[inlier])
    d = DI[inlier]
    w = WI[inlier]
    lg = legs[inlier] if legs is not None else None
    var = np.mean(e * e)
    sums = np.zeros(len(edges) - 1)
    cnt = np.zeros(len(edges) - 1)
    for wi in np.unique(w):
        m = w == wi
        ee, dd = e[m], d[m]
        diff = np.abs(dd[:, None] - dd[None, :])
        prod = ee[:, None] * ee[None, :]
        iu = np.triu_indices(len(ee), 1)
        diff, prod = diff[iu], prod[iu]
        if lg is not None:
            ll = lg[m]
            sel = (ll[:, None] == ll[None, :])[iu]
            if not same:
                sel = ~sel
            diff, prod = diff[sel], prod[sel]
        b = np.digitize(diff, edges) - 1
        for k in range(len(edges) - 1):
            mk = b == k
            sums[k] += prod[mk].sum()
            cnt[k] += mk.sum()
    rho = sums / np.maximum(cnt, 1) / var
    mids = 0.5 * (edges[:-1] + edges[1:])
    # fit rho(d) = a exp(-d / L) by least squares over a grid of L (weighted by pair counts)
    best = None
    for Lc in np.arange(0.5, 60.01, 0.25):
        f = np.exp(-mids / Lc)
        wgt = np.sqrt(cnt)
        a = float(np.sum(wgt * f * rho) / np.sum(wgt * f * f))
        a = min(max(a, 0.0), 1.0)
        sse = float(np.sum(cnt * (rho - a * f) ** 2))
        if best is None or sse < best[0]:
            best = (sse, Lc, a)
    return {"distance_m": mids.tolist(), "rho": rho.tolist(), "pairs": cnt.astype(int).tolist(),
            "variance_deg2": float(var * DEG * DEG), "fit_length_m": float(best[1]),
            "fit_amplitude": float(best[2]),
            "model": "rho(d) = a exp(-d/L) for d > 0 (a < 1: the rest is white per step)"}


# ----------------------------------------------------------------------------------------
# parameter sets and the check by simulation


def parameter_sets(foot, phone):
    """The fitted parameter sets per mount, in the config field names (radians, metres)."""
    r = math.radians
    ml = foot["heading_model_ml"]
    vg = foot["variogram"]
    sc = foot["length"]["scale"]
    len_sigma = foot["length"]["residual_m"]["robust_sigma"]
    scale_sigma0 = math.sqrt(sc["sd"] ** 2 + (sc["mean"] - 1) ** 2)
    dheading_sigma = round(r(ml["sigma_s"]), 4)
    drift0 = round(r(ml["sigma_r0"]), 5)
    foot_params = {
        "convention": "stride k moves along H_k = H_(k-1) + dheading_k (the step model); "
                      "dheading = change of the direction of the stride's INS displacement",
        "footslam_motion": {
            "length_sigma": round(len_sigma, 3),
            "dheading_sigma": dheading_sigma,
            "drift_rate_sigma0": drift0,
            "drift_rate_walk_sigma": round(r(0.002), 6),
            "length_scale_sigma0": round(scale_sigma0, 3),
            "duck_walk_sigma": "keep 0.1 deg (not measured)",
        },
        "tracker": {
            "length_sigma": round(len_sigma, 3),
            "dheading_sigma": dheading_sigma,
            "scale_sigma": round(scale_sigma0, 3),
            "drift_sigma": drift0,
            "drift_walk_sigma": 0.0,
        },
        "simulator_noise": {
            "length_sigma": round(len_sigma, 3),
            "length_scale": round(sc["mean"], 3),
            "dheading_sigma": dheading_sigma,
            "drift_total_per_step": drift0,
            "drift_rate_walk_sigma": round(r(0.001), 6),
            "dz_sigma": round(foot["dz_error_m"]["robust_sigma"], 3),
            "_note": "drift_total = drift_total_per_step x strides (the simulator takes the walk's total)",
        },
        "white_direction_sigma_deg": {"ml": ml["sigma_w"],
                                      "variogram": vg["fit_lag2_8"]["white_sigma_deg"]},
    }
    ph = phone
    corr = ph["step_heading_correlation"]
    gu = ph["step_heading_error"]["gauss_uniform"]
    ws = ph["length"]["walk_scale_straight_legs"]
    period = float(np.median([w["step_period_s"] for w in ph["walks"]]))
    lv = ph["leg_variogram"]
    gyro_s_upper = ph["gyro_walk_upper_deg_per_step"]
    gyro_r0_upper = ph["gyro_drift"]["rate_deg_per_s"]["robust_sigma"] * period
    a = corr["fit_amplitude"]
    s_in = r(gu["sigma_deg"])
    eps = round(max(gu["outlier_probability"], 0.01), 3)
    phone_params = {
        "footslam_motion_rotation_vector_steps": {
            "dheading_sigma": round(r(lv["rotation_vector"]["walk_sigma_deg_per_step"]), 4),
            "drift_rate_sigma0": 0.0,
            "drift_rate_walk_sigma": 0.0,
            "length_sigma": round(ph["length"]["assumed_length_sigma_m"], 3),
            "length_scale_sigma0": round(math.sqrt(ws["sd"] ** 2 + (ws["mean"] - 1) ** 2), 3),
        },
        "footslam_motion_gyro_only_steps": {
            "dheading_sigma": round(r(gyro_s_upper), 4),
            "drift_rate_sigma0": round(r(gyro_r0_upper), 5),
            "drift_rate_walk_sigma": 0.0,
            "duck_walk_sigma": round(r(ph["gyro_heading_variogram_on_straight_legs"]["walk_sigma_deg_per_step"]), 4),
            "duck_max": round(r(ph["gyro_wander_bound_deg"]), 3),
        },
        "heading": {
            "sigma": round(s_in, 3),
            "outlier_probability": eps,
            "correlation_length": round(corr["fit_length_m"], 1),
            "offset": round(r(ph["rotation_offset_deg"]), 3),
        },
        "tracker": {
            "length_sigma": round(ph["length"]["assumed_length_sigma_m"], 3),
            "scale_sigma": round(math.sqrt(ws["sd"] ** 2 + (ws["mean"] - 1) ** 2), 3),
            "dheading_sigma": round(r(lv["rotation_vector"]["walk_sigma_deg_per_step"]), 4),
        },
        "simulator_noise": {
            "length_sigma": round(ph["length"]["assumed_length_sigma_m"], 3),
            "length_scale": round(ws["mean"], 3),
            "dheading_sigma": round(r(gyro_s_upper), 4),
            "drift_total_per_step": round(r(gyro_r0_upper), 5),
            "drift_rate_walk_sigma": 0.0,
            "dz_sigma": "not measured (no barometer in ILC site 1): keep 0.02",
        },
        "simulator_compass": {
            "noise_sigma": round(s_in * math.sqrt(max(1 - a, 0)), 3),
            "disturbance_sigma": round(s_in * math.sqrt(a), 3),
            "disturbance_length": round(corr["fit_length_m"], 1),
            "outlier_probability": eps,
        },
        "step_period_s": period,
    }
    return {"foot": foot_params, "phone": phone_params}


def sim_drift(n, total, walk_sigma, rng):
    """Port of step_sensor::drift_increments."""
    sign = 1.0 if rng.random() < 0.5 else -1.0
    walk = np.cumsum(walk_sigma * rng.standard_normal(n))
    return sign * total / n + walk - walk.mean()


def simulate_foot(foot, params, seeds=20):
    """The simulator's step noise (a port of step_sensor::measure_steps) on the real walks'
    stride indices; the same statistics measured on the result."""
    p = params["foot"]["simulator_noise"]
    A = foot["_arrays"]
    xs, vgs, rates = [], [], []
    rng = np.random.default_rng(1)
    for _ in range(seeds):
        series = []
        for idx, e in A["series"]:
            n = int(idx[-1]) + 1
            drift = sim_drift(n, p["drift_total_per_step"] * n, p["drift_rate_walk_sigma"], rng)
            ce = np.cumsum(p["dheading_sigma"] * rng.standard_normal(n) + drift)
            es = ce[idx] - ce[idx[0]]
            series.append((idx, es))
            xs.append(np.diff(es)[np.diff(idx) == 1])
            rates.append(huber_line(idx, es)[0])
        vgs.append(_variogram(series, 12)["v_deg2"])
    return {"heading_change": summary(np.concatenate(xs), DEG),
            "variogram_v_deg2": np.mean(np.array(vgs), axis=0).tolist(),
            "rate_sd_deg_per_stride": float(np.std(rates) * DEG)}


def simulate_compass(phone, params, seeds=20):
    """Port of compass::read_compass on the real steps of the straight legs."""
    c = params["phone"]["simulator_compass"]
    A = phone["_arrays"]
    rng = np.random.default_rng(2)
    Es, Ds, Ws = [], [], []
    for seed in range(seeds):
        for wi, ser in enumerate(A["per_walk_series"]):
            unit = rng.standard_normal()
            prev = None
            for cum, e in ser:
                for d in cum:
                    step = 0.7 if prev is None else d - prev
                    prev = d
                    rho = math.exp(-max(step, 0) / c["disturbance_length"])
                    unit = rho * unit + math.sqrt(1 - rho * rho) * rng.standard_normal()
                    if rng.random() < c["outlier_probability"]:
                        r = rng.uniform(-math.pi, math.pi)
                    else:
                        r = c["disturbance_sigma"] * unit + c["noise_sigma"] * rng.standard_normal()
                    Es.append(wrap(r))
                    Ds.append(d)
                    Ws.append(seed * 1000 + wi)
    E, D, W = np.array(Es), np.array(Ds), np.array(Ws)
    s = summary(E, DEG)
    s["share_beyond_45deg"] = float(np.mean(np.abs(E) > math.radians(45)))
    corr = _distance_correlation(E, D, W, np.abs(E) < math.radians(45))
    return {"step_heading_error": s, "correlation": corr}


# ----------------------------------------------------------------------------------------
# figures


def save(fig, path):
    """PNG at 80 dpi, reduced to a 256-colour palette (a third of the size, same look)."""
    import io

    from PIL import Image

    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, dpi=80, format="png")
    plt.close(fig)
    buf.seek(0)
    img = Image.open(buf).convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    img.save(path, optimize=True)


def _t_pdf(xx, nu, s):
    from math import lgamma
    return math.exp(lgamma((nu + 1) / 2) - lgamma(nu / 2)) / math.sqrt(nu * math.pi) / s * \
        (1 + (xx / s) ** 2 / nu) ** (-(nu + 1) / 2)


def figures(foot, phone, sim_foot, sim_comp, params, fig_dir):
    A = foot["_arrays"]
    col = {"hallway": "C0", "vicon": "C1"}
    # 1. foot heading
    fig, ax = plt.subplots(2, 3, figsize=(13, 7.5))
    for (idx, e), kind in zip(A["series"], A["kinds"]):
        ax[0, 0].plot(idx, e * DEG, color=col[kind], lw=0.8, alpha=0.8)
    ax[0, 0].plot([], [], color="C0", label="hallway")
    ax[0, 0].plot([], [], color="C1", label="Vicon")
    ax[0, 0].axhline(0, color="k", lw=0.5)
    ax[0, 0].set_ylim(-40, 40)
    ax[0, 0].set(xlabel="stride", ylabel="H_k - truth chord direction (deg; clipped at +-40)",
                 title="cumulative heading error per walk")
    ax[0, 0].legend(fontsize=8)
    X = A["X"] * DEG
    hc = foot["heading_change"]
    bins = np.linspace(-15, 15, 61)
    for m, lab, c in ((A["hall"], "hallway", "C0"), (~A["hall"], "Vicon", "C1")):
        ax[0, 1].hist(np.clip(X[m], -14.9, 14.9), bins=bins, histtype="step", color=c,
                      weights=np.full(int(m.sum()), 1.0 / (len(X) * (bins[1] - bins[0]))),
                      label=f"{lab} ({int(m.sum())})")
    xx = np.linspace(-15, 15, 400)
    t = hc["student_t"]
    ax[0, 1].plot(xx, _t_pdf(xx, t["nu"], t["scale_deg"]), "k--", lw=0.8,
                  label=f"t, all: nu {t['nu']:g}, scale {t['scale_deg']:.1f} deg")
    ax[0, 1].set_yscale("log")
    ax[0, 1].set_ylim(1e-4, 0.5)
    ax[0, 1].set(xlabel="dheading - truth turn (deg; beyond +-15 in the end bins)", ylabel="density",
                 title="heading-change error per stride")
    ax[0, 1].legend(fontsize=7, loc="upper left")
    bt = hc["by_turn"]
    ax[0, 2].plot([0.5 * (b["lo"] + b["hi"]) for b in bt], [b["value"] for b in bt], "o-", color="C3")
    for b in bt:
        ax[0, 2].annotate(str(b["n"]), (0.5 * (b["lo"] + b["hi"]), b["value"]), fontsize=7,
                          textcoords="offset points", xytext=(3, 4))
    ax[0, 2].set_ylim(0, None)
    ax[0, 2].set(xlabel="|truth turn| in the stride (deg; bins 0-10-30-60-90-180)",
                 ylabel="robust sigma (deg)", title="heading-change error vs turn (labels: strides)")
    vg = foot["variogram"]
    ax[1, 0].plot(vg["lag"], vg["v_deg2"], "o-", color="C3", label="measured (robust)")
    ax[1, 0].plot(vg["lag"], sim_foot["variogram_v_deg2"], "k--", label="simulator preset")
    ax[1, 0].set_ylim(0, None)
    ax[1, 0].set(xlabel="lag (strides)", ylabel="robust mean sq. change (deg^2)",
                 title="variogram of the detrended cumulative error")
    ax[1, 0].legend(fontsize=8)
    ml = foot["heading_model_ml"]
    ps = np.array(ml["profile_sigma_s"])
    ax[1, 1].plot(ps[:, 0], ps[:, 1] - ml["loglik"], "o-", color="C3")
    ax[1, 1].axhline(-1.92, color="k", lw=0.5, ls=":")
    lo, hi = ml["sigma_s_interval95_deg"]
    ax[1, 1].axvspan(lo, hi, color="C3", alpha=0.15)
    ax[1, 1].set_ylim(-60, 5)
    ax[1, 1].set_xlim(0, 2.2)
    ax[1, 1].set(xlabel="accumulating noise sigma_s (deg/stride)", ylabel="profile log-likelihood",
                 title=f"state-space fit: sigma_s {ml['sigma_s']:.2f} (95 %: {lo:.2f}-{hi:.2f})")
    ws = foot["walks"]
    y = np.arange(len(ws))
    ax[1, 2].errorbar([w["drift_deg_per_s"] for w in ws], y,
                      xerr=[w["drift_se_deg_per_s"] for w in ws], fmt="none", ecolor="0.6")
    ax[1, 2].scatter([w["drift_deg_per_s"] for w in ws], y,
                     c=[col[w["walk"].split("/")[0]] for w in ws], s=18, zorder=3)
    ax[1, 2].axvline(0, color="k", lw=0.5)
    ax[1, 2].set_yticks(y)
    ax[1, 2].set_yticklabels([w["walk"].split("/")[1][-8:] for w in ws], fontsize=6)
    ax[1, 2].set(xlabel="heading drift rate (deg/s, Huber fit +- 1 se)", title="drift per walk")
    save(fig, os.path.join(fig_dir, "error-models-foot-heading.png"))

    # 2. foot length
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    sc = A["scales"]
    ax[0].scatter(A["paces"], sc, c=[col[k] for k in A["kinds"]], s=20)
    ax[0].axhline(1, color="k", lw=0.5)
    ax[0].set(xlabel="median stride duration of the walk (s)", ylabel="sum measured / sum truth",
              title="per-walk stride scale vs pace (blue hallway)")
    R = A["R"]
    ax[1].hist(np.clip(R, -0.3, 0.3), bins=np.linspace(-0.3, 0.3, 61), density=True, histtype="step")
    t = foot["length"]["student_t"]
    xx = np.linspace(-0.3, 0.3, 400)
    ax[1].plot(xx, _t_pdf(xx, t["nu"], t["scale_m"]), "r--", lw=0.8,
               label=f"t: nu {t['nu']:g}, scale {t['scale_m'] * 100:.1f} cm")
    ax[1].set_yscale("log")
    ax[1].set_ylim(0.01, 50)
    ax[1].legend(fontsize=8)
    ax[1].set(xlabel="stride length residual after the walk's scale (m)", ylabel="density",
              title="length residual (clipped at +-0.3 m)")
    sca = ax[2].scatter(A["D"], A["RR"] * 100, c=np.minimum(A["LT"] * DEG, 90), s=6, cmap="viridis")
    ax[2].set_ylim(-20, 15)
    ax[2].set_xlim(0.6, 2.0)
    ax[2].axhline(0, color="k", lw=0.5)
    ax[2].set(xlabel="stride duration (s)", ylabel="residual (% of stride)",
              title="residual vs pace (colour: |turn| deg)")
    fig.colorbar(sca, ax=ax[2])
    save(fig, os.path.join(fig_dir, "error-models-foot-length.png"))

    # 3. phone heading
    P = phone["_arrays"]
    fig, ax = plt.subplots(2, 2, figsize=(10, 7.5))
    E = P["E"] * DEG
    ax[0, 0].hist(E, bins=np.linspace(-180, 180, 73), density=True, histtype="step", label="measured")
    gu = phone["step_heading_error"]["gauss_uniform"]
    st = phone["step_heading_error"]["student_t"]
    xx = np.linspace(-180, 180, 721)
    s, eps = gu["sigma_deg"], gu["outlier_probability"]
    ax[0, 0].plot(xx, (1 - eps) * np.exp(-0.5 * (xx / s) ** 2) / (s * math.sqrt(2 * math.pi)) + eps / 360,
                  "r--", lw=0.8, label=f"normal+uniform: sigma {s:.1f}, eps {eps:.3f}")
    ax[0, 0].plot(xx, _t_pdf(xx, st["nu"], st["scale_deg"]), "g:", lw=0.8,
                  label=f"t: nu {st['nu']:g}, scale {st['scale_deg']:.1f}")
    ax[0, 0].set_yscale("log")
    ax[0, 0].set_ylim(1e-5, 0.1)
    ax[0, 0].set(xlabel="step heading - leg bearing (deg)", ylabel="density",
                 title="phone absolute heading error per step (straight legs)")
    ax[0, 0].legend(fontsize=7)
    c = phone["step_heading_correlation"]
    cs = sim_comp["correlation"]
    ax[0, 1].plot(c["distance_m"], c["rho"], "o-", label="all pairs")
    ax[0, 1].plot(c["same_leg"]["distance_m"], np.where(np.array(c["same_leg"]["pairs"]) > 50,
                                                       c["same_leg"]["rho"], np.nan), "s-", label="same leg")
    ax[0, 1].plot(c["other_legs"]["distance_m"], np.where(np.array(c["other_legs"]["pairs"]) > 50,
                                                         c["other_legs"]["rho"], np.nan), "^-",
                  label="different legs")
    dd = np.linspace(0.1, 25, 200)
    ax[0, 1].plot(dd, c["fit_amplitude"] * np.exp(-dd / c["fit_length_m"]), "r--",
                  label=f"fit a={c['fit_amplitude']:.2f}, L={c['fit_length_m']:.1f} m")
    ax[0, 1].plot(cs["distance_m"], cs["rho"], "k:", label="simulator preset")
    ax[0, 1].axhline(0, color="k", lw=0.5)
    ax[0, 1].set(xlabel="distance walked between the two steps (m)", ylabel="correlation",
                 title="correlation of the heading error")
    ax[0, 1].legend(fontsize=7)
    ax[1, 0].scatter(P["Lw"], P["seg_err"] * DEG, s=8)
    ax[1, 0].axhline(0, color="k", lw=0.5)
    ax[1, 0].set_ylim(-60, 60)
    ax[1, 0].set(xlabel="waypoint leg length (m)", ylabel="PDR direction - leg bearing (deg)",
                 title=f"per-leg heading error (rotation vector; offset {phone['rotation_offset_deg']:+.2f} deg)")
    for key, m, lab in (("gyro_only", "o-", "gyroscope only"), ("rotation_vector", "s-", "rotation vector")):
        lv = phone["leg_variogram"][key]
        ax[1, 1].plot(lv["steps"], lv["v_deg2"], m, label=lab)
    ax[1, 1].set(xlabel="steps between the legs' middles", ylabel="robust mean sq. change (deg^2)",
                 title="change of the leg direction error between legs")
    ax[1, 1].legend(fontsize=8)
    save(fig, os.path.join(fig_dir, "error-models-phone-heading.png"))

    # 4. phone length
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.6))
    ax[0].hist(P["walk_scale"], bins=np.linspace(0.8, 1.3, 26))
    ax[0].set(xlabel="sum of step lengths / sum of leg lengths (straight legs)", ylabel="walks",
              title="phone per-walk stride scale (K = 0.47)")
    ax[1].scatter(P["periods"], P["ratios"], s=8)
    for b in phone["length"]["segment_ratio_by_period_s"]:
        if np.isfinite(b["value"]):
            ax[1].plot([max(b["lo"], 0.45), min(b["hi"], 0.65)], [b["value"]] * 2, "r-")
    ax[1].set(xlabel="median step period in the leg (s)", ylabel="leg ratio",
              title="per-leg stride scale vs pace (red: bin means)")
    ax[1].set_ylim(0.6, 1.6)
    save(fig, os.path.join(fig_dir, "error-models-phone-length.png"))

    # 5. autocorrelations
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.6))
    ac = foot["autocorrelation"]
    lags = np.arange(1, 9)
    ax[0].plot(lags, ac["heading_change"], "o-", label="heading change")
    ax[0].plot(lags, ac["length_residual"], "^-", label="length residual")
    ax[0].axhline(0, color="k", lw=0.5)
    ax[0].axhline(-0.5, color="k", lw=0.5, ls=":")
    ax[0].set(xlabel=f"lag (strides of {ac['mean_stride_m']:.2f} m)", ylabel="autocorrelation",
              title="foot: per-stride errors")
    ax[0].legend(fontsize=8)
    pa = phone["dheading_acf"]
    ax[1].plot(np.arange(1, 7), pa["rotation_vector"], "o-", label="rotation vector")
    ax[1].plot(np.arange(1, 7), pa["gyro_only"], "s-", label="gyroscope only")
    ax[1].axhline(0, color="k", lw=0.5)
    ax[1].axhline(-0.5, color="k", lw=0.5, ls=":")
    ax[1].set(xlabel="lag (steps of about 0.7 m)", ylabel="autocorrelation",
              title="phone: heading change per step, straight legs")
    ax[1].legend(fontsize=8)
    gv = phone["gyro_heading_variogram_on_straight_legs"]
    ax[2].plot(gv["lag_steps"], gv["v_deg2"], "o-")
    ax[2].set(xlabel="lag (steps)", ylabel="robust mean sq. change (deg^2)",
              title="phone: gyro heading along a straight leg")
    save(fig, os.path.join(fig_dir, "error-models-autocorr.png"))


# ----------------------------------------------------------------------------------------


def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items() if not k.startswith("_arr")}
    if isinstance(o, list):
        return [strip(v) for v in o]
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    return o


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--foot-data", default="/work/shared/data/foot-imu")
    ap.add_argument("--ilc-data", default="/work/shared/data/ilc-site1-F1")
    ap.add_argument("--footslam", default=os.path.join(root, "target", "release", "footslam"))
    ap.add_argument("--out", default=os.path.join(root, "outputs", "error-models"))
    ap.add_argument("--fig-dir", default=os.path.join(root, "docs"))
    ap.add_argument("--reuse", action="store_true", help="reuse step traces already in OUT")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    os.makedirs(args.fig_dir, exist_ok=True)
    for sub in ("foot", "phone"):
        os.makedirs(os.path.join(args.out, sub), exist_ok=True)

    fw = analyse_foot(args.foot_data, args.footslam, args.out, args.reuse)
    foot = foot_statistics(fw)
    pw = analyse_phone(args.ilc_data, args.footslam, args.out, args.reuse)
    phone = phone_statistics(pw)
    params = parameter_sets(foot, phone)
    sim_foot = simulate_foot(foot, params)
    sim_comp = simulate_compass(phone, params)
    figures(foot, phone, sim_foot, sim_comp, params, args.fig_dir)
    result = {"foot": strip(foot), "phone": strip(phone), "parameters": params,
              "simulated": {"foot": sim_foot, "compass": strip(sim_comp)}}
    with open(os.path.join(args.out, "error_models.json"), "w") as f:
        json.dump(result, f, indent=1)
    print_table(foot, phone, params, sim_foot, sim_comp)
    print(f"\nwrote {os.path.join(args.out, 'error_models.json')} and {args.fig_dir}/error-models-*.png")


def print_table(foot, phone, params, sim_foot, sim_comp):
    m = foot["matching"]
    print(f"FOOT: {m['steps']} step events, {m['truth_strides']} truth strides, {m['matched_steps']} steps "
          f"matched by time (+-{MATCH_TOLERANCE_S} s; {m['extra_steps']} second steps on one stance joined "
          f"to the next), {m['single_units']} one-to-one, {m['split_steps']} split parts merged, "
          f"{m['walking_pairs']} walking stride pairs")
    print(f"{'walk':30s} {'str':>4s} {'s':>5s} {'scale':>6s} {'drift deg/str':>13s} {'deg/s':>6s} "
          f"{'final':>6s} {'dh rs':>5s}")
    for w in foot["walks"]:
        print(f"{w['walk']:30s} {w['truth_strides']:4d} {w['duration_s']:5.0f} {w['scale']:6.3f} "
              f"{w['drift_deg_per_stride']:+6.2f} +- {w['drift_se_deg_per_stride']:4.2f} "
              f"{w['drift_deg_per_s']:+6.2f} {w['final_cum_error_deg']:+6.1f} "
              f"{w['heading_change_robust_sigma_deg']:5.1f}")
    hc = foot["heading_change"]
    t, g = hc["student_t"], hc["gauss_uniform"]
    for k in ("all", "hallway", "vicon", "straight_lt_10deg"):
        s = hc[k]
        print(f"heading change ({k}): n {s['n']} sigma {s['sigma']:.1f} robust {s['robust_sigma']:.2f} "
              f"p95 {s['p95_abs']:.1f} p99 {s['p99_abs']:.1f} max {s['max_abs']:.1f} deg, kurtosis "
              f"{s['excess_kurtosis']:.1f}, beyond 3 robust sigma {s['share_beyond_3_robust_sigma']:.3f}")
    print(f"  t nu {t['nu']:g} scale {t['scale_deg']:.2f} deg (loglik {t['loglik'] - t['gauss_loglik']:+.0f} "
          f"over Gaussian); normal+uniform sigma {g['sigma_deg']:.2f} eps {g['outlier_probability']:.3f}")
    print("  robust sigma by |turn|:", [(b['lo'], b['hi'], b['n'], round(b['value'], 2)) for b in hc["by_turn"]])
    print("  robust sigma by stride duration:", [(b['lo'], b['hi'], b['n'], round(b['value'], 2))
                                                 for b in hc["by_duration_s"]])
    la = hc["lookahead_check"]
    print(f"  look-ahead check: error = {la['gain']:.2f} x (next turn - this turn) (about 1/2 for a leading heading); "
          f"robust sigma {la['robust_sigma_before_deg']:.2f} -> {la['robust_sigma_after_deg']:.2f} deg")
    for b in hc["beyond_10deg"]:
        print(f"  beyond 10 deg: {b['walk']} stride {b['stride']}: {b['error_deg']:+.1f} deg, turn {b['turn_deg']:+.0f}, "
              f"length {b['length_m']:.2f} m / truth {b['truth_length_m']:.2f} m, cumulative {b['cum_error_deg']:+.1f} deg")
    tn = hc["truth_noise"]
    print(f"  truth noise: hallway footprints <= {tn['hallway_footprint_sigma_upper_m'] * 100:.1f} cm -> <= "
          f"{tn['heading_change_noise_upper_deg']:.1f} deg of heading change; hallway excess over Vicon "
          f"{tn['hallway_excess_over_vicon_deg']:.2f} deg")
    ml = foot["heading_model_ml"]
    vg = foot["variogram"]["fit_lag2_8"]
    dr = foot["drift"]
    print(f"ML: sigma_s {ml['sigma_s']:.2f} deg/stride (95 % {ml['sigma_s_interval95_deg'][0]:.2f}-"
          f"{ml['sigma_s_interval95_deg'][1]:.2f}), sigma_w {ml['sigma_w']:.2f} deg, sigma_r0 "
          f"{ml['sigma_r0']:.3f} deg/stride, sigma_q {ml['sigma_q']:.4f} (<= {ml['sigma_q_upper95_deg']:.3f}) "
          f"deg/stride^2 [{ml['points_dropped_as_outliers']} of {ml['points']} points dropped as outliers]")
    for k, f in list(ml["by_outlier_cut"].items()) + [("hallway", ml["hallway"]), ("vicon", ml["vicon"])]:
        print(f"  {k:>7s}: sigma_s {f['sigma_s']:.2f} sigma_w {f['sigma_w']:.2f} sigma_r0 {f['sigma_r0']:.3f} "
              f"[{f['points_dropped_as_outliers']} dropped]")
    print(f"variogram (robust) {np.round(foot['variogram']['v_deg2'], 1).tolist()} deg^2 at lags 1..12: "
          f"walk {vg['walk_sigma_deg_per_stride']:.2f} deg/stride, white {vg['white_sigma_deg']:.2f} deg")
    print(f"per-walk drift rate: sd {dr['rate_deg_per_stride']['sigma']:.2f} robust "
          f"{dr['rate_deg_per_stride']['robust_sigma']:.2f} deg/stride (sd {dr['rate_deg_per_s']['sigma']:.2f} "
          f"robust {dr['rate_deg_per_s']['robust_sigma']:.2f} deg/s); spread beyond noise "
          f"{dr['spread_beyond_noise_deg_per_stride']:.2f} deg/stride {dr['spread_beyond_noise_deg_per_s']:.2f} deg/s "
          f"(hallway {dr['hallway_spread_beyond_noise_deg_per_stride']:.2f} deg/stride "
          f"{dr['hallway_spread_beyond_noise_deg_per_s']:.2f} deg/s, Vicon "
          f"{dr['vicon_spread_beyond_noise_deg_per_stride']:.2f} deg/stride "
          f"{dr['vicon_spread_beyond_noise_deg_per_s']:.2f} deg/s)")
    for k, ts in foot["turn_scale_factor"].items():
        print(f"turn scale factor ({k}): {ts['scale_factor'] * 100:+.2f} +- {ts['se'] * 100:.2f} % of the truth turn")
    ln = foot["length"]
    r = ln["residual_m"]
    print(f"length: per-walk scale mean {ln['scale']['mean']:.3f} sd {ln['scale']['sd']:.3f} "
          f"[{ln['scale']['min']:.3f}, {ln['scale']['max']:.3f}], corr with stride duration "
          f"{ln['scale']['corr_with_median_stride_s']:+.2f}; residual (n {r['n']}) sigma {r['sigma']:.3f} robust "
          f"{r['robust_sigma']:.3f} p95 {r['p95_abs']:.3f} p99 {r['p99_abs']:.3f} max {r['max_abs']:.2f} m, "
          f"kurtosis {r['excess_kurtosis']:.0f}; t nu {ln['student_t']['nu']:g} scale {ln['student_t']['scale_m']:.3f} m")
    print(f"  hallway / Vicon robust {ln['residual_m_hallway']['robust_sigma']:.4f} / "
          f"{ln['residual_m_vicon']['robust_sigma']:.4f} m, p99 {ln['residual_m_hallway']['p99_abs']:.3f} / "
          f"{ln['residual_m_vicon']['p99_abs']:.3f} m; relative robust {ln['relative_residual']['robust_sigma'] * 100:.1f} % "
          f"p95 {ln['relative_residual']['p95_abs'] * 100:.1f} %")
    print("  robust sigma by stride duration:", [(b['lo'], b['hi'], b['n'], round(b['value'], 3)) for b in ln["by_duration_s"]])
    print("  median relative residual by duration:", [(b['lo'], b['hi'], round(b['value'] * 100, 2)) for b in ln["mean_relative_by_duration_s"]])
    print("  robust sigma by |turn|:", [(b['lo'], b['hi'], b['n'], round(b['value'], 3)) for b in ln["by_turn_deg"]])
    ac = foot["autocorrelation"]
    print("ACF lag 1..4: heading change", np.round(ac["heading_change"][:4], 2).tolist(),
          "length", np.round(ac["length_residual"][:4], 2).tolist())
    dz = foot["dz_error_m"]
    print(f"dz error (n {dz['n']}): sigma {dz['sigma']:.3f} robust {dz['robust_sigma']:.3f} p99 {dz['p99_abs']:.3f} m")
    sh = sim_foot["heading_change"]
    print(f"simulated (preset): heading change robust {sh['robust_sigma']:.2f} p95 {sh['p95_abs']:.1f} deg; "
          f"variogram lag 1 / 12 {sim_foot['variogram_v_deg2'][0]:.1f} / {sim_foot['variogram_v_deg2'][11]:.1f} deg^2; "
          f"rate sd {sim_foot['rate_sd_deg_per_stride']:.3f} deg/stride")
    print()
    print(f"PHONE: legs {phone['segments']}; rotation offset {phone['rotation_offset_deg']:+.2f} deg")
    s = phone["step_heading_error"]
    print(f"step heading error: n {s['n']} sigma {s['sigma']:.1f} robust {s['robust_sigma']:.1f} p95 {s['p95_abs']:.1f} "
          f"p99 {s['p99_abs']:.1f} deg; beyond 45 deg {s['share_beyond_45deg']:.3f}, beyond 90 {s['share_beyond_90deg']:.4f}; "
          f"normal+uniform sigma {s['gauss_uniform']['sigma_deg']:.1f} eps {s['gauss_uniform']['outlier_probability']:.3f}; "
          f"t nu {s['student_t']['nu']:g} scale {s['student_t']['scale_deg']:.1f}")
    print(f"  robust sigma less the leg-chord noise ({phone['segment_error_vs_length']['chord_noise_at_median_leg_deg']:.1f} deg): "
          f"{s['robust_sigma_less_chord_noise_deg']:.1f} deg")
    c = phone["step_heading_correlation"]
    print(f"correlation: fit a {c['fit_amplitude']:.2f} L {c['fit_length_m']:.1f} m; same leg L "
          f"{c['same_leg']['fit_length_m']:.1f} m; other legs rho {np.round(c['other_legs']['rho'], 2).tolist()}; "
          f"per-walk mean error sd {c['per_walk_mean_error_sd_deg']:.1f} deg")
    sg = phone["segment_heading_error"]
    print(f"per-leg heading error: sigma {sg['sigma']:.1f} robust {sg['robust_sigma']:.1f} deg; vs length: "
          f"intrinsic {phone['segment_error_vs_length']['intrinsic_sigma_deg']:.1f} deg, waypoint "
          f"{phone['segment_error_vs_length']['waypoint_sigma_m']:.2f} m")
    for k in ("rotation_vector", "gyro_only"):
        d = phone["dheading_on_straight_legs"][k]
        lv = phone["leg_variogram"][k]
        print(f"{k}: dheading on straight legs robust {d['robust_sigma']:.1f} p99 {d['p99_abs']:.1f} deg; "
              f"leg variogram {np.round(lv['v_deg2']).tolist()} at steps {lv['steps']}: walk "
              f"{lv['walk_sigma_deg_per_step']:.2f} deg/step")
    print(f"gyro: accumulating <= {phone['gyro_walk_upper_deg_per_step']:.2f} deg/step; bounded wander sigma "
          f"{phone['gyro_wander_sigma_deg']:.1f} deg (uniform bound {phone['gyro_wander_bound_deg']:.1f} deg)")
    g = phone["gyro_drift"]
    print(f"gyro drift per walk ({g['walks']} walks): median |rate| {g['rate_deg_per_s']['p50_abs']:.2f} deg/s, "
          f"robust sd {g['rate_deg_per_s']['robust_sigma']:.2f} deg/s (median se {g['median_se_deg_per_s']:.2f})")
    ln = phone["length"]
    print(f"length: per-walk scale (straight legs) {ln['walk_scale_straight_legs']}; polyline ratio mean "
          f"{ln['walk_scale_polyline']['mean']:.3f}; leg ratio by period "
          f"{[(b['lo'], b['hi'], b['n'], round(b['value'], 3)) for b in ln['segment_ratio_by_period_s']]}; "
          f"within-walk robust sd {ln['segment_ratio_within_walk_robust_sd']:.3f}; sigma_l <= "
          f"{ln['length_sigma_upper_bound_m']:.2f} m")
    cs = sim_comp["step_heading_error"]
    print(f"compass simulated (preset): sigma {cs['sigma']:.1f} robust {cs['robust_sigma']:.1f} p95 {cs['p95_abs']:.1f} "
          f"p99 {cs['p99_abs']:.1f} beyond 45 {cs['share_beyond_45deg']:.3f}; L {sim_comp['correlation']['fit_length_m']:.1f} "
          f"a {sim_comp['correlation']['fit_amplitude']:.2f}")
    print()
    print(json.dumps(params, indent=1))


if __name__ == "__main__":
    sys.exit(main())
