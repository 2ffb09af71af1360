"""The feed-profile CSV and the speed plot of either trajectory kind: columns, number formats,
atomic writes, and matplotlib loaded only when a plot is drawn."""

from __future__ import annotations

import csv
import math
import os
import re
import subprocess
import sys

import pytest

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.io.atomic import OutputError
from trcopt.io.feed_csv import render_feed_csv, write_feed_csv
from trcopt.io.plot import plot_speed
from trcopt.timing import TimedTrajectory, time_parameterize
from trcopt.timing.jerk import JerkTrajectory, jerk_limited

J = 5e4  # mm/s³
ISO = Machine(
    name="iso",
    rapid_mm_min=12000.0,
    axes=(
        ("X", AxisLimits(200.0, 2000.0, J)),
        ("Y", AxisLimits(200.0, 2000.0, J)),
        ("Z", AxisLimits(200.0, 2000.0, J)),
    ),
)
COLUMNS = [
    "t_s", "s_mm", "x_mm", "y_mm", "z_mm", "path_speed_mm_s",
    "vx_mm_s", "vy_mm_s", "vz_mm_s", "ax_mm_s2", "ay_mm_s2", "az_mm_s2", "segment", "block",
]
JERK_COLUMNS = [*COLUMNS[:-2], "jx_mm_s3", "jy_mm_s3", "jz_mm_s3", *COLUMNS[-2:]]


def seg(g, feed=200.0, block="N10"):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", 3, 1, block), feed)


@pytest.fixture(scope="module")
def line_arc() -> TimedTrajectory:
    path = [
        seg(Line((0, 0, 0), (20, 0, 0)), block="N10"),
        seg(Arc((20.0, 5.0), 5.0, -math.pi / 2, math.pi), block="N20"),
    ]
    return time_parameterize(path, ISO)


@pytest.fixture(scope="module")
def line_arc_line() -> JerkTrajectory:
    path = [
        seg(Line((-30.0, -5.0, 0.0), (0.0, -5.0, 0.0)), 150.0, "N10"),
        seg(Arc((0.0, 0.0), 5.0, -math.pi / 2, math.pi), 150.0, "N20"),
        seg(Line((0.0, 5.0, 0.0), (-30.0, 5.0, 0.0)), 150.0, "N30"),
    ]
    return jerk_limited(path, ISO)


def _decimals(field: str) -> int:
    assert re.fullmatch(r"-?\d+\.\d+", field), field
    return len(field.split(".")[1])


def test_feed_csv_of_an_acceleration_limited_profile(line_arc, tmp_path):
    out = write_feed_csv(line_arc, tmp_path / "profile.csv")
    with out.open(newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == COLUMNS
    assert {r[-1] for r in rows[1:]} == {"N10", "N20"}
    # t, s, x, y, z, speed and v with 6 decimals, a with 3, the segment index as an integer
    assert [_decimals(f) for f in rows[1][:12]] == [6] * 9 + [3] * 3
    assert {int(r[12]) for r in rows[1:]} == {0, 1}
    assert float(rows[-1][0]) == pytest.approx(line_arc.duration, abs=5e-7)  # 6 decimals
    assert out.read_bytes() == render_feed_csv(line_arc).encode("utf-8")
    assert out.read_bytes().count(b"\r\n") == len(rows)  # csv.writer line ends, untranslated


def test_feed_csv_of_a_jerk_limited_profile(line_arc_line, tmp_path):
    out = write_feed_csv(line_arc_line, tmp_path / "feed.csv", dt=1e-2)
    with out.open(newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == JERK_COLUMNS
    assert [_decimals(f) for f in rows[1][:15]] == [6] * 9 + [3] * 3 + [1] * 3
    assert float(rows[-1][0]) == pytest.approx(line_arc_line.duration)
    assert {r[-1] for r in rows[1:]} == {"N10", "N20", "N30"}


def test_feed_csv_is_written_atomically(line_arc, tmp_path, monkeypatch):
    p = tmp_path / "profile.csv"
    p.write_text("complete old file")

    def boom(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OutputError, match="No space left"):
        write_feed_csv(line_arc, p)
    assert p.read_text() == "complete old file"
    assert os.listdir(tmp_path) == ["profile.csv"]


@pytest.mark.parametrize("kind", ["acceleration", "jerk"])
def test_speed_plot_png_and_svg(kind, line_arc, line_arc_line, tmp_path):
    traj = line_arc if kind == "acceleration" else line_arc_line
    plot_speed(traj, tmp_path / "speed.png")
    plot_speed(traj, tmp_path / "speed.svg")
    assert (tmp_path / "speed.png").stat().st_size > 1000 and (tmp_path / "speed.svg").exists()
    assert (tmp_path / "speed.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (tmp_path / "speed.svg").read_bytes()[:1000]


def test_speed_plot_without_suffix_gets_the_default_format(line_arc, tmp_path):
    # as matplotlib's savefig(path) does: the default format, its suffix appended
    plot_speed(line_arc, tmp_path / "speed")
    assert os.listdir(tmp_path) == ["speed.png"]


def test_speed_plot_is_written_atomically(line_arc, tmp_path, monkeypatch):
    p = tmp_path / "speed.png"
    p.write_bytes(b"complete old picture")

    def boom(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OutputError, match="No space left"):
        plot_speed(line_arc, p)
    assert p.read_bytes() == b"complete old picture"
    assert os.listdir(tmp_path) == ["speed.png"]


def test_speed_plot_into_given_axes_writes_nothing(line_arc, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2)
    assert plot_speed(line_arc, ax=axes) is fig
    assert axes[0].get_xlabel() == "s [mm]" and axes[1].get_title() == "speed over the path"
    plt.close(fig)
    assert os.listdir(tmp_path) == []


def test_the_speed_colours_span_the_cutting_moves_not_the_rapids():
    path = [
        Segment(Line((0, 0, 0), (60, 0, 0)), Plane.G17, Role.RAPID, SourceSpan("t.mpf", 2, 1, "N10"), None),
        seg(Line((60, 0, 0), (60, 20, 0)), 20.0, "N20"),
        seg(Line((60, 20, 0), (0, 20, 0)), 30.0, "N30"),
    ]
    traj = time_parameterize(path, ISO)
    fig = plot_speed(traj)
    coloured = [c for c in fig.axes[1].collections if c.get_array() is not None]
    assert len(coloured) == 1
    vmax = coloured[0].norm.vmax
    assert 29.0 < vmax <= 30.0 + 1e-6  # the fastest cutting move, not the rapid (≈ 200 mm/s)
    assert len(fig.axes[1].collections) == 2  # the rapid, grey
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_writing_a_speed_plot_keeps_the_backend_in_use(line_arc, tmp_path):
    import matplotlib

    before = matplotlib.get_backend()
    try:
        matplotlib.use("svg")  # a backend that is not Agg, as a notebook's inline one is not
        plot_speed(line_arc, tmp_path / "speed.png")
        assert matplotlib.get_backend() == "svg"
    finally:
        matplotlib.use(before)
    assert (tmp_path / "speed.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_writers_load_no_plotting_or_numerical_library_on_import():
    code = (
        "import sys, trcopt.trajectory, trcopt.io.feed_csv, trcopt.io.plot; "
        "print('matplotlib' in sys.modules, 'numpy' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]
