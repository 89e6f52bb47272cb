"""learn, learn_one, others_map, merge and plan: the maps and paths ``footslam learn``,
``merge`` and ``plan`` write, for the same inputs and seeds."""

import numpy as np
import pytest

import footslam
from conftest import read_csv, read_json, same_report

PARTICLES = 300
SEED = 5


def assert_track(got, expected):
    """A learned path against learn's track.csv (t, x, y to a millimetre)."""
    assert len(got["t"]) == len(expected["t"])
    for c in ["t", "x", "y"]:
        np.testing.assert_allclose(got[c], expected[c], rtol=0, atol=6e-4)


@pytest.fixture(scope="module")
def office(cli, sim, tmp_path_factory):
    """One office walk learned by the CLI and by Python."""
    out = tmp_path_factory.mktemp("learn")
    steps = sim / "office" / "steps.csv"
    cli("learn", "--steps", steps, "--particles", PARTICLES, "--seed", SEED, "--out", out)
    got = footslam.learn(steps, particles=PARTICLES, seed=SEED)
    return out, got


def test_learn_matches_the_cli(office):
    out, got = office
    walk = got["walks"][0]
    assert_track(walk["track"], read_csv(out / "track.csv"))
    expected = read_json(out / "map.geojson")
    assert len(walk["map"]["features"]) == len(expected["features"]) > 50
    assert walk["map"] == expected
    assert walk["plan"] == read_json(out / "plan.geojson")
    summary = read_json(out / "summary.json")
    assert same_report(got["summary"], summary)
    for key in ["hexagons", "steps", "seed", "particles", "quality"]:
        assert walk["summary"][key] == summary[key], key
    assert got["config"] == read_json(out / "config.json")
    assert got["merged"] is None and got["radio_map"] is None


def test_a_dataframe_learns_what_the_file_learns(sim, office):
    pd = pytest.importorskip("pandas")
    _, from_file = office
    frame = pd.read_csv(sim / "office" / "steps.csv")
    got = footslam.learn(frame, particles=PARTICLES, seed=SEED)
    assert got["walks"][0]["map"] == from_file["walks"][0]["map"]
    np.testing.assert_array_equal(got["walks"][0]["track"]["x"], from_file["walks"][0]["track"]["x"])


def test_config_dict_equals_config_file_and_flags(cli, sim, tmp_path):
    steps = sim / "office" / "steps.csv"
    config = {"particles": 200, "seed": 11, "hex_radius": 0.6}
    (tmp_path / "c.json").write_text(__import__("json").dumps(config))
    cli("learn", "--steps", steps, "--config", tmp_path / "c.json", "--out", tmp_path / "out")
    from_dict = footslam.learn(steps, config=config)
    from_file = footslam.learn(steps, config=tmp_path / "c.json")
    expected = read_json(tmp_path / "out" / "map.geojson")
    assert from_dict["walks"][0]["map"] == expected == from_file["walks"][0]["map"]


def test_a_batch_and_its_tasks_match_the_cli(cli, sim, tmp_path):
    """Two walks learned as a batch; each again as a task (learn_one); maps merged."""
    steps = [sim / "office" / "steps.csv", sim / "tower" / "steps.csv"]
    cli("learn", "--steps", steps[0], "--steps", steps[1], "--particles", PARTICLES,
        "--seed", SEED, "--out", tmp_path)
    got = footslam.learn(steps, particles=PARTICLES, seed=SEED)
    for i, walk in enumerate(got["walks"]):
        folder = tmp_path / f"walk-{i + 1}"
        assert_track(walk["track"], read_csv(folder / "track.csv"))
        assert walk["map"] == read_json(folder / "map.geojson")
        task = footslam.learn_one(steps[i], i, particles=PARTICLES, seed=SEED)
        assert task["map"] == walk["map"]
    merged = read_json(tmp_path / "merged.geojson")
    assert got["merged"] == merged
    assert same_report(got["summary"], read_json(tmp_path / "summary.json"))
    assert got["config"] == read_json(tmp_path / "config.json")
    for i, walk in enumerate(got["walks"]):
        assert walk["config"] == read_json(tmp_path / f"walk-{i + 1}" / "config.json")
    maps = [w["map"] for w in got["walks"]]
    walk_maps = [tmp_path / f"walk-{i}" / "map.geojson" for i in (1, 2)]
    cli("merge", *walk_maps, "--out", tmp_path / "m.geojson")
    assert footslam.merge(maps) == read_json(tmp_path / "m.geojson")
    assert footslam.others_map(maps, 0)["features"] == maps[1]["features"]
    assert footslam.feetslam_passes(2, known_starts=False) == 0
    assert footslam.feetslam_passes(2, known_starts=True) == 2


def test_a_batch_fanned_out_pass_by_pass_learns_what_the_cli_learns(cli, sim, tmp_path):
    """Walks with known starts share a frame: FeetSLAM passes, each walk a task
    (learn_one) given the others' merged map of the pass before (others_map)."""
    steps = [sim / "office" / "steps.csv", sim / "office2" / "steps.csv"]
    cli("learn", "--steps", steps[0], "--steps", steps[1], "--start", "0,0,0", "--start",
        "0,0,0", "--particles", PARTICLES, "--seed", SEED, "--out", tmp_path)
    passes = footslam.feetslam_passes(len(steps), known_starts=True)
    assert passes == read_json(tmp_path / "summary.json")["iterations"] > 0
    maps = [None, None]
    for _ in range(passes + 1):
        previous = list(maps)
        maps = [
            footslam.learn_one(s, i, start=(0, 0, 0), particles=PARTICLES, seed=SEED,
                               others=footslam.others_map(previous, i) if previous[0] else None)["map"]
            for i, s in enumerate(steps)
        ]
    for i, m in enumerate(maps):
        assert m == read_json(tmp_path / f"walk-{i + 1}" / "map.geojson")


def test_gps_outline_and_prior_map_match_the_cli(cli, sim, tmp_path):
    """A campus walk placed by GPS inside its outline, then learned again on its own map."""
    pd = pytest.importorskip("pandas")
    campus = sim / "campus"
    args = ["--steps", campus / "steps.csv", "--gps", campus / "gps.csv", "--outline",
            campus / "outline.geojson", "--particles", PARTICLES, "--seed", SEED]
    cli("learn", *args, "--out", tmp_path / "first")
    outline = read_json(campus / "outline.geojson")
    first = footslam.learn(campus / "steps.csv", gps=pd.read_csv(campus / "gps.csv"),
                           outline=outline, particles=PARTICLES, seed=SEED)
    walk = first["walks"][0]
    assert walk["map"] == read_json(tmp_path / "first" / "map.geojson")
    assert_track(walk["track"], read_csv(tmp_path / "first" / "track.csv"))
    cli("learn", *args, "--prior-map", tmp_path / "first" / "map.geojson",
        "--out", tmp_path / "second")
    second = footslam.learn(campus / "steps.csv", gps=campus / "gps.csv", outline=outline,
                            prior_map=walk["map"], particles=PARTICLES, seed=SEED)
    walk = second["walks"][0]
    assert walk["map"] == read_json(tmp_path / "second" / "map.geojson")
    assert walk["merged_with_prior"] == read_json(tmp_path / "second" / "merged.geojson")
    assert second["summary"]["prior_map_walks"] == 1


def test_merge_and_plan_match_the_cli(cli, office, tmp_path):
    out, got = office
    map_path = out / "map.geojson"
    cli("merge", map_path, map_path, "--weights", "1,0.5", "--out", tmp_path / "m.geojson")
    assert footslam.merge([map_path, got["walks"][0]["map"]], [1, 0.5]) == read_json(
        tmp_path / "m.geojson"
    )
    cli("plan", "--map", map_path, "--out", tmp_path / "plan")
    planned = footslam.plan(got["walks"][0]["map"])
    assert planned["plan"] == read_json(tmp_path / "plan" / "plan.geojson")
    summary = read_json(tmp_path / "plan" / "summary.json")
    assert same_report(footslam.plan(map_path)["summary"], summary)
    assert planned["summary"]["map_file"] == "map"  # a dict is named by its argument
    assert planned["config"] == read_json(tmp_path / "plan" / "config.json")
    grid = planned["grids"][0]["occupancy"]
    assert grid.shape == (summary["grid_height"], summary["grid_width"])
    assert (grid == 0).sum() == summary["grid_free"]
    assert (grid == 100).sum() == summary["grid_occupied"]


def test_learn_with_wifi_makes_the_cli_radio_map(cli, sim, tmp_path):
    tower = sim / "tower"
    cli("learn", "--steps", tower / "steps.csv", "--wifi", tower / "wifi.csv",
        "--particles", PARTICLES, "--seed", SEED, "--out", tmp_path)
    got = footslam.learn(tower / "steps.csv", wifi=tower / "wifi.csv", particles=PARTICLES,
                         seed=SEED)
    assert got["radio_map"] == read_json(tmp_path / "radiomap.geojson")
    assert got["walks"][0]["map"] == read_json(tmp_path / "map.geojson")
    assert same_report(got["summary"], read_json(tmp_path / "summary.json"))


def test_geopandas_reads_the_maps(office):
    gpd = pytest.importorskip("geopandas")
    _, got = office
    frame = gpd.GeoDataFrame.from_features(got["walks"][0]["map"])
    assert len(frame) == len(got["walks"][0]["map"]["features"])
    assert {"q", "r", "counts", "visits", "level"} <= set(frame.columns)
