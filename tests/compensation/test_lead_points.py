"""The analytic lead construction sar_points (spec R37–R42) with the numbers of spec §C."""

from __future__ import annotations

import math

import pytest

from trcopt.compensation.leads import LeadSpec, lead_spec, sar_points
from trcopt.errors import AlarmError, SourceSpan
from trcopt.modes import LeadSegmentation, LeadShape, LeadSide, RetractEnd, SarContour
from trcopt.nc.model import SarSpec

G340, G341 = LeadSegmentation.SPATIAL, LeadSegmentation.PLANAR


def spec(contour: str, side: str = "G140", seg=G340, **kw) -> SarSpec:
    return SarSpec(SarContour(contour), LeadSide(side), seg, **kw)


def approx3(p, q, tol=1e-9):
    return all(abs(a - b) <= tol for a, b in zip(p, q, strict=True))


def alarm_of(exc: pytest.ExceptionInfo[AlarmError]) -> int | None:
    return exc.value.diagnostic.alarm


def test_example7_line_g340() -> None:
    g = sar_points(
        spec("G147", disr=13.0, discl=(3.0, False)),
        p0=(10, 0, 30),
        p4=(40, -10, 0),
        tangent=(1, 0),
        comp_side=1,
        radius=7.0,
    )
    assert g.line_length == pytest.approx(20.0)  # DISR + R
    assert approx3(g.p3, (20, -10, 3)) and approx3(g.p2, g.p3) and approx3(g.p1, (20, -10, 30))
    assert approx3(g.p0, (10, 0, 30)) and approx3(g.p4, (40, -10, 0))
    assert g.p3_centre == pytest.approx((20, -3)) and g.p4_centre == pytest.approx((40, -3))
    assert g.center is None and g.side == 0 and not g.helix
    # the cutter front edge is DISR before P4
    assert g.p4[0] - (g.p3_centre[0] + 7.0) == pytest.approx(13.0)


def test_example8_quadrant_g341() -> None:
    g = sar_points(
        spec("G247", seg=G341, disr=13.0, discl=(5.0, True)),
        p0=(0, 0, 20),
        p4=(40, -10, 0),
        tangent=(1, 0),
        comp_side=1,
        radius=7.0,
    )
    assert g.side == 1 and g.ccw is True
    assert g.radius_programmed == pytest.approx(20.0) and g.radius_centre == pytest.approx(13.0)
    assert g.center == pytest.approx((40, 10))
    assert approx3(g.p3, (20, 10, 0)) and approx3(g.p2, (20, 10, 5)) and approx3(g.p1, (20, 10, 20))
    assert g.p3_centre == pytest.approx((27, 10)) and g.p4_centre == pytest.approx((40, -3))
    assert not g.helix  # G341: always in the plane


def test_example9_approach_and_retraction_with_offn() -> None:
    r_eff = 10.0 + 5.0  # DP6 + OFFN
    a = sar_points(
        spec("G247", seg=G341, disr=10.0, discl=(7.0, True)),
        p0=(0, 0, 20),
        p4=(30, -10, 0),
        tangent=(1, 0),
        comp_side=1,
        radius=r_eff,
    )
    assert a.radius_programmed == pytest.approx(25.0) and a.center == pytest.approx((30, 15))
    assert approx3(a.p3, (5, 15, 0)) and approx3(a.p2, (5, 15, 7)) and approx3(a.p1, (5, 15, 20))
    assert a.p3_centre == pytest.approx((20, 15))
    r = sar_points(
        spec("G248", seg=G340, disr=5.0, discl=(6.0, False)),
        p0=(70, 0, 20),
        p4=(50, -10, 2),
        tangent=(1, 0),
        comp_side=1,
        radius=r_eff,
    )
    assert r.radius_programmed == pytest.approx(20.0) and r.center == pytest.approx((50, 10))
    assert approx3(r.p3, (70, 10, 8)) and approx3(r.p1, (70, 10, 20)) and approx3(r.p0, (70, 0, 20))
    assert r.helix and r.ccw is True and r.p3_centre == pytest.approx((55, 10))


def test_example10_semicircle_helix_g143_with_g42() -> None:
    g = sar_points(
        spec("G347", "G143", disr=6.0, discl=(2.0, False)),
        p0=(0, 30, 10),
        p4=(20, 0, -5),
        tangent=(1, 0),
        comp_side=-1,
        radius=4.0,
    )
    assert g.side == 1 and g.ccw is True  # P0 left of the tangent: cross = +30
    assert g.radius_programmed == pytest.approx(2.0)  # 6 + (−1)(+1)(4)
    assert g.center == pytest.approx((20, 2))
    assert approx3(g.p3, (20, 4, -3)) and approx3(g.p1, (20, 4, 10))
    assert g.p3_centre == pytest.approx((20, 8)) and g.p4_centre == pytest.approx((20, -4))
    assert g.helix


def test_example11_retraction_line_g341() -> None:
    g = sar_points(
        spec("G148", seg=G341, disr=10.0, discl=(2.0, False)),
        p0=(60, 20, 10),
        p4=(40, 0, 0),
        tangent=(1, 0),
        comp_side=1,
        radius=5.0,
    )
    assert g.line_length == pytest.approx(15.0)
    assert approx3(g.p3, (55, 0, 0)) and approx3(g.p2, (55, 0, 2)) and approx3(g.p1, (55, 0, 10))
    assert approx3(g.p0, (60, 20, 10)) and g.p3_centre == pytest.approx((55, 5))


@pytest.mark.parametrize(
    ("side", "comp_side", "p0", "expected"),
    [
        ("G141", 0, (0, -30, 0), 1),
        ("G142", 0, (0, 30, 0), -1),
        ("G140", 1, (0, -30, 0), 1),  # from G41 regardless of the start point
        ("G140", -1, (0, 30, 0), -1),  # from G42
        ("G140", 0, (0, -30, 0), -1),  # G40: behaves like G143
        ("G143", 1, (0, -30, 0), -1),  # automatic: P0 right of the tangent
        ("G143", -1, (0, 30, 0), 1),  # automatic: P0 left of the tangent
    ],
)
def test_circle_side_rules(side: str, comp_side: int, p0, expected: int) -> None:
    g = sar_points(
        spec("G247", side, disr=30.0),
        p0=p0,
        p4=(20, 0, 0),
        tangent=(1, 0),
        comp_side=comp_side,
        radius=4.0,
    )
    assert g.side == expected and g.ccw is (expected > 0)
    assert g.center == pytest.approx((20, expected * g.radius_programmed))


def test_g143_side_follows_a_rotated_tangent() -> None:
    t = (math.cos(0.7), math.sin(0.7))
    left = (20 - 5 * t[1], 5 * t[0], 0)  # a point on the left normal
    g = sar_points(spec("G247", "G143", disr=3.0), p0=left, p4=(20, 0, 0), tangent=t)
    assert g.side == 1
    # the quadrant ends in P4 with the tangent t: P4 − M is perpendicular to t
    m = g.center
    assert (20 - m[0]) * t[0] + (0 - m[1]) * t[1] == pytest.approx(0.0, abs=1e-12)


def test_g140_with_radius_zero_uses_the_programmed_side() -> None:
    g = sar_points(
        spec("G247", disr=5.0),
        p0=(0, 30, 0),
        p4=(20, 0, 0),
        tangent=(1, 0),
        comp_side=-1,
        radius=0.0,
    )
    assert g.side == -1 and g.radius_programmed == pytest.approx(5.0)


@pytest.mark.parametrize("discl", [None, (0.0, False), (0.0, True)])
def test_g340_discl_zero_contour_runs_from_p1(discl) -> None:
    """§D-3: P1, P2, P3 coincide at the level of P1; the helix descends all the way to P4."""
    g = sar_points(
        spec("G247", seg=G340, disr=5.0, discl=discl), p0=(0, 30, 10), p4=(20, 0, 0), tangent=(1, 0)
    )
    assert g.p1 == g.p2 == g.p3 and g.p3[2] == pytest.approx(10.0)
    assert g.helix


def test_g341_discl_zero_p2_equals_p3_in_the_plane() -> None:
    g = sar_points(
        spec("G247", seg=G341, disr=5.0, discl=(0.0, False)),
        p0=(0, 30, 10),
        p4=(20, 0, 0),
        tangent=(1, 0),
    )
    assert g.p2 == g.p3 and g.p3[2] == pytest.approx(0.0) and g.p1[2] == pytest.approx(10.0)
    assert not g.helix


def test_disrp_sets_the_level_of_p1() -> None:
    g = sar_points(
        spec("G147", disr=5.0, discl=(2.0, False), disrp=(8.0, False)),
        p0=(0, 30, 20),
        p4=(20, 0, 0),
        tangent=(1, 0),
    )
    assert g.p1[2] == pytest.approx(8.0) and g.p2[2] == pytest.approx(2.0)
    g2 = sar_points(
        spec("G147", disr=5.0, discl=(2.0, False), disrp=(12.0, True)),
        p0=(0, 30, 20),
        p4=(20, 0, 0),
        tangent=(1, 0),
    )
    assert g2.p1[2] == pytest.approx(12.0)


def test_disrp_below_the_discl_level_is_10748() -> None:
    with pytest.raises(AlarmError) as exc:
        sar_points(
            spec("G147", disr=5.0, discl=(6.0, False), disrp=(3.0, False)),
            p0=(0, 30, 20),
            p4=(20, 0, 0),
            tangent=(1, 0),
        )
    assert alarm_of(exc) == 10748


# ---- example 12: alarms -------------------------------------------------------------------------


def test_12a_internal_circle_radius_not_positive() -> None:
    with pytest.raises(AlarmError) as exc:
        sar_points(
            spec("G247", "G142", disr=8.0),
            p0=(0, -20, 5),
            p4=(30, 0, 0),
            tangent=(1, 0),
            comp_side=1,
            radius=10.0,
        )
    assert alarm_of(exc) == 10742 and exc.value.diagnostic.severity.value == "error"


@pytest.mark.parametrize(("disr", "ok"), [(-12.0, False), (-10.0, False), (-9.5, True)])
def test_12b_negative_disr_on_a_line(disr: float, ok: bool) -> None:
    kw = dict(p0=(0, 20, 5), p4=(30, 0, 0), tangent=(1, 0), comp_side=1, radius=10.0)
    if ok:
        g = sar_points(spec("G147", disr=disr), **kw)
        assert g.line_length == pytest.approx(0.5) and g.p3[0] == pytest.approx(29.5)
    else:
        with pytest.raises(AlarmError) as exc:
            sar_points(spec("G147", disr=disr), **kw)
        assert alarm_of(exc) == 10742


def test_line_without_compensation_needs_positive_disr() -> None:
    with pytest.raises(AlarmError) as exc:
        sar_points(spec("G147", disr=0.0), p0=(0, 20, 5), p4=(30, 0, 0), tangent=(1, 0))
    assert alarm_of(exc) == 10742
    g = sar_points(
        spec("G147"), p0=(0, 20, 5), p4=(30, 0, 0), tangent=(1, 0), comp_side=1, radius=4.0
    )
    assert g.line_length == pytest.approx(4.0)  # assumption: missing DISR on a line counts as 0


@pytest.mark.parametrize("disr", [None, 0.0, -3.0])
def test_12c_circle_disr_missing_or_not_positive(disr) -> None:
    with pytest.raises(AlarmError) as exc:
        sar_points(
            spec("G347", "G141", disr=disr),
            p0=(0, 20, 5),
            p4=(30, 0, 0),
            tangent=(1, 0),
            comp_side=1,
            radius=10.0,
        )
    assert alarm_of(exc) == 10742


def test_12d_direction_reversal_and_snap() -> None:
    kw = dict(
        p0=(0, 20, 20),
        p4=(30, 0, 0),
        tangent=(1, 0),
        comp_side=1,
        radius=5.0,
        span=SourceSpan("p.mpf", 3, 1, "N20"),
    )
    with pytest.raises(AlarmError) as exc:
        sar_points(spec("G247", seg=G341, disr=10.0, discl=(25.0, True)), **kw)
    assert alarm_of(exc) == 10741 and exc.value.diagnostic.span.block == "N20"
    g = sar_points(spec("G247", seg=G341, disr=10.0, discl=(20.005, True)), **kw)
    assert g.snapped and g.p2[2] == 20.0 and g.p1[2] == 20.0
    with pytest.raises(AlarmError):  # a tighter MD20204 makes the same program an alarm
        sar_points(
            spec("G247", seg=G341, disr=10.0, discl=(20.005, True)), clearance_tolerance=0.001, **kw
        )


def test_snap_below_the_machining_plane() -> None:
    g = sar_points(
        spec("G147", seg=G341, disr=5.0, discl=(-0.004, False)),
        p0=(0, 20, 20),
        p4=(30, 0, 0),
        tangent=(1, 0),
    )
    assert g.snapped and g.p2[2] == 0.0
    with pytest.raises(AlarmError) as exc:
        sar_points(
            spec("G147", seg=G341, disr=5.0, discl=(-1.0, False)),
            p0=(0, 20, 20),
            p4=(30, 0, 0),
            tangent=(1, 0),
        )
    assert alarm_of(exc) == 10741


@pytest.mark.parametrize("side", ["G143", "G140"])
@pytest.mark.parametrize("end", [RetractEnd.NONE, RetractEnd.APPLICATE_ONLY])
def test_12f_automatic_side_on_retraction_needs_an_end_point(side: str, end: RetractEnd) -> None:
    with pytest.raises(AlarmError) as exc:
        sar_points(
            spec("G248", side, disr=10.0, discl=(2.0, False)),
            p0=(40, 0, 0),
            p4=(40, 0, 0),
            tangent=(1, 0),
            retract_end=end,
        )
    assert alarm_of(exc) == 10747


def test_g143_retraction_with_programmed_end_point() -> None:
    g = sar_points(spec("G248", "G143", disr=10.0), p0=(60, -20, 0), p4=(40, 0, 0), tangent=(1, 0))
    assert g.side == -1 and g.ccw is False and approx3(g.p3, (50, -10, 0))


def test_retraction_end_modes() -> None:
    """R45: no geometry axis → ends in P2; only the applicate → ends in P1."""
    kw = dict(p4=(40, 0, 0), tangent=(1, 0), comp_side=1, radius=5.0)
    g = sar_points(
        spec("G148", seg=G341, disr=10.0, discl=(2.0, False)),
        p0=(40, 0, 0),
        retract_end=RetractEnd.NONE,
        **kw,
    )
    assert approx3(g.p0, (55, 0, 2)) and g.p0 == g.p1 == g.p2
    g = sar_points(
        spec("G148", seg=G341, disr=10.0, discl=(2.0, False)),
        p0=(40, 0, 30),
        retract_end=RetractEnd.APPLICATE_ONLY,
        **kw,
    )
    assert approx3(g.p0, (55, 0, 30)) and g.p0 == g.p1
    g = sar_points(
        spec("G148", seg=G341, disr=10.0), p0=(40, 0, 0), retract_end=RetractEnd.NONE, **kw
    )
    assert g.p0 == g.p3  # DISCL = 0: entirely in the plane


def test_lead_spec_is_dialect_neutral() -> None:
    lead = lead_spec(spec("G348", "G142", G341, disr=4.0, discl=(3.0, True), disrp=(9.0, False)))
    assert lead == LeadSpec(
        LeadShape.SEMICIRCLE, False, LeadSide.RIGHT, LeadSegmentation.PLANAR, 4.0, 3.0, True, 9.0, False
    )
    assert lead_spec(lead) is lead
    g = sar_points(lead, p0=(0, 0, 0), p4=(10, 0, 0), tangent=(2, 0))  # tangent is normalised
    assert g.center == pytest.approx((10, -4)) and approx3(g.p3, (10, -8, 0)) and g.p2[2] == 3.0
    assert g.p1[2] == 9.0  # DISRP incremental from the machining plane


def test_zero_tangent_is_10744() -> None:
    with pytest.raises(AlarmError) as exc:
        sar_points(spec("G147", disr=1.0), p0=(0, 0, 0), p4=(10, 0, 0), tangent=(0, 0))
    assert alarm_of(exc) == 10744
