"""The figure scripts' progress lines (scripts/progress.py)."""
import concurrent.futures as cf
import io
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
from progress import Progress, _clock  # noqa: E402


def test_a_line_per_finished_item_and_a_total_off_a_terminal():
    out = io.StringIO()
    bar = Progress(3, "walks", stream=out)
    for name in ("a", "b"):
        bar.start(name)
        bar.done(name, "median 1.0 m")
    bar.start("c")
    bar.failed("c", "no steps")
    bar.finish()
    lines = out.getvalue().splitlines()
    assert len(lines) == 4, lines
    assert lines[0].startswith("[1/3 walks] a in ") and "median 1.0 m" in lines[0]
    assert "FAILED no steps" in lines[2] and lines[2].startswith("[3/3 walks] c")
    assert lines[3].startswith("3/3 walks in ") and lines[3].endswith("1 failed")
    # No ETA guessed before the first item finished; one after.
    assert "eta" in lines[0] and "eta —" not in lines[0]


def test_parallel_items_are_counted_once_each():
    out = io.StringIO()
    bar = Progress(20, "items", stream=out)
    with cf.ThreadPoolExecutor(4) as ex:
        got = list(ex.map(bar.wrap(lambda i: i * i, name=lambda i: f"item {i}"), range(20)))
    assert got == [i * i for i in range(20)]
    assert bar.finished == 20 and bar.failures == 0
    assert len(out.getvalue().splitlines()) == 20


def test_quiet_and_clock():
    out = io.StringIO()
    os.environ["FOOTSLAM_QUIET"] = "1"
    try:
        bar = Progress(1, "x", stream=out)
        bar.start("a")
        bar.done("a")
        bar.finish()
    finally:
        del os.environ["FOOTSLAM_QUIET"]
    assert out.getvalue() == ""
    assert _clock(42) == "42 s" and _clock(185) == "3m05s" and _clock(3720) == "1h02m"
