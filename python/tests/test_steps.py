"""steps: raw IMU → step events, as ``footslam steps`` makes them."""

import numpy as np
import pytest

import footslam
from conftest import DATA, read_csv, read_json, same_report

# steps.csv's precision: t, field and field_up 3 decimals, length and dz 4, dheading and heading 6.
TOLERANCE = {"t": 6e-4, "length": 6e-5, "dheading": 6e-7, "dz": 6e-5, "heading": 6e-7,
             "field": 6e-4, "field_up": 6e-4}


@pytest.mark.parametrize("mount", ["phone", "foot"])
def test_steps_match_the_cli(cli, tmp_path, mount):
    imu = DATA / f"{mount}_excerpt.csv"
    cli("steps", "--imu", imu, "--mount", mount, "--out", tmp_path)
    expected = read_csv(tmp_path / "steps.csv")
    got = footslam.steps(imu, mount)
    steps = got["steps"]
    assert len(steps["t"]) == len(expected["t"]) > 0
    for column, tolerance in TOLERANCE.items():
        if column in expected:
            np.testing.assert_allclose(steps[column], expected[column], rtol=0, atol=tolerance)
    assert got["path"].shape == (len(steps["t"]) + 1, 3)
    summary = read_json(tmp_path / "summary.json")
    assert ("field" in steps) == (mount == "phone"), "the phone excerpt has a magnetometer"
    assert same_report(got["summary"], summary)


def test_arrays_and_frames_give_what_the_file_gives():
    pd = pytest.importorskip("pandas")
    imu = DATA / "phone_excerpt.csv"
    from_file = footslam.steps(imu, "phone")
    frame = pd.read_csv(imu)
    from_frame = footslam.steps(frame, "phone")
    from_dict = footslam.steps({c: frame[c].to_numpy() for c in frame.columns}, "phone")
    for got in (from_frame, from_dict):
        for column, values in from_file["steps"].items():
            np.testing.assert_array_equal(got["steps"][column], values)
        np.testing.assert_array_equal(got["path"], from_file["path"])


def test_units_and_flips_are_the_cli_flags(cli, tmp_path):
    pd = pytest.importorskip("pandas")
    frame = pd.read_csv(DATA / "foot_excerpt.csv")
    in_g = frame.copy()
    for axis in ["ax", "ay", "az"]:
        in_g[axis] = frame[axis] / 9.80665
    in_g.to_csv(tmp_path / "g.csv", index=False)
    cli("steps", "--imu", tmp_path / "g.csv", "--mount", "foot", "--accel-unit", "g",
        "--out", tmp_path / "out")
    expected = read_csv(tmp_path / "out" / "steps.csv")
    got = footslam.steps(in_g, "foot", accel_unit="g")
    np.testing.assert_allclose(got["steps"]["length"], expected["length"], atol=6e-5)


def test_learn_takes_the_field_of_the_steps():
    got = footslam.steps(DATA / "phone_excerpt.csv", "phone")["steps"]
    n = len(got["t"])
    walk = footslam.learn(got, particles=100, seed=1)["walks"][0]["summary"]
    field = walk["magnetic_field"]
    assert field["steps_with_field"] == n
    # A few dozen steps are too few to calibrate the field on.
    assert field["unused"] == "too_few_readings" and field["steps_weighed"] == 0
    assert footslam.learn(got, particles=100, seed=1)["walks"][0]["field_map"] is None
    without = footslam.learn({k: v for k, v in got.items() if not k.startswith("field")},
                             particles=100, seed=1)["walks"][0]["summary"]
    assert without["magnetic_field"] is None
