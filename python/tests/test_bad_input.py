"""Bad input raises a clear Python exception — the command line's message where the command
line has one — and never crashes the interpreter."""

import json

import numpy as np
import pytest

import footslam
from conftest import DATA, cli_error

STEPS = {
    "t": np.array([0.0, 0.5, 1.0]),
    "length": np.array([0.7, 0.7, 0.7]),
    "dheading": np.array([0.0, 0.1, 0.0]),
}


def with_column(name, values):
    table = dict(STEPS)
    table[name] = values
    return table


def test_file_errors_carry_the_cli_message(cli, tmp_path):
    bad = tmp_path / "steps.csv"
    bad.write_text("t,length,dheading\n0,0.7,0\n0.5,NaN,0\n")
    expected = cli_error(cli("learn", "--steps", bad, "--out", tmp_path / "o", check=False))
    with pytest.raises(footslam.FootslamError) as e:
        footslam.learn(bad)
    assert str(e.value) == expected
    assert "column `length`" in expected


def test_unknown_config_keys_carry_the_cli_message(cli, tmp_path):
    config = tmp_path / "c.json"
    config.write_text(json.dumps({"particles": 10, "bogus": 1}))
    expected = cli_error(cli("learn", "--config", config, "--out", tmp_path / "o", check=False))
    with pytest.raises(footslam.FootslamError) as from_file:
        footslam.learn(STEPS, config=config)
    assert str(from_file.value) == expected
    with pytest.raises(footslam.FootslamError, match="unknown field `bogus`") as from_dict:
        footslam.learn(STEPS, config={"particles": 10, "bogus": 1})
    assert str(from_dict.value).split("invalid configuration: ")[1] == expected.split(
        "invalid configuration: "
    )[1]
    with pytest.raises(footslam.FootslamError, match="unknown field `nope`"):
        footslam.track(DATA / "missing.geojson", STEPS, config={"kld": {"nope": 1}})


def test_configuration_values_are_checked():
    with pytest.raises(footslam.FootslamError, match="invalid configuration: .*particles"):
        footslam.learn(STEPS, particles=0)


def test_nan_in_a_required_column_names_the_row():
    with pytest.raises(footslam.FootslamError) as e:
        footslam.learn(with_column("length", np.array([0.7, np.nan, 0.7])))
    assert str(e.value) == "steps row 1: column `length`: `NaN` is not a finite number"
    with pytest.raises(footslam.FootslamError, match="steps row 2: column `t`: `inf`"):
        footslam.learn(with_column("t", np.array([0.0, 1.0, np.inf])))


def test_nan_in_an_optional_column_is_an_empty_cell():
    got = footslam.learn(with_column("heading", np.array([0.1, np.nan, 0.2])), particles=20)
    assert got["walks"][0]["summary"]["steps_with_heading"] == 2


def test_unsorted_times_and_empty_tables():
    with pytest.raises(footslam.FootslamError, match="steps row 2: .*increasing"):
        footslam.learn(with_column("t", np.array([0.0, 1.0, 0.5])))
    empty = {k: np.array([]) for k in STEPS}
    with pytest.raises(footslam.FootslamError, match="no steps"):
        footslam.learn(empty)
    with pytest.raises(ValueError, match="no columns"):
        footslam.learn({})
    with pytest.raises(footslam.FootslamError, match="missing column `dheading`"):
        footslam.learn({"t": [0.0], "length": [0.7]})
    with pytest.raises(footslam.FootslamError, match="no samples"):
        footslam.steps({c: [] for c in ["t", "ax", "ay", "az", "gx", "gy", "gz"]}, "foot")
    with pytest.raises(footslam.FootslamError, match="an empty list of walks"):
        footslam.learn([])


def test_wrong_dtypes_name_the_column():
    with pytest.raises(TypeError, match="steps: column `length` has dtype <U3"):
        footslam.learn(with_column("length", np.array(["0.7", "0.7", "abc"])))
    with pytest.raises(TypeError, match="column `t`"):
        footslam.learn(with_column("t", [0.0, "x", 1.0]))
    with pytest.raises(TypeError, match="column `dz`"):
        footslam.learn(with_column("dz", np.array([True, False, True])))
    with pytest.raises(ValueError, match="column `length` must be one-dimensional"):
        footslam.learn(with_column("length", np.ones((3, 2))))
    with pytest.raises(ValueError, match="column `length` has 2 values but column `t` has 3"):
        footslam.learn(with_column("length", np.array([0.7, 0.7])))
    with pytest.raises(TypeError, match="expected a path, a pandas DataFrame"):
        footslam.learn(42)
    with pytest.raises(TypeError, match="start: expected"):
        footslam.track(DATA / "nothing.geojson", STEPS, start=3.5)
    # Integer columns are numbers; extra columns are ignored, whatever they hold.
    table = dict(STEPS, t=np.array([0, 1, 2]), note=np.array(["a", "b", "c"]))
    assert len(footslam.learn(table, particles=20)["walks"][0]["track"]["t"]) == 3


def test_dataframe_with_a_text_column():
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame(STEPS)
    frame["length"] = frame["length"].astype(str)
    with pytest.raises(TypeError, match="column `length` has dtype object"):
        footslam.learn(frame)


def test_nullable_pandas_columns_read_na_as_missing():
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame(STEPS).astype("Float64")
    frame["heading"] = pd.array([0.1, None, 0.2], dtype="Float64")
    got = footslam.learn(frame, particles=20)
    assert got["walks"][0]["summary"]["steps_with_heading"] == 2
    frame.loc[1, "length"] = None
    with pytest.raises(footslam.FootslamError, match="steps row 1: column `length`"):
        footslam.learn(frame)


def test_missing_files_raise_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError, match="step trace `.*nope.csv` does not exist"):
        footslam.learn(tmp_path / "nope.csv")
    with pytest.raises(FileNotFoundError, match="IMU recording"):
        footslam.steps(str(tmp_path / "nope.csv"), "phone")
    with pytest.raises(FileNotFoundError, match="floor plan"):
        footslam.track(tmp_path / "plan.geojson", STEPS)
    with pytest.raises(FileNotFoundError, match="configuration"):
        footslam.learn(STEPS, config=tmp_path / "c.toml")
    with pytest.raises(FileNotFoundError, match="map"):
        footslam.merge([tmp_path / "m.geojson"])


def test_bad_geojson_and_arguments(sim):
    tower = sim / "tower"
    with pytest.raises(footslam.FootslamError, match="plan: .*origin"):
        footslam.track({"type": "FeatureCollection", "features": []}, tower / "steps.csv")
    with pytest.raises(footslam.FootslamError, match="plan:1: not a GeoJSON FeatureCollection"):
        footslam.track({"type": "Feature"}, tower / "steps.csv")
    with pytest.raises(ValueError, match="plan: cannot be written as JSON"):
        footslam.track({"type": "FeatureCollection", "features": [], "x": float("nan")},
                       tower / "steps.csv")
    with pytest.raises(ValueError, match="mount must be"):
        footslam.steps(DATA / "foot_excerpt.csv", "hand")
    with pytest.raises(footslam.FootslamError, match="radio_map and wifi go together"):
        footslam.track(tower / "floor.geojson", tower / "steps.csv", wifi=tower / "wifi.csv")
    with pytest.raises(footslam.FootslamError, match="no `dz` column"):
        footslam.track(tower / "floor.geojson", STEPS)
    with pytest.raises(footslam.FootslamError, match="start: HEADING `NaN` is not a finite number"):
        footslam.track(tower / "floor.geojson", tower / "steps.csv", start=(1, 2, float("nan")))
    with pytest.raises(footslam.FootslamError, match="walks\\[0\\].wifi row 0: rssi"):
        wifi = {"t": [0.5], "bssid": ["aa:bb"], "rssi": [20.0]}
        footslam.survey(tower / "floor.geojson", [(tower / "steps.csv", wifi)])
    with pytest.raises(footslam.FootslamError, match="2 gps entries for 1 walks|list of one"):
        footslam.learn([STEPS], gps=[None, None])


def test_inputs_that_do_not_belong_together():
    # Each input is valid alone; together they are of another grid or another clock.
    learned = footslam.learn(STEPS, particles=50, seed=1)
    prior = learned["walks"][0]["map"]
    with pytest.raises(footslam.FootslamError) as grid:
        footslam.learn(STEPS, particles=50, prior_map=prior, hex_radius=0.6)
    assert "hexagons of radius 0.5 m, but this run uses 0.6 m, or pass hex_radius=0.5" in str(
        grid.value
    )
    late = {"t": [5000.0, 5001.0], "lat": [48.1, 48.1], "lon": [11.5, 11.5]}
    with pytest.raises(footslam.FootslamError, match="gps: no fix falls within the walk's time span"):
        footslam.learn(STEPS, particles=50, gps=late)
    # gps_t0 is for GPX files: with a table it would be ignored, so it is refused.
    with pytest.raises(footslam.FootslamError, match="no walk has a GPX file"):
        footslam.learn(STEPS, particles=50, gps=late, gps_t0=1.7e9)


def test_integer_arguments_out_of_range_name_themselves_and_threads_are_capped():
    for kwargs, name in [({"seed": -1}, "seed"), ({"seed": 2**70}, "seed"),
                         ({"particles": 10**30}, "particles"), ({"particles": 10**8 + 1}, "particles"),
                         ({"threads": -2}, "threads")]:
        with pytest.raises(ValueError, match=f"{name} = .* is out of range"):
            footslam.learn(STEPS, **kwargs)
    with pytest.raises(TypeError, match="seed must be an integer"):
        footslam.learn(STEPS, seed=1.5)
    # A million threads would take minutes to schedule: capped, with a warning, same result.
    with pytest.warns(footslam.FootslamWarning, match="threads=1000000 capped"):
        many = footslam.learn(STEPS, particles=50, seed=1, threads=10**6)
    one = footslam.learn(STEPS, particles=50, seed=1, threads=1)
    np.testing.assert_array_equal(many["walks"][0]["track"]["x"], one["walks"][0]["track"]["x"])


def test_an_all_nan_dz_column_is_no_dz_column(sim):
    tower = sim / "tower"
    table = {"t": [1.0, 2.0, 3.0], "length": [0.7, 0.7, 0.7], "dheading": [0.0, 0.0, 0.0],
             "dz": [float("nan")] * 3}
    with pytest.raises(footslam.FootslamError, match="no `dz` column"):
        footslam.track(tower / "floor.geojson", table)
