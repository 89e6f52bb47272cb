"""track and survey: the tracks and radio maps ``footslam track`` and ``survey`` write, for
the same inputs and seeds."""

import json
import threading
import time

import numpy as np
import pytest

import footslam
from conftest import read_csv, read_json, same_report

# A smaller prior than the default 8 million particles keeps the suite fast.
CONFIG = {"kld": {"max_particles": 100_000}}


def assert_points(got, expected, columns=("t", "x", "y", "z", "level")):
    """A track against track.csv (millimetres) row by row."""
    assert len(got["t"]) == len(expected["t"])
    for c in columns:
        np.testing.assert_allclose(got[c], expected[c], rtol=0, atol=6e-4, err_msg=c)


@pytest.fixture(scope="module")
def config_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("config") / "tracker.json"
    path.write_text(json.dumps(CONFIG))
    return path


@pytest.fixture(scope="module")
def surveyed(cli, sim, tmp_path_factory):
    """The tower walk surveyed into a radio map by the CLI and by Python."""
    out = tmp_path_factory.mktemp("survey")
    tower = sim / "tower"
    config = {"tracker": CONFIG}
    (out / "config.toml").write_text("[tracker.kld]\nmax_particles = 100000\n")
    cli("survey", "--plan", tower / "floor.geojson", "--steps", tower / "steps.csv",
        "--wifi", tower / "wifi.csv", "--seed", 2, "--cell", 4, "--config",
        out / "config.toml", "--out", out / "run")
    got = footslam.survey(tower / "floor.geojson", [(tower / "steps.csv", tower / "wifi.csv")],
                          seed=2, cell=4, config=config)
    return out / "run", got


def test_survey_matches_the_cli(surveyed):
    out, got = surveyed
    expected = read_json(out / "radiomap.geojson")
    assert len(got["radio_map"]["features"]) == len(expected["features"]) > 10
    assert got["radio_map"] == expected
    coverage = read_csv(out / "coverage.csv")
    np.testing.assert_allclose(got["coverage"]["coverage"] * 100, coverage["coverage_percent"],
                               atol=0.051)
    np.testing.assert_array_equal(got["coverage"]["cells"], coverage["cells"])
    summary = read_json(out / "summary.json")
    walk = summary["walks"][0]
    for key in ["steps_to_localise", "steps_placed", "scans_added", "scans_skipped", "quality"]:
        assert got["walks"][0][key] == walk[key], key
    assert same_report(got["summary"], summary)
    assert got["walks"] == got["summary"]["walks"]
    assert got["config"] == read_json(out / "config.json")


def test_track_matches_the_cli(cli, sim, config_file, tmp_path):
    tower = sim / "tower"
    cli("track", "--plan", tower / "floor.geojson", "--steps", tower / "steps.csv",
        "--seed", 6, "--config", config_file, "--out", tmp_path)
    with pytest.warns(footslam.FootslamWarning, match="kld.max_particles") as warned:
        got = footslam.track(tower / "floor.geojson", tower / "steps.csv", seed=6, config=CONFIG)
    assert warned[0].filename == __file__  # the warning points at the caller
    expected = read_csv(tmp_path / "track.csv")
    assert_points(got["track"], expected)
    np.testing.assert_array_equal(got["track"]["certain"], expected["certain"] == 1)
    np.testing.assert_array_equal(got["track"]["hypotheses"], expected["hypotheses"])
    np.testing.assert_allclose(got["track"]["spread"], expected["spread"], atol=0.006)
    np.testing.assert_allclose(got["track"]["share"], expected["share"], atol=0.0006)
    assert ((got["track"]["share"] > 0) & (got["track"]["share"] <= 1)).all()
    assert_points(got["filtered"], read_csv(tmp_path / "track_filtered.csv"))
    summary = read_json(tmp_path / "summary.json")
    assert same_report(got["summary"], summary)
    assert list(got["steps"]["particles"]) == summary["particles_per_step"]
    assert got["config"] == read_json(tmp_path / "config.json")


def test_track_with_a_radio_map_matches_the_cli(cli, sim, surveyed, config_file, tmp_path):
    out, got_survey = surveyed
    tower = sim / "tower"
    cli("track", "--plan", tower / "floor.geojson", "--steps", tower / "steps.csv",
        "--radiomap", out / "radiomap.geojson", "--wifi", tower / "wifi.csv", "--seed", 7,
        "--config", config_file, "--out", tmp_path)
    got = footslam.track(tower / "floor.geojson", tower / "steps.csv", seed=7,
                         radio_map=got_survey["radio_map"], wifi=tower / "wifi.csv",
                         config=CONFIG)
    assert_points(got["track"], read_csv(tmp_path / "track.csv"))
    expected = read_json(tmp_path / "summary.json")
    # The radio map came as a dict here, as a file there: its name differs, nothing else.
    assert got["summary"]["rf"].pop("radiomap_file") != expected["rf"].pop("radiomap_file")
    assert same_report(got["summary"], expected)


def test_track_on_a_learned_plan_from_arrays(cli, sim, tmp_path):
    """learn → plan → track, the walk given as arrays, the plan as a dict, a known start."""
    pd = pytest.importorskip("pandas")
    steps = sim / "office" / "steps.csv"
    cli("learn", "--steps", steps, "--particles", 300, "--seed", 1, "--out", tmp_path / "l")
    cli("track", "--plan", tmp_path / "l" / "plan.geojson", "--steps", steps, "--plan-margin",
        0.25, "--start", "0,0,0", "--online", "--seed", 3, "--out", tmp_path / "t")
    learned = footslam.learn(pd.read_csv(steps), particles=300, seed=1)
    plan = footslam.plan(learned["walks"][0]["map"])["plan"]
    got = footslam.track(plan, pd.read_csv(steps), plan_margin=0.25, start=(0, 0, 0),
                         online=True, seed=3)
    assert_points(got["track"], read_csv(tmp_path / "t" / "track.csv"))
    assert set(got["track"]) == {"t", "x", "y", "z", "level"}


@pytest.mark.filterwarnings("ignore::footslam.FootslamWarning")
def test_the_gil_is_released_while_a_filter_runs(sim):
    """Python threads run while a track runs; two tracks run side by side."""
    tower = sim / "tower"
    results, ticks = [], 0

    def run():
        results.append(footslam.track(tower / "floor.geojson", tower / "steps.csv", seed=6,
                                      config=CONFIG))

    threads = [threading.Thread(target=run) for _ in range(2)]
    started = time.perf_counter()
    for t in threads:
        t.start()
    while any(t.is_alive() for t in threads):
        ticks += 1
        time.sleep(0.001)
    elapsed = time.perf_counter() - started
    assert len(results) == 2
    assert results[0]["track"]["x"].tolist() == results[1]["track"]["x"].tolist()
    # Held, the GIL would stop this loop until the runs were over.
    assert elapsed > 0.1 and ticks > 20, (ticks, elapsed)


def test_progress_is_reported_and_changes_nothing(sim):
    """A progress callable sees each stage from 0 to its total, a few hundred calls at most;
    the result is the one without it; an exception it raises comes out when the run ends."""
    office = sim / "office"
    calls = []
    quiet = footslam.learn(office / "steps.csv", particles=300, seed=2)
    told = footslam.learn(office / "steps.csv", particles=300, seed=2,
                          progress=lambda *a: calls.append(a))
    assert told["walks"][0]["track"]["x"].tolist() == quiet["walks"][0]["track"]["x"].tolist()
    stages = {stage for stage, _, _ in calls}
    assert stages, calls
    for stage in stages:
        seen = [(done, total) for s, done, total in calls if s == stage]
        total = seen[0][1]
        assert seen[0] == (0, total) and seen[-1] == (total, total), seen
        assert [d for d, _ in seen] == sorted(d for d, _ in seen)
        assert len(seen) <= 203

    def fails(stage, done, total):
        raise RuntimeError(f"stop at {stage} {done}")

    with pytest.raises(RuntimeError, match="stop at"):
        footslam.track(office / "floor.geojson", office / "steps.csv", start=(0, 0, 0),
                       progress=fails)
    with pytest.raises(TypeError, match="progress must be a callable"):
        footslam.track(office / "floor.geojson", office / "steps.csv", progress=3)


def test_fingerprint_matches_the_cli(cli, surveyed, sim, tmp_path):
    run, _ = surveyed
    tower = sim / "tower"
    cli("fingerprint", "--radiomap", run / "radiomap.geojson", "--wifi", tower / "wifi.csv",
        "--k", 2, "--out", tmp_path)
    got = footslam.fingerprint(run / "radiomap.geojson", tower / "wifi.csv", k=2)
    expected = read_csv(tmp_path / "track.csv")
    assert len(got["track"]["t"]) == len(expected["t"]) > 10
    for c in ["t", "x", "y"]:
        np.testing.assert_allclose(got["track"][c], expected[c], atol=6e-4)
    assert same_report(got["summary"], read_json(tmp_path / "summary.json"))
    assert got["config"] == read_json(tmp_path / "config.json")
    assert got["summary"]["placed"] + got["summary"]["unplaced"] == got["summary"]["scans"]
