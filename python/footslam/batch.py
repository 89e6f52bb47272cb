"""Thousands of walks on a cluster: footslam's batch runner on Dask distributed.

A manifest lists buildings × walks. Per building the runner does what ``footslam learn
--walks`` does for one batch — raw IMU to steps, each walk learned alone, FeetSLAM passes
in which each walk is learned again against the merged map of the other walks' previous
pass, the merged map, its walkable plan and the radio map of the walks' WiFi — with every
walk of every building a task, so buildings and walks fan out over the cluster, and the
merges are reductions of edge counts (sums). Seeds are ``seed + k`` for the
``k``-th walk of a building, as in ``footslam learn``, so the maps do not depend on how the
tasks were scheduled: they are those of the buildings learned one by one.

Dask (not Ray) because its futures graph is what this is — tasks that pass results to
tasks, reductions over lists of futures — with no actor or object-store model to learn, the
same code on a ``LocalCluster`` and a real scheduler (``Client("tcp://host:8786")``), and
the PyData stack (pandas, geopandas) its users already run. The Rust code releases the GIL,
so worker threads run filters in parallel, each filter on one thread by default.

The manifest is a CSV, paths relative to it::

    building,steps,imu,mount,wifi,gps,start
    mall-1,walks/a/steps.csv,,,walks/a/wifi.csv,,"12.5,3,0"
    mall-1,,walks/b/imu.csv,phone,walks/b/wifi.csv,,"40,8"

``building`` and one of ``steps`` (a step trace) or ``imu`` with ``mount`` (``phone`` or
``foot``) are required; ``wifi``, ``gps`` and ``start`` (``X,Y[,HEADING[,LEVEL]]``, quoted)
are optional. Walks that each have a ``start`` share their building's frame and are
iterated (FeetSLAM); walks without are learned alone.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import footslam

@dataclass(frozen=True)
class Walk:
    """One walk of the manifest."""

    building: str
    #: The walk's 0-based number in its building (manifest order): its seed is seed + index.
    index: int
    steps: str | None
    imu: str | None
    mount: str | None
    wifi: str | None
    gps: str | None
    start: tuple[float, ...] | None


def read_manifest(path: str | Path) -> dict[str, list[Walk]]:
    """The manifest's walks per building, buildings and walks in manifest order.

    Raises:
        FileNotFoundError: the manifest or a file it names does not exist.
        ValueError: a row without a building, without steps or IMU, or with a bad start
            (the message names the manifest's line).
    """
    path = Path(path)
    folder = path.parent
    buildings: dict[str, list[Walk]] = {}
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        if reader.fieldnames is None or "building" not in reader.fieldnames:
            raise ValueError(f"{path}: the header must name `building` (and `steps` or `imu`)")
        for line, row in enumerate(reader, start=2):
            where = f"{path}:{line}"

            def file(column: str) -> str | None:
                value = (row.get(column) or "").strip()
                if not value:
                    return None
                p = folder / value
                if not p.is_file():
                    raise FileNotFoundError(f"{where}: {column} `{p}` does not exist")
                return str(p)

            building = (row.get("building") or "").strip()
            if not building:
                raise ValueError(f"{where}: no building")
            steps, imu = file("steps"), file("imu")
            mount = (row.get("mount") or "").strip() or None
            if (steps is None) == (imu is None):
                raise ValueError(f"{where}: give one of steps or imu")
            if imu is not None and mount not in ("phone", "foot"):
                raise ValueError(f"{where}: imu needs mount `phone` or `foot`, got `{mount}`")
            start = parse_start((row.get("start") or "").strip(), where)
            walks = buildings.setdefault(building, [])
            walks.append(
                Walk(building, len(walks), steps, imu, mount, file("wifi"), file("gps"), start)
            )
    if not buildings:
        raise ValueError(f"{path}: no walks")
    return buildings


def parse_start(text: str, where: str) -> tuple[float, ...] | None:
    """``X,Y[,HEADING[,LEVEL]]`` (empty HEADING: unknown) as footslam's ``start`` takes it."""
    if not text:
        return None
    parts = [p.strip() for p in text.split(",")]
    if not 2 <= len(parts) <= 4:
        raise ValueError(f"{where}: start `{text}`: expected X,Y[,HEADING[,LEVEL]]")
    try:
        values = [float(p) if p else float("nan") for p in parts]
    except ValueError:
        raise ValueError(f"{where}: start `{text}` is not numbers") from None
    return tuple(values)


def _start_arg(start: tuple[float, ...] | None) -> Any:
    """The ``start`` argument of footslam's functions: a string as the manifest gives it."""
    if start is None:
        return None
    return ",".join("" if v != v else repr(v) for v in start)


# Tasks: plain functions of plain data, so any worker can run them.


def steps_task(walk: Walk) -> Any:
    """The walk's steps: its trace file, or its IMU recording turned into steps."""
    if walk.steps is not None:
        return walk.steps
    return footslam.steps(walk.imu, walk.mount)["steps"]


def learn_task(steps: Any, walk: Walk, previous: list[dict] | None, learn_args: dict) -> dict:
    """One walk of a pass: alone (``previous`` None) or against the merged map of the other
    walks' maps of the previous pass (``previous``: every walk's map, in order)."""
    others = None
    if previous is not None:
        others = footslam.others_map(previous, walk.index)
    return footslam.learn_one(
        steps,
        walk.index,
        others=others,
        start=_start_arg(walk.start),
        gps=walk.gps,
        wifi=walk.wifi,
        **learn_args,
    )


def map_of(result: dict) -> str:
    """A walk's map, the only part of its result the next pass and the merge need, as
    GeoJSON text: written once here, it is read as it is by every task of the next pass
    (each reads the other walks' maps: a dict would be written to JSON again in each, a
    cost that grows with the square of the building's walks)."""
    return json.dumps(result["map"], allow_nan=False)


def merge_task(maps: list[dict]) -> dict:
    """The reduction: the maps' edge counts summed."""
    return footslam.merge(maps)


def finish_task(
    walks: list[Walk], steps: list[Any], results: list[dict], merged: dict, cell: float | None
) -> dict:
    """A building's plan and radio map from its merged map and walks."""
    out: dict[str, Any] = {"merged": merged, "plan": footslam.plan(merged)["plan"]}
    with_wifi = [i for i, w in enumerate(walks) if w.wifi is not None]
    if with_wifi:
        radio = footslam.radio_map(
            merged,
            [results[i]["track"] for i in with_wifi],
            [walks[i].wifi for i in with_wifi],
            cell=cell,
        )
        out["radio_map"] = radio["radio_map"]
        out["radio_plan"] = radio["plan"]
    return out


def run_batch(
    manifest: str | Path,
    client: Any,
    *,
    config: dict | str | None = None,
    seed: int | None = None,
    particles: int | None = None,
    origin: tuple[float, float] | None = None,
    cell: float | None = None,
    threads: int | None = 1,
) -> dict[str, dict]:
    """Runs the manifest's buildings on a Dask ``client`` and waits for them.

    Args:
        manifest: the buildings × walks CSV (see the module's documentation).
        client: a ``dask.distributed.Client`` (``Client(LocalCluster())`` on one machine,
            ``Client("tcp://scheduler:8786")`` on a cluster).
        config, seed, particles: FootSLAM's configuration and overrides, as ``learn``'s.
        origin: the WGS84 ``(lat, lon)`` of every building's local frame (default 0, 0).
        cell: radio-map cell granularity, metres (default 3).
        threads: threads each walk's filter runs on (default 1: the cluster's workers and
            their threads are the parallelism, one filter per worker thread, so that filters
            do not compete for cores; ``None``: a pool of one thread per core in each
            worker). Results do not depend on it.

    Returns:
        per building (manifest order): ``walks`` (each walk's result, as
        :func:`footslam.learn_one` gives it), ``passes`` (FeetSLAM passes run after the
        first), ``merged`` (the merged map, GeoJSON), ``plan`` (its walkable plan) and, with
        WiFi, ``radio_map`` and ``radio_plan``.
    """
    buildings = read_manifest(manifest)
    learn_args = {
        "config": config, "seed": seed, "particles": particles, "origin": origin,
        "threads": threads,
    }
    futures = {}
    for name, walks in buildings.items():
        known = all(w.start is not None for w in walks)
        passes = footslam.feetslam_passes(len(walks), known_starts=known, config=config)
        steps = [client.submit(steps_task, w, pure=False) for w in walks]
        results = [
            client.submit(learn_task, s, w, None, learn_args, pure=False)
            for s, w in zip(steps, walks)
        ]
        for _ in range(passes):
            previous = [client.submit(map_of, r, pure=False) for r in results]
            results = [
                client.submit(learn_task, s, w, previous, learn_args, pure=False)
                for s, w in zip(steps, walks)
            ]
        # One merge of the building's maps in walk order: edge counts are whole numbers and
        # sum exactly in any order, but a floor's height is a running weighted mean whose
        # last bit depends on the order, and a merge takes milliseconds.
        maps = [client.submit(map_of, r, pure=False) for r in results]
        merged = client.submit(merge_task, maps, pure=False)
        finish = client.submit(finish_task, walks, steps, results, merged, cell, pure=False)
        futures[name] = (passes, results, finish)
    out = {}
    for name, (passes, results, finish) in futures.items():
        done = finish.result()
        out[name] = {"walks": client.gather(results), "passes": passes, **done}
    return out


def write_outputs(results: dict[str, dict], out: str | Path) -> None:
    """Writes each building's maps under ``out/<building>/`` (merged.geojson, plan.geojson,
    radiomap.geojson, walk-<k>/map.geojson and track.csv)."""
    out = Path(out)
    for name, r in results.items():
        folder = out / name
        folder.mkdir(parents=True, exist_ok=True)
        for key, file in [("merged", "merged.geojson"), ("plan", "plan.geojson"),
                          ("radio_map", "radiomap.geojson")]:
            if r.get(key) is not None:
                (folder / file).write_text(json.dumps(r[key]))
        for k, walk in enumerate(r["walks"], start=1):
            w = folder / f"walk-{k}"
            w.mkdir(exist_ok=True)
            (w / "map.geojson").write_text(json.dumps(walk["map"]))
            track = walk["track"]
            columns = list(track)
            rows = zip(*(track[c] for c in columns))
            (w / "track.csv").write_text(
                ",".join(columns) + "\n" + "".join(",".join(map(repr, r)) + "\n" for r in rows)
            )
