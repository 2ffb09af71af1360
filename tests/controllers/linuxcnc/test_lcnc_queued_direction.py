"""LinuxCNC checks the direction of the lines still queued whenever it flushes them where they are.

An inside corner moves the start of the next line to the intersection of the offsets; when that
intersection lies beyond the line's own offset end, the queued line runs backwards. LinuxCNC's
``move_endpoint_and_flush`` finds that at the next outside corner of a straight block, at G40 and at
the program end (``Straight feed in concave corner cannot be reached by the tool without gouging``,
at the block being read); at a near-tangent joint it flushes without the check and runs the line
backwards. Every expected value below is LinuxCNC's own (rs274 of commit 5c41560e on these
programs): the error line, and the path up to it.
"""

from __future__ import annotations

import pytest

from trcopt.pipeline import PlanOptions, plan

# entry from X50 to X32 with the tool on the right, then a short line at a sharp inside corner:
# the entry is cut back to (33.8141, 1), beyond the line's offset end (33.4934, 0.4921)
HEAD = "G21 G17 G90 F6000\nG0 X50 Y0\nG42.1 D2 G1 X32 Y0\nG1 X32.64782 Y1.026\n"


def _plan(text: str):  # type: ignore[no-untyped-def]
    return plan(text, file="t.ngc", options=PlanOptions(dialect="rs274", timing=False))


@pytest.mark.parametrize(
    "tail",
    [
        "G1 X33.02082 Y2.07749\nG40 G1 X50 Y0\nM2\n",  # an outside corner of a straight block
        "G40 G1 X50 Y0\nM2\n",  # compensation off
        "M2\n",  # program end with compensation on
    ],
    ids=["outside-corner", "g40", "program-end"],
)
def test_a_reversed_queued_line_is_linuxcncs_concave_gouge_error(tail: str) -> None:
    r = _plan(HEAD + tail)
    assert [(d.code, d.span.line) for d in r.errors] == [("LCNC-CONCAVE-GOUGE", 5)]
    # the entry, cut back to the inside corner, is final; the reversed line is discarded
    compensated = [s for s in r.toolpath if s.radius > 0.0]
    assert [s.role.value for s in compensated] == ["approach"]
    assert compensated[-1].end_xyz[:2] == pytest.approx((33.8141, 1.0), abs=1e-4)


def test_after_a_near_tangent_joint_linuxcnc_runs_the_reversed_line() -> None:
    # the next line continues the short one within 0.05 rad: no check, the line runs backwards
    r = _plan(HEAD + "G1 X32.8080 Y1.2797\nG40 G1 X50 Y0\nM2\n")
    assert not r.errors
    ends = [c for s in r.toolpath if s.radius > 0.0 for c in s.end_xyz[:2]]
    assert ends == pytest.approx([33.8141, 1.0, 33.4934, 0.4921, 33.6536, 0.7458], abs=1e-4)
    # a real reversal of the path: the verification says so
    tangency = r.verification.families["tangency"]
    assert tangency.max_residual >= 1.0 and tangency.line == 4


def test_outside_corner_after_a_forward_line_flushes_as_before() -> None:
    # the same outside corner after an entry that is not cut back past the line: no error
    text = HEAD.replace("X50 Y0", "X20 Y-10", 1) + "G1 X33.02082 Y2.07749\nG40 G1 X50 Y0\nM2\n"
    r = _plan(text)
    assert not r.errors
    assert [s.role.value for s in r.toolpath if s.radius > 0.0].count("corner") >= 1
