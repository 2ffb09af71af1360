"""The cycle-time model that chooses between transition plans (``corners.time_model``): exact for
its own profile on lines and arcs (closed forms below), stops where the timing stage stops, and
the choice falls back to the timing stage where two plans are close."""

from __future__ import annotations

import math

import pytest

from trcopt.config import DEFAULT_MACHINE
from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line
from trcopt.geometry.plane import Plane
from trcopt.optimize.corners import time_model
from trcopt.optimize.corners.time_model import estimate_time, quicker
from trcopt.path import Role, Segment
from trcopt.timing import time_parameterize

A = 2000.0  # the default machine's X/Y acceleration limit, mm/s²


def _seg(g: Line | Arc, feed: float) -> Segment:
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t", 1, 1), feed)


def _rest_to_rest(length: float, v: float, a: float = A) -> float:
    """Time of a move from rest to rest with speed ≤ v and acceleration ≤ a."""
    if length >= v * v / a:
        return length / v + v / a
    return 2.0 * math.sqrt(length / a)


@pytest.mark.parametrize("length", [0.5, 4.0, 100.0])
def test_a_line_is_the_closed_form_rest_to_rest_move(length: float) -> None:
    seg = _seg(Line((0.0, 0.0, 0.0), (length, 0.0, 0.0)), 100.0)
    assert estimate_time([seg], DEFAULT_MACHINE) == pytest.approx(_rest_to_rest(length, 100.0), rel=1e-12)
    # the timing stage's profile on a line along one axis is the same
    assert time_parameterize([seg]).duration == pytest.approx(_rest_to_rest(length, 100.0), rel=1e-3)


def test_an_arc_runs_at_the_speed_of_its_centripetal_limit() -> None:
    R = 5.0
    arc = Arc((0.0, 0.0), R, 0.0, math.pi / 2)
    v = math.sqrt(A * R)  # 100 mm/s, below the feed
    expected = _rest_to_rest(arc.length, v)
    assert estimate_time([_seg(arc, 200.0)], DEFAULT_MACHINE) == pytest.approx(expected, rel=1e-12)


def test_the_path_stops_at_a_corner_and_runs_through_a_tangent_joint() -> None:
    a = _seg(Line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0)), 100.0)
    corner = _seg(Line((10.0, 0.0, 0.0), (10.0, 10.0, 0.0)), 100.0)
    straight = _seg(Line((10.0, 0.0, 0.0), (20.0, 0.0, 0.0)), 100.0)
    assert estimate_time([a, corner], DEFAULT_MACHINE) == pytest.approx(2 * _rest_to_rest(10.0, 100.0), rel=1e-12)
    assert estimate_time([a, straight], DEFAULT_MACHINE) == pytest.approx(_rest_to_rest(20.0, 100.0), rel=1e-12)
    # a slower feed on the second line: the model decelerates into it
    slow = _seg(Line((10.0, 0.0, 0.0), (20.0, 0.0, 0.0)), 50.0)
    t = estimate_time([a, slow], DEFAULT_MACHINE)
    # line 1: up to 100, cruise, down to 50
    expected = 100 / A + (10.0 - 100**2 / (2 * A) - (100**2 - 50**2) / (2 * A)) / 100 + 50 / A
    expected += 50 / A + (10.0 - 50**2 / (2 * A)) / 50  # line 2: cruise at 50, then down to rest
    assert t == pytest.approx(expected, rel=1e-12)


def test_quicker_trusts_the_model_only_beyond_its_margin(monkeypatch: pytest.MonkeyPatch) -> None:
    import trcopt.timing

    calls = []
    real = trcopt.timing.time_parameterize

    def counted(segs, machine=DEFAULT_MACHINE, **kw):  # type: ignore[no-untyped-def]
        calls.append(len(segs))
        return real(segs, machine, **kw)

    monkeypatch.setattr(trcopt.timing, "time_parameterize", counted)
    fast = [_seg(Line((0.0, 0.0, 0.0), (50.0, 0.0, 0.0)), 100.0)]
    slow = [_seg(Line((0.0, 0.0, 0.0), (50.0, 0.0, 0.0)), 50.0)]
    assert quicker(fast, slow, DEFAULT_MACHINE) and not quicker(slow, fast, DEFAULT_MACHINE)
    assert calls == []  # 0.55 s against 1.025 s: the model decides
    close = [_seg(Line((0.0, 0.0, 0.0), (50.0, 0.0, 0.0)), 100.0 * (1 - time_model.MODEL_MARGIN / 4))]
    assert quicker(fast, close, DEFAULT_MACHINE) and not quicker(close, fast, DEFAULT_MACHINE)
    assert len(calls) == 4  # within the margin: the timing stage times both, both ways
    # a narrower margin (run splines against circular blends): 6 % apart is decided by the model
    between = [_seg(Line((0.0, 0.0, 0.0), (50.0, 0.0, 0.0)), 100.0 * 0.94)]
    assert quicker(fast, between, DEFAULT_MACHINE, time_model.RUN_SPLINE_MARGIN)
    assert not quicker(between, fast, DEFAULT_MACHINE, time_model.RUN_SPLINE_MARGIN)
    assert len(calls) == 4
    assert quicker(fast, between, DEFAULT_MACHINE) and len(calls) == 6  # (within the default margin)


def test_a_g2_plan_that_cannot_be_timed_gives_the_circles_and_says_why(monkeypatch: pytest.MonkeyPatch) -> None:
    from pathlib import Path

    from trcopt.errors import TimingError
    from trcopt.geometry import Poly
    from trcopt.modes import TransitionKind
    from trcopt.optimize.corners import blend_corners, selection
    from trcopt.pipeline import PlanOptions, plan

    real = time_model.estimate_time

    def refusing(segs, machine):  # type: ignore[no-untyped-def]
        if any(isinstance(s.geometry, Poly) for s in segs):
            raise TimingError("no profile for this curve")
        return real(segs, machine)

    monkeypatch.setattr(time_model, "estimate_time", refusing)
    monkeypatch.setattr(selection, "estimate_time", refusing)
    prog = Path(__file__).resolve().parents[2] / "problems" / "corners" / "cam_quarter_circle.mpf"
    r = plan(prog.read_text(), file=prog.name, options=PlanOptions(timing=False))
    out = blend_corners(r.toolpath, r.programmed, tolerance_mm=0.01, mode="optimal")
    assert out.count(TransitionKind.SPLINE) == 0 and out.count(TransitionKind.ARC) > 0
    reasons = {c.reason for c in out.corners if c.transition is TransitionKind.ARC}
    why = "the G2 plan could not be timed (no profile for this curve)"
    assert any(r and r.startswith(why) for r in reasons), reasons
