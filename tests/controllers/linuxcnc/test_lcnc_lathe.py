"""LinuxCNC lathe tools under cutter compensation: the tip of a tool of orientation 1–8 is
programmed, the path is the compensated nose centre moved by the radius towards the tip (checked
against LinuxCNC's own test program in test_lcnc_programs and against rs274 on the stored corpus);
the verification measures the nose centre."""

from __future__ import annotations

import math

import pytest

from trcopt.controllers.linuxcnc.lathe import tip_shift
from trcopt.geometry.plane import Plane
from trcopt.pipeline import PlanOptions, plan
from trcopt.pipeline.stream import Unstreamable, plan_streamed

PROFILE = """N10 G21 G18 G90 F300
N20 G0 X20 Z0
N30 {comp} D4 L{orientation}
N40 G1 X10 Z5
N50 G1 Z30
N60 G2 X20 Z40 R10
N70 G1 X25
N80 G40
N90 G0 X40
N100 M2
"""


@pytest.mark.parametrize(
    ("orientation", "dx", "dz"),
    [
        (0, 0, 0), (1, -1, 1), (2, -1, -1), (3, 1, -1), (4, 1, 1),
        (5, 0, 1), (6, -1, 0), (7, 0, -1), (8, 1, 0), (9, 0, 0),
    ],
)
def test_tip_shift_by_orientation(orientation, dx, dz):
    d = tip_shift(orientation, 2.0, Plane.G18)
    if dx == dz == 0:
        assert d is None
    else:
        assert d == Plane.G18.to_uvw((2.0 * dx, 0.0, 2.0 * dz))


def _plan(text):
    return plan(text, file="lathe.ngc", options=PlanOptions(dialect="rs274", timing=False, corners="exact"))


@pytest.mark.parametrize("orientation", range(10))
@pytest.mark.parametrize("comp", ["G41.1", "G42.1"])
def test_the_path_is_the_tip_and_the_centre_is_verified(orientation, comp):
    tip = _plan(PROFILE.format(comp=comp, orientation=orientation))
    mill = _plan(PROFILE.format(comp=comp, orientation=0))
    assert tip.ok and not tip.warnings, [d.format() for d in tip.diagnostics]
    assert tip.verification is not None and tip.verification.ok
    d = tip_shift(orientation, 2.0, Plane.G18) or (0.0, 0.0, 0.0)
    # the compensated contour (line N50 on) is the mill tool's centre path moved by the shift
    a = [s for s in tip.toolpath if s.span.line in (5, 6, 7)]
    b = [s for s in mill.toolpath if s.span.line in (5, 6, 7)]
    assert len(a) == len(b)
    for sa, sb in zip(a, b, strict=True):
        for pa, pb in ((sa.geometry.start, sb.geometry.start), (sa.geometry.end, sb.geometry.end)):
            assert math.dist(pa, (pb[0] + d[0], pb[1] + d[1], pb[2] + d[2])) < 1e-9
    # the entry starts where the tool is; the move after G40 starts at the tip
    assert tip.toolpath[1].start_xyz == pytest.approx((20.0, 0.0, 0.0))
    exit_move = next(s for s in tip.toolpath if s.span.line == 9)
    last = next(s for s in reversed(tip.toolpath) if s.span.line == 7)
    assert exit_move.start_xyz == pytest.approx(last.end_xyz)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("G21 G17\nT2 M6\nG0 X0 Y0\nG41 G1 X10\nM2\n", "G41 with lathe tool, but plane is not G18"),
        ("G21 G17\nG0 X0 Y0\nG42.1 D2 L3 G1 X10\nM2\n", "G42.1 with L word, but plane is not G18"),
    ],
)
def test_lathe_tools_outside_g18_are_linuxcncs_errors(tmp_path, text, message):
    table = tmp_path / "t.tbl"
    table.write_text("T2 P2 Z0 X0 D0.4 Q3 ;\n")
    result = plan(text, file=str(tmp_path / "p.ngc"),
                  options=PlanOptions(dialect="rs274", timing=False, tool_table=str(table)))  # fmt: skip
    assert not result.ok
    assert result.errors[0].message == message
    assert result.errors[0].span.line == (4 if "G41 " in text else 3)


def test_a_lathe_program_is_planned_whole(tmp_path):
    path = tmp_path / "lathe.ngc"
    path.write_text(PROFILE.format(comp="G41.1", orientation=3))
    with pytest.raises(Unstreamable, match="lathe"):
        plan_streamed(str(path), PlanOptions(timing=False))
