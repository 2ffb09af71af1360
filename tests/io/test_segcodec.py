"""The columns of ``trcopt.io.segcodec`` give back every field of every segment with its type, or
refuse a chunk they cannot hold exactly (the spill then pickles it)."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt import plan
from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane
from trcopt.geometry.poly import Poly
from trcopt.io.segcodec import decode, encode
from trcopt.io.spill import SpilledSegments
from trcopt.modes import Side
from trcopt.path import Role, Segment
from trcopt.pipeline import PlanOptions

ROOT = Path(__file__).resolve().parents[2]


def _fields(s: Segment) -> list[object]:
    g = s.geometry
    geo = [g.start, g.end] if isinstance(g, Line) else [g.center, g.radius, g.a0, g.sweep, g.w0, g.w1] if isinstance(
        g, Arc) else [g]  # fmt: skip
    sp = s.span
    values = [type(g), *geo, s.plane, s.role, s.feed_mm_s, s.side, s.radius, s.t_start_s, s.t_end_s, s.stop,
              s.smooth_end, sp.file, sp.line, sp.column, sp.block, sp.end_column, sp.machine, sp.run]  # fmt: skip
    flat: list[object] = []
    for v in values:
        flat.extend(v if isinstance(v, tuple) else [v])
    return [(type(v), v) for v in flat]


def _round_trip(segs: list[Segment]) -> list[Segment]:
    cols = encode(segs)
    assert cols is not None
    back = decode(*cols)
    assert back == segs
    assert [_fields(s) for s in back] == [_fields(s) for s in segs]
    return back


@pytest.mark.parametrize(
    "name", ["siemens/ex05_kont_g451.mpf", "heidenhain/h14_circle_cc.h", "rs274/cam_fusion_drill_profile.ngc"]
)
def test_planned_paths_come_back_field_by_field(name: str) -> None:
    path = ROOT / "problems" / name
    if not path.exists():
        pytest.skip(f"no {name}")
    res = plan(path.read_text(), file=str(path), options=PlanOptions())
    segs = res.timing.segments_with_times() if res.timing is not None else list(res.toolpath)
    _round_trip(list(segs))
    _round_trip(list(res.toolpath))


def test_rare_fields() -> None:
    span = SourceSpan("p.mpf", 7, 3, "N70", end_column=12, machine=(1.5, None, -2.0), run=2)
    plain = SourceSpan("q.mpf", 8, 1, None)
    poly = Poly(((0.0, 0.0, 0.0), (1.0, 0.5, 0.0)), ((1.0, 0.0, 0.0), (1.0, 0.0, 0.0)), (0.0, 1.1))
    segs = [
        Segment(Line((0.0, -0.0, 1.0), (2.0, 3.0, 1.0)), Plane.G18, Role.APPROACH, span, None, Side.LEFT, 2.5,
                0.0, 0.25, True, False),
        Segment(Arc((1.0, 2.0), 3.0, 0.5, -1.25, 0.0, -1.0), Plane.G17, Role.CORNER, span, 12.5, Side.RIGHT, 1.0,
                stop=False, smooth_end=True),
        Segment(poly, Plane.G19, Role.CONTOUR, plain, 3.0),
        Segment(Line((1e-300, 5.0, 0.0), (1e5, -1e5, 0.0)), Plane.G17, Role.RAPID, plain, None),
    ]  # fmt: skip
    back = _round_trip(segs)
    assert back[2].geometry is poly
    assert back[0].span.machine == (1.5, None, -2.0) and back[1].span.machine == (1.5, None, -2.0)
    assert _round_trip([]) == []


def test_what_the_columns_cannot_hold_is_pickled() -> None:
    span = SourceSpan("p.ngc", 1, 1)
    ints = Segment(Line((0, 0, 0), (1.0, 0.0, 0.0)), Plane.G17, Role.CONTOUR, span, 1.0)  # int coordinates
    assert encode([ints]) is None
    listed = Segment(Line([0.0, 0.0, 0.0], (1.0, 0.0, 0.0)), Plane.G17, Role.CONTOUR, span, 1.0)  # type: ignore[arg-type]
    assert encode([listed]) is None  # a list point comes back as a list (pickled), not a tuple
    spill = SpilledSegments()
    try:
        spill.append([ints])
        (back,) = list(spill)
        assert back == ints and type(back.geometry.start[0]) is int
    finally:
        spill.close()
