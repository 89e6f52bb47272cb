"""The Dask batch runner: 5 simulated buildings × 20 walks on a two-worker LocalCluster give
the maps of the same walks learned one building at a time (``footslam.learn``), and every
walk's map and track; a bad manifest says which line."""

from pathlib import Path

import pytest
from dask.distributed import Client, LocalCluster

import footslam
import footslam.batch

BUILDINGS = 5
WALKS = 20
PARTICLES = 300


def make_batch(cli, root: Path) -> Path:
    """Five office floors of different sizes, twenty one-lap walks each from the known
    start (the origin, facing east); the manifest of them all."""
    rows = ["building,steps,start"]
    for b in range(BUILDINGS):
        config = root / f"office-{b}.toml"
        config.write_text(
            f"[office]\nloop_width = {30 + 3 * b}\nloop_height = {18 + 2 * b}\n"
            f"rooms_per_long_side = {3 + b % 2}\n[walk]\nlaps = 1\n"
        )
        for w in range(WALKS):
            out = root / f"b{b}" / f"w{w}"
            cli("simulate", "--building", "office", "--config", config,
                "--seed", 1000 * b + w, "--out", out)
            rows.append(f'office-{b},b{b}/w{w}/steps.csv,"0,0,0"')
    manifest = root / "buildings.csv"
    manifest.write_text("\n".join(rows) + "\n")
    return manifest


@pytest.fixture(scope="module")
def client():
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    with Client(cluster) as c:
        yield c
    cluster.close()


def test_buildings_on_a_cluster_match_one_by_one(cli, tmp_path, client):
    manifest = make_batch(cli, tmp_path)
    results = footslam.batch.run_batch(manifest, client, particles=PARTICLES, seed=7)
    assert list(results) == [f"office-{b}" for b in range(BUILDINGS)]
    buildings = footslam.batch.read_manifest(manifest)
    for name, walks in buildings.items():
        alone = footslam.learn(
            [w.steps for w in walks],
            start=["0,0,0"] * len(walks),
            particles=PARTICLES,
            seed=7,
        )
        got = results[name]
        assert got["passes"] == 2
        assert got["merged"] == alone["merged"], name
        for k, (a, b) in enumerate(zip(got["walks"], alone["walks"])):
            assert a["map"] == b["map"], f"{name} walk {k}"
            for column in a["track"]:
                assert (a["track"][column] == b["track"][column]).all(), f"{name} {k} {column}"
        assert got["plan"]["features"], name
    out = tmp_path / "out"
    footslam.batch.write_outputs(results, out)
    assert (out / "office-0" / "merged.geojson").is_file()
    assert (out / "office-4" / "walk-20" / "track.csv").is_file()


def test_the_radio_map_of_a_building(cli, tmp_path, client):
    rows = ["building,steps,wifi,start"]
    for s in (4, 5):
        out = tmp_path / f"t{s}"
        cli("simulate", "--building", "tower", "--minutes", 2, "--seed", s, "--out", out)
        start = ",".join(open(out / "truth.csv").readlines()[1].split(",")[1:3])
        rows.append(f'tower,t{s}/steps.csv,t{s}/wifi.csv,"{start}"')
    manifest = tmp_path / "tower.csv"
    manifest.write_text("\n".join(rows) + "\n")
    got = footslam.batch.run_batch(manifest, client, particles=PARTICLES, seed=3)["tower"]
    walks = footslam.batch.read_manifest(manifest)["tower"]
    alone = footslam.learn(
        [w.steps for w in walks],
        wifi=[w.wifi for w in walks],
        start=[footslam.batch._start_arg(w.start) for w in walks],
        particles=PARTICLES,
        seed=3,
    )
    assert got["merged"] == alone["merged"]
    assert got["radio_map"] == alone["radio_map"]


def test_a_bad_manifest_names_its_line(tmp_path):
    manifest = tmp_path / "m.csv"
    manifest.write_text("building,steps\nb1,\n")
    with pytest.raises(ValueError, match=r"m.csv:2: give one of steps or imu"):
        footslam.batch.read_manifest(manifest)
    manifest.write_text("building,steps\nb1,missing.csv\n")
    with pytest.raises(FileNotFoundError, match=r"m.csv:2: steps"):
        footslam.batch.read_manifest(manifest)
