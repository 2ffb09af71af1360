"""Where the controller's own rules bring the tool nearer than R (trcopt.verify.joints), and the
closed CAM contour entered from outside with LinuxCNC's G41.1/G42.1.

Every tool path planned here is LinuxCNC's own (rs274 of commit 5c41560e gives the same points to
its 4 printed decimals, or the same error at the same line).
"""

from __future__ import annotations

import math

import pytest

from trcopt.geometry import Line
from trcopt.pipeline import PlanOptions, plan
from trcopt.verify import verify_plan

MODEL = ("radius", "tangency", "continuity", "no_reversal", "clearance")
R = 1.0  # G41.1/G42.1 D2


def _plan(text: str):  # type: ignore[no-untyped-def]
    return plan(text, file="t.ngc", options=PlanOptions(dialect="rs274", timing=False, corners="exact"))


def _turned(p: tuple[float, float], angle: float, length: float) -> tuple[float, float]:
    return (p[0] + length * math.cos(angle), p[1] + length * math.sin(angle))


# G41.1 along +x, then a joint turning +0.03 rad (towards the tool: concave) and one turning
# -0.04 rad (convex): both within LinuxCNC's 0.05 rad, so both are left as they are
P1 = (20.0, 0.0)
P2 = _turned(P1, 0.03, 20.0)
P3 = _turned(P2, -0.01, 20.0)
NEAR_TANGENT = (
    "G21 G17 G90 F600\nG0 X-10 Y-5\nG41.1 D2 G1 X0 Y0\nG1 X20 Y0\n"
    f"G1 X{P2[0]:.9f} Y{P2[1]:.9f}\nG1 X{P3[0]:.9f} Y{P3[1]:.9f}\nG40 G1 X70 Y-10\nM2\n"
)


def _first_contour_of_line(r, line: int) -> int:  # type: ignore[no-untyped-def]
    return next(k for k, s in enumerate(r.toolpath) if s.span.line == line and s.role.value == "contour")


def test_radius_residual_counts_the_offset_error_once() -> None:
    # measured without the controller's rule: the continuation line of the convex joint starts
    # R·cos(0.04) from its carrier — that is the error, not twice that
    r = _plan(NEAR_TANGENT)
    rep = verify_plan(r.programmed, r.toolpath)
    assert rep.max_residual("radius") == pytest.approx(R * (1.0 - math.cos(0.04)), rel=1e-6)


def test_near_tangent_joints_left_as_they_are_verify_and_are_noted() -> None:
    r = _plan(NEAR_TANGENT)
    assert not r.errors
    k = _first_contour_of_line(r, 5)
    assert r.toolpath[k].start_xyz == pytest.approx(r.toolpath[k - 1].end_xyz)  # where the tool is
    rep = r.verification
    for fam in MODEL:
        assert rep.max_residual(fam) <= 1e-9, (fam, rep.summary_line())
    assert rep.ok
    (note,) = [n for n in rep.notes if n.startswith("near-tangent")]
    # the concave joint puts the tool R·(1 − cos 0.03) nearer than R to the next element
    amount = float(note.split("up to ")[1].split(" mm")[0])
    assert R * (1.0 - math.cos(0.03)) * (1 - 1e-6) <= amount <= R * (1.0 - math.cos(0.05))


def test_near_tangent_allowance_still_catches_a_deeper_tool() -> None:
    r = _plan(NEAR_TANGENT)
    k = _first_contour_of_line(r, 5)  # starts at the concave joint
    tp = list(r.toolpath)
    a, b = tp[k - 1].geometry, tp[k].geometry
    deeper = (b.start[0], b.start[1] - 0.01, b.start[2])  # 10 µm towards the part, joint kept
    tp[k - 1] = tp[k - 1].with_geometry(Line(a.start, deeper))
    tp[k] = tp[k].with_geometry(Line(deeper, b.end))
    rep = verify_plan(r.programmed, tp, near_tangent_rad=0.05)
    assert rep.max_residual("radius") == pytest.approx(0.01, abs=1e-6)
    # beyond the allowance R·cos 0.03 of that joint: the whole 10 µm, seen from the next line
    assert rep.max_residual("clearance") == pytest.approx(0.01 * math.cos(0.03), rel=1e-6)
    assert not rep.ok


def test_a_joint_beyond_the_limit_left_as_it_is_is_a_gouge() -> None:
    # 0.08 rad concave: LinuxCNC cuts the lines back to the intersection; a path that leaves the
    # joint as it is instead comes R·(1 − cos 0.08) too close, and that is not excused
    p2 = _turned(P1, 0.08, 20.0)
    r = _plan(f"G21 G17 G90 F600\nG0 X-10 Y-5\nG41.1 D2 G1 X0 Y0\nG1 X20 Y0\nG1 X{p2[0]:.9f} Y{p2[1]:.9f}\nM2\n")
    assert r.verification.ok
    k = _first_contour_of_line(r, 5)
    tp = list(r.toolpath)
    joint = (20.0, R, 0.0)  # the offset of the joint on the first line's side
    tp[k - 1] = tp[k - 1].with_geometry(Line(tp[k - 1].geometry.start, joint))
    tp[k] = tp[k].with_geometry(Line(joint, tp[k].geometry.end))
    rep = verify_plan(r.programmed, tp, near_tangent_rad=0.05)
    gouge = R * (1.0 - math.cos(0.08))
    assert rep.max_residual("clearance") == pytest.approx(gouge, rel=1e-6)
    assert rep.max_residual("radius") >= gouge * (1 - 1e-6)


def _polygon(n: int = 24, radius: float = 20.0) -> str:
    """A closed CCW polygon entered at its first point from outside with the tool inside (G41.1)."""
    pts = [_turned((0.0, 0.0), 2 * math.pi * i / n, radius) for i in range(n + 1)]
    body = "".join(f"G1 X{x:.6f} Y{y:.6f}\n" for x, y in pts[1:])
    return "G21 G17 G90 F600\nG0 X30 Y0\nG41.1 D2 G1 X20 Y0\n" + body + "G40 G1 X30 Y0\nM2\n"


def test_entry_arc_round_the_first_point_is_a_lead_move() -> None:
    # LinuxCNC's outside-corner arc about (20, 0) turns the tool from the entry side (20, -1) to
    # the first line's offset: it crosses the last block, which ends at (20, 0)
    r = _plan(_polygon())
    k = next(k for k, s in enumerate(r.toolpath) if s.role.value == "corner")
    arc = r.toolpath[k]
    assert r.toolpath[k - 1].role.value == "approach" and arc.span.line == 4
    rep = r.verification
    assert rep.ok, rep.summary_line()
    assert rep.max_residual("clearance") <= 1e-9
    lead = rep.families["lead_clearance"]
    assert lead.max_residual == pytest.approx(R) and lead.segment == k
    assert "line 4" in (rep.lead_note() or "")


def test_closing_joint_overlap_is_the_entry_points_and_noted() -> None:
    # no corner is compensated between the last block and the first: the first line's offset start
    # (where the entry arc ends) is R·cos 15° from the last block, and so is the last line's end
    r = _plan(_polygon())
    rep = r.verification
    (note,) = [n for n in rep.notes if n.startswith("the closed contour")]
    amount = float(note.split("up to ")[1].split(" mm")[0])
    assert amount == pytest.approx(R * (1.0 - math.cos(math.radians(15.0))), rel=1e-5)  # 6 digits
    assert rep.families["lead_clearance"].max_residual >= amount


def test_closing_joint_still_catches_a_tool_deeper_than_the_entry_point() -> None:
    # a detour of the first line 0.5 mm back along its own offset carrier, beyond the entry point:
    # still R from the first line, but 0.5·sin 15° nearer to the last block than the entry point
    r = _plan(_polygon())
    k = _first_contour_of_line(r, 4)
    seg = r.toolpath[k]
    g = seg.geometry
    d = g.start_tangent()
    back = (g.start[0] - 0.5 * d[0], g.start[1] - 0.5 * d[1], 0.0)
    tp = list(r.toolpath)
    tp[k : k + 1] = [seg.with_geometry(Line(g.start, back)), seg.with_geometry(Line(back, g.end))]
    rep = verify_plan(r.programmed, tp, near_tangent_rad=0.05)
    clear = rep.families["clearance"]
    assert clear.max_residual == pytest.approx(0.5 * math.sin(math.radians(15.0)), rel=1e-6)
    assert clear.segment in (k, k + 1)
    assert not rep.ok


# ---- the CAM contour of benchmarks/bench_cam_scale.py ----------------------------------------


def _cam(chords: int, side: str) -> str:
    """The closed freeform contour r(t) = c·(30 + 5 sin 5t + 2 cos 11t) as ``chords`` G1 moves,
    entered with ``side`` D2 from X50 Y0 and left with G40 to X50 Y0 (as the benchmark writes it)."""
    out = ["G21 G17 G90 G40 F6000", "G0 X50 Y0 Z1", "G1 Z0"]
    scale = max(1.0, chords * 0.25 / (2 * math.pi * 30))
    pts = []
    for i in range(chords + 1):
        t = 2 * math.pi * i / chords
        rad = scale * (30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t))
        pts.append((rad * math.cos(t), rad * math.sin(t)))
    out.append(f"{side} D2 G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}")
    out += [f"G1 X{x:.5f} Y{y:.5f}" for x, y in pts[1:]]
    out += ["G40 G1 X50 Y0", "G0 Z5", "M2"]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("chords", [200, 1000])
def test_cam_contour_g41_verifies(chords: int) -> None:
    r = _plan(_cam(chords, "G41.1"))
    assert not r.errors and not r.warnings
    rep = r.verification
    for fam in MODEL:
        assert rep.max_residual(fam) <= 1e-9, (fam, rep.summary_line())
    # the entry arc about X32 Y0 (line 5) crosses the closing chord: a lead move, reported
    lead = rep.families["lead_clearance"]
    assert lead.line == 5 and lead.max_residual == pytest.approx(R)
    assert {n.split(" ")[0] for n in rep.notes} == {"near-tangent", "the"}


def test_cam_contour_g42_stops_where_linuxcnc_does() -> None:
    # 200 chords: the entry is cut back past the first chord's offset end, and the outside corner
    # after it finds the reversed line (rs274: the error at line 6)
    r = _plan(_cam(200, "G42.1"))
    assert [(d.code, d.span.line) for d in r.errors] == [("LCNC-CONCAVE-GOUGE", 6)]


def test_cam_contour_g42_reversed_first_chord_is_reported() -> None:
    # 1000 chords: the same reversed first chord, but the joint after it is near-tangent, so
    # LinuxCNC runs it backwards: a real reversal, which the verification reports
    r = _plan(_cam(1000, "G42.1"))
    assert not r.errors
    tangency = r.verification.families["tangency"]
    assert tangency.max_residual >= 1.0 and tangency.line == 5
    assert r.verification.max_residual("clearance") <= 1e-9
