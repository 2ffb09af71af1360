"""TRC rules of sinumerik_trc.md R3–R30 beyond the worked examples, through the Siemens front end."""

from __future__ import annotations

import math

import pytest

from trcopt.config import TrcSettings
from trcopt.geometry import Arc, Poly
from trcopt.pipeline import PlanOptions, plan

TOOL = "$TC_DP1[1,1]=120 $TC_DP6[1,1]=5 $TC_DP6[1,2]=3 $TC_DP15[1,2]=0.5\n"


def run(text: str, **settings):
    opts = PlanOptions(timing=False, settings=TrcSettings(**settings)) if settings else PlanOptions(timing=False)
    return plan(TOOL + text, file="t.mpf", options=opts)


def path(result):
    return [(s.kind, s.span.block, s.start_xyz, s.end_xyz) for s in result.toolpath]


def approx(p, q, tol=1e-6):
    return all(abs(a - b) <= tol for a, b in zip(p, q, strict=True))


def codes(result):
    return [(d.severity.value, d.code, d.span.block) for d in result.diagnostics]


def test_variable_radius_line_then_spiral_r9() -> None:
    r = run("N10 T1 D1 G0 X-10 Y10\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 X40 D2\nN50 G2 X60 Y0 I10 J0 D1\nM30\n")
    segs = r.toolpath
    n40 = [s for s in segs if s.span.block == "N40"][0]
    # the radius changes from 5 (D1) to 3 + 0.5 (D2 with wear) over N40: a slanted line; its end is the
    # intersection of y = 3.5 with N50's start offset (radius 10 + 3.5 around (50, 0)), R9
    assert approx(n40.start_xyz, (20, 5, 0)) and approx(n40.end_xyz, (50 - math.sqrt(13.5**2 - 3.5**2), 3.5, 0))
    n50 = [s for s in segs if s.span.block == "N50"][0]
    assert isinstance(n50.geometry, Poly)  # a spiral from radius 13.5 to 15
    assert approx(n50.end_xyz, (65, 0, 0), 1e-9)
    assert abs(math.dist(n50.geometry.points[len(n50.geometry.points) // 2][:2], (50, 0)) - 14.25) < 0.1


def test_dummy_blocks_run_at_the_transition_circle_start_r12() -> None:
    r = run(
        "N10 T1 D1 G0 X-10 Y-10\nN20 G1 G41 X0 Y0 F100\nN30 Y20\nN40 Z-2\nN50 M8\nN60 X20\nN70 Z-4\nN80 Y0\n"
        "N90 X0\nN100 G40 X-10 Y-10\nM30\n"
    )
    p = path(r)
    as_floats = [(k, b, tuple(map(float, s)), tuple(map(float, e))) for k, b, s, e in p]
    assert ("line", "N40", (-5.0, 20.0, 0.0), (-5.0, 20.0, -2.0)) in as_floats
    corner_n60 = [s for s in r.toolpath if s.span.block == "N60" and s.role.value == "corner"][0]
    assert approx(corner_n60.start_xyz, (-5, 20, -2)) and approx(corner_n60.geometry.center, (0, 20))
    z_n70 = [s for s in r.toolpath if s.span.block == "N70"][0]
    assert approx(z_n70.start_xyz, (20, 25, -2)) and approx(z_n70.end_xyz, (20, 25, -4))
    assert r.ok and not r.warnings


def test_too_many_dummy_blocks_10762_and_the_setting() -> None:
    text = (
        "N10 T1 D1 G0 X-10 Y10\nN20 G1 G41 X0 Y0 F100\nN30 M8\nN40 M9\nN50 M8\nN60 M9\nN70 X20\n"
        "N80 G40 X30 Y10\nM30\n"
    )
    assert ("error", "10762", "N60") in codes(run(text))
    assert run(text, cutcom_maxnum_dummy_blocks=4).ok


def test_offn_and_d0() -> None:
    r = run(
        "N10 T1 D1 G0 X-10 Y10 OFFN=2\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 G40 X30 Y10\n"
        "N50 D0 G0 X-10 Y10\nN60 G1 G41 X0 Y0\nN70 X20\nN80 G40 X30 Y10\nM30\n"
    )
    n30 = [s for s in r.toolpath if s.span.block == "N30"][0]
    assert approx(n30.start_xyz, (0, 7, 0)) and n30.radius == 7.0  # R = DP6 + OFFN = 5 + 2
    n70 = [s for s in r.toolpath if s.span.block == "N70"][0]
    assert approx(n70.start_xyz, (0, 0, 0)) and approx(n70.end_xyz, (20, 0, 0))  # D0: radius 0


def test_helix_is_offset_in_the_plane_only() -> None:
    r = run("N10 T1 D1 G0 X-10 Y0 Z0\nN20 G1 G41 X0 Y0 F100\nN30 G3 X0 Y0 Z-3 I20 J0\nN40 G40 G1 X-10 Y0\nM30\n")
    helix = [s for s in r.toolpath if s.span.block == "N30"][0].geometry
    assert isinstance(helix, Arc) and helix.radius == pytest.approx(15.0)  # G41 + G3: 20 − 5
    assert helix.sweep == pytest.approx(2 * math.pi) and (helix.w0, helix.w1) == (0.0, -3.0)


def test_kontc_and_kontt_are_tangent_polynomials_r20() -> None:
    r = run(
        "N10 T1 D1 G0 X-20 Y-10\nN20 G1 G41 KONTC X0 Y0 F100\nN30 G3 X20 Y20 I0 J20\nN40 G1 X40\n"
        "N50 KONTT G40 X60 Y0\nM30\n"
    )
    approach, arc = r.toolpath[1], r.toolpath[2]
    assert isinstance(approach.geometry, Poly) and approach.role.value == "approach"
    assert approx(approach.end_xyz, (0, 5, 0))  # S = P1 + R·n1
    t_poly = approach.geometry.end_tangent()
    assert approx(t_poly, arc.geometry.start_tangent(), 1e-9)
    retract = r.toolpath[-1]
    assert isinstance(retract.geometry, Poly) and approx(retract.end_xyz, (60, 0, 0))
    assert approx(retract.geometry.start_tangent(), (1.0, 0.0), 1e-9)


@pytest.mark.parametrize("disc", [0, 25, 50, 90])
def test_disc_conic_midpoint_r22(disc: int) -> None:
    # [A] R22: the curve's mid-point lies at R + DISC/100 · (R/cos(|δ|/2) − R) from the corner
    text = f"N10 T1 D1 G0 X-10 Y-10\nN20 G1 G41 DISC={disc} X0 Y0 F100\nN30 Y20\nN40 X20\nN50 G40 X30 Y30\nM30\n"
    r = run(text, cutcom_max_disc=100)
    corner = [s for s in r.toolpath if s.role.value == "corner"][0]
    g = corner.geometry
    mid = g.point(g.length / 2)
    expected = 5 + disc / 100 * (5 * math.sqrt(2) - 5)
    assert math.dist(mid[:2], (0, 20)) == pytest.approx(expected, abs=1e-3)
    assert approx(corner.start_xyz, (-5, 20, 0), 1e-9) and approx(corner.end_xyz, (0, 25, 0), 1e-9)


def test_disc_100_is_the_intersection_and_disc_is_clamped_to_md20220() -> None:
    text = "N10 T1 D1 G0 X-10 Y-10\nN20 G1 G41 DISC=100 X0 Y0 F100\nN30 Y20\nN40 X20\nN50 G40 X30 Y30\nM30\n"
    sharp = run(text, cutcom_max_disc=100)
    assert not [s for s in sharp.toolpath if s.role.value == "corner"]
    assert approx(sharp.toolpath[2].end_xyz, (-5, 25, 0))
    clamped = run(text)  # MD20220 = 50
    assert any(d.code == "NC-DISC-CLAMPED" for d in clamped.diagnostics)
    corner = [s for s in clamped.toolpath if s.role.value == "corner"][0]
    mid = corner.geometry.point(corner.geometry.length / 2)
    assert math.dist(mid[:2], (0, 20)) == pytest.approx(5 + 0.5 * (5 * math.sqrt(2) - 5), abs=1e-3)


def test_selection_without_plane_axes_is_deferred_r3_4() -> None:
    r = run("N10 T1 D1 G0 X-10 Y-10\nN20 G41 Z5\nN30 G1 X0 Y0 F100\nN40 Y20\nN50 G40 X-10 Y30\nM30\n")
    kinds = [(s.role.value, s.span.block) for s in r.toolpath]
    assert kinds[1] == ("rapid", "N20") and kinds[2] == ("approach", "N30")
    assert approx(r.toolpath[2].end_xyz, (-5, 0, 5))


def test_g40_right_after_selection_means_no_selection_r3_5() -> None:
    r = run("N10 T1 D1 G0 X-10 Y-10\nN20 G1 G41 X0 Y0 F100\nN30 G40 X10 Y10\nM30\n")
    assert [approx(s.end_xyz, e) for s, e in zip(r.toolpath[1:], [(0, 0, 0), (10, 10, 0)], strict=True)] == [True, True]
    assert all(s.radius == 0 for s in r.toolpath)


def test_kont_start_within_radius_10755() -> None:
    r = run("N10 T1 D1 G0 X3 Y-2\nN20 G1 G41 KONT X0 Y0 F100\nN30 Y20\nN40 G40 X-10 Y30\nM30\n")
    assert ("error", "10755", "N20") in codes(r)


def test_g18_compensation_in_z_x() -> None:
    r = run(
        "N10 T1 D1 G18 G0 Z-10 X-10\nN20 G1 G41 Z0 X0 F100\nN30 Z20\nN40 G2 Z30 X10 K10 I0\nN50 G1 X20\n"
        "N60 G40 Z40 X30\nM30\n"
    )
    n30 = [s for s in r.toolpath if s.span.block == "N30"][0]
    assert approx(n30.start_xyz, (5, 0, 0)) and approx(n30.end_xyz, (5, 0, 30 - math.sqrt(15**2 - 5**2)))
    arc = [s for s in r.toolpath if s.span.block == "N40"][0]
    assert arc.plane.value == "G18" and arc.geometry.radius == pytest.approx(15.0)
    assert approx(arc.center_xyz, (0, 0, 30))


def test_side_change_without_g40_is_an_error_r5() -> None:
    r = run("N10 T1 D1 G0 X-10 Y-10\nN20 G1 G41 X0 Y0 F100\nN30 Y20\nN40 G42 X20\nN50 G40 X30 Y30\nM30\n")
    assert ("error", "TRC-SIDE-CHANGE", "N40") in codes(r)


def test_reversal_is_an_outside_corner_with_a_half_circle() -> None:
    r = run("N10 T1 D1 G0 X-10 Y-10\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 X10\nN50 G40 X0 Y-10\nM30\n")
    corner = [s for s in r.toolpath if s.role.value == "corner"][0]
    assert approx(corner.start_xyz, (20, 5, 0)) and approx(corner.end_xyz, (20, -5, 0))
    assert corner.geometry.sweep == pytest.approx(-math.pi)


def test_degenerate_arc_omitted_with_cdon_alarm_with_cdof_r30() -> None:
    text = (
        "N10 T1 D1 G0 X-10 Y10 {mode}\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 G3 X26 Y0 I3 J0\nN50 G1 X40\n"
        "N60 G40 X50 Y10\nM30\n"
    )
    on = run(text.format(mode="CDON"))
    assert codes(on) == [("warning", "10763", "N40")]
    assert approx(on.toolpath[2].end_xyz, (26, 5, 0))
    off = run(text.format(mode="CDOF"))
    assert ("error", "10751", "N40") in codes(off)


def test_predictive_search_omits_blocks_r25_3_and_check_blocks_setting() -> None:
    # a 2 mm step down and back up: with R = 5 the inside corners have no adjacent intersection
    text = (
        "N10 T1 D1 G0 X-10 Y10\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 Y-2\nN50 X22\nN60 Y0\nN70 X40\n"
        "N80 G40 X50 Y10\nM30\n"
    )
    r = run(text)
    assert r.ok, codes(r)
    # N40's transition circle around (20, 0) meets N70's around (22, 0) at (21, √24): N50, N60 omitted
    arcs = [s for s in r.toolpath if s.kind == "arc"]
    assert [s.span.block for s in arcs] == ["N40", "N70"]
    meet = (21, math.sqrt(24), 0)
    assert approx(arcs[0].end_xyz, meet, 1e-9) and approx(arcs[1].start_xyz, meet, 1e-9)
    assert codes(r) == [("warning", "10763", "N50"), ("warning", "10763", "N60")]
    # with a look-ahead of 2 blocks (MD20240) N70 is out of reach: alarm 10751
    assert ("error", "10751", "N40") in codes(run(text, cutcom_maxnum_check_blocks=2))


def test_suppress_10763_setting() -> None:
    text = (
        "N10 T1 D1 G0 X-10 Y10 CDON\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 G3 X26 Y0 I3 J0\nN50 G1 X40\n"
        "N60 G40 X50 Y10\nM30\n"
    )
    assert run(text, suppress_10763=True).diagnostics == []


def test_strict_mode_turns_cdof_reversal_into_10751() -> None:
    text = (
        "N10 T1 D1 G0 X-10 Y10\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 Y-20\nN50 X26\nN60 Y0\nN70 X50\n"
        "N80 G40 X60 Y10\nM30\n"
    )
    assert ("error", "10751", "N50") in codes(run(text, strict=True))
