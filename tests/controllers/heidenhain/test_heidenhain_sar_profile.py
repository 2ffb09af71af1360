"""APPR/DEP geometry of spec §7/§10 (H4-H7, E5, E6, R9 alternative) and the heidenhain profile."""

from __future__ import annotations

import pytest

from trcopt import controllers
from trcopt.compensation.profiles import compensate_with_profile, map_diagnostic
from trcopt.controllers.heidenhain import appr_dep as sar
from trcopt.controllers.heidenhain.profile import HEIDENHAIN
from trcopt.controllers.heidenhain.reader import read_heidenhain
from trcopt.controllers.heidenhain.state import HeidenhainOptions
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.modes import ApprRadius

UP = (0.0, 1.0)  # first element at PA = (0, 20) runs +Y; RL: tool side is -X


def pts(lead):
    return [(p.start, p.end, p.center) for p in lead.centre]


def test_appr_lt_h4():
    lead = sar.appr_lt((-20, -20), (0, 0), UP, 1, 5.0, 10.0)
    assert lead.points["PH"] == pytest.approx((0, -10))
    assert [q[1] for q in pts(lead)] == [pytest.approx((-5, -10)), pytest.approx((-5, 0))]


def test_appr_ln_and_dep_ln_h5():
    lead = sar.appr_ln((-30, 20), (0, 20), UP, 1, 5.0, 10.0)
    assert [q[1] for q in pts(lead)] == [pytest.approx((-15, 20)), pytest.approx((-5, 20))]
    assert sar.dep_ln((0, 20), UP, 1, 5.0, 10.0).points["PN"] == pytest.approx((-15, 20))


def test_dep_lt_h4():
    assert sar.dep_lt((0, 0), (-1, 0), 1, 5.0, 12.0).points["PN"] == pytest.approx((-12, -5))


def test_appr_ct_and_dep_ct_h6():
    lead = sar.appr_ct((-30, 0), (0, 20), UP, 1, 5.0, 90.0, 10.0)
    (s0, e0, _), (s1, e1, c1) = pts(lead)
    assert (
        e0 == pytest.approx((-10, 15))
        and c1 == pytest.approx((-10, 20))
        and e1 == pytest.approx((-5, 20))
    )
    assert lead.centre[1].ccw is True
    dep = sar.dep_ct((0, 20), UP, 1, 5.0, 90.0, 10.0)
    assert dep.points["PN"] == pytest.approx((-10, 25)) and dep.centre[0].ccw is True


def test_appr_ct_centre_reading_r9_h6():
    lead = sar.appr_ct((-30, 0), (0, 20), UP, 1, 5.0, 90.0, 10.0, radius_ref="centre")
    assert lead.points["M"] == pytest.approx((-15, 20)) and lead.centre[0].end == pytest.approx(
        (-15, 10)
    )


def test_appr_lct_and_dep_lct_h7():
    lead = sar.appr_lct((-30, 0), (0, 20), UP, 1, 5.0, 10.0)
    assert lead.centre[0].end == pytest.approx((-7.1451, 15.8951), abs=1e-4)
    dep = sar.dep_lct((0, 20), UP, 1, 5.0, (-30, 40), 10.0)
    assert dep.centre[0].end == pytest.approx((-7.1451, 24.1049), abs=1e-4)
    assert dep.centre[1].end == pytest.approx((-30, 40))


def test_appr_lct_centre_reading_r9_h7():
    lead = sar.appr_lct((-30, 0), (0, 20), UP, 1, 5.0, 10.0, radius_ref="centre")
    assert lead.points["M"] == pytest.approx((-15, 20))
    assert lead.centre[0].end == pytest.approx((-10.0679, 11.3009), abs=1e-4)


def test_appr_ct_material_side_e6():
    lead = sar.appr_ct((30, 0), (0, 20), UP, 1, 5.0, 90.0, -10.0)
    assert lead.points["M"] == pytest.approx((10, 20))
    assert lead.centre[0].end == pytest.approx((10, 5)) and lead.centre[1].ccw is False
    assert lead.centre[1].end == pytest.approx((-5, 20))


@pytest.mark.parametrize(
    ("call", "code"),
    [
        (
            lambda: sar.appr_ct((-30, 0), (0, 20), UP, 1, 5.0, 90.0, 4.0),
            "HH-TOOL-RADIUS-TOO-LARGE",
        ),  # E5
        (lambda: sar.appr_ct((-30, 0), (0, 20), UP, 1, 5.0, 0.0, 10.0), "HH-APPR-CCA"),
        (lambda: sar.appr_ct((-30, 0), (0, 20), UP, 1, 5.0, 361.0, 10.0), "HH-APPR-CCA"),
        (lambda: sar.appr_lct((-11, 21), (0, 20), UP, 1, 5.0, 10.0), "HH-APPR-NO-TANGENT"),
        (
            lambda: sar.appr_lct((-30, 0), (0, 20), UP, 1, 9.0, 9.0),
            "HH-TOOL-RADIUS-TOO-LARGE",
        ),  # H28 / R9
    ],
)
def test_lead_errors(call, code):
    with pytest.raises(sar.LeadError) as info:
        call()
    assert info.value.code == code


def test_appr_lct_r9_with_radius_equal_to_tool_works_in_centre_reading():
    lead = sar.appr_lct((-30, 0), (0, 20), UP, 1, 9.0, 9.0, radius_ref="centre")
    assert lead.points["M"] == pytest.approx((-18, 20))


# --- profile --------------------------------------------------------------------------------------
def test_profile_data():
    assert controllers.get("heidenhain").compensate.__module__ == "trcopt.controllers.heidenhain"
    s = HEIDENHAIN.engine_settings()
    assert s.cutcom_curve_insert_limit_deg == 0.0 and s.cutcom_corner_limit_deg == 180.0 and s.strict is True
    assert HeidenhainOptions().appr_radius is ApprRadius.CENTRE
    assert HeidenhainOptions(appr_radius="centre").appr_radius is ApprRadius.CENTRE  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="valid: contour, centre"):
        HeidenhainOptions(appr_radius="tool")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="valid: .*heidenhain.*linuxcnc.*rs274.*siemens"):
        controllers.get("fanuc")


@pytest.mark.parametrize("key", ["10751", "10763", "TRC-CONTOUR-VIOLATION"])
def test_engine_alarms_read_as_tool_radius_too_large(key):
    alarm = int(key) if key.isdigit() else None
    d = Diagnostic(Severity.WARNING, key, "engine text", SourceSpan("p.h", 7, 1, "6"), alarm)
    m = map_diagnostic(HEIDENHAIN, d)
    assert (m.severity, m.code, m.span.block) == (Severity.ERROR, "HH-TOOL-RADIUS-TOO-LARGE", "6")
    assert m.message.startswith("Tool radius too large")


def test_compensate_with_profile_small_deflection_gets_the_transition_arc():
    # a 5° outside corner: SINUMERIK's curve-insert limit would intersect, the TNC inserts the arc
    text = (
        "0 BEGIN PGM T MM\n1 TOOL DEF 1 R+5\n2 TOOL CALL 1 Z\n3 L X-10 Y+10 R0 FMAX\n4 L X+0 Y+0 RR F100\n"
        "5 L X+50 Y+0\n6 L X+100 Y+4.3744\n7 L X+120 Y+20 R0\n8 END PGM T MM\n"
    )
    p = read_heidenhain(text)
    diags: list[Diagnostic] = []
    segs = list(compensate_with_profile(p.moves, HEIDENHAIN, None, diags))
    assert not diags
    assert [s.role.value for s in segs if s.span.block == "6"][0] == "corner"


def test_compensate_with_profile_maps_a_bottleneck_to_an_error():
    # pocket 40 x 30 with r = 16: offsets reverse; the engine alone only warns under CDOF
    text = (
        "0 BEGIN PGM T MM\n1 TOOL DEF 1 R+16\n2 TOOL CALL 1 Z\n3 L X+30 Y+25 R0 FMAX\n4 L X+30 Y+10 RL F200\n"
        "5 L X+50 Y+10\n6 L X+50 Y+40\n7 L X+10 Y+40\n8 L X+10 Y+10\n9 L X+30 Y+10\n10 L X+30 Y+25 R0\n"
        "11 END PGM T MM\n"
    )
    from trcopt.controllers.heidenhain import reader as hh

    reader = hh.HeidenhainReader("p.h")
    reader._check_radius = lambda: None  # type: ignore[method-assign]  # engine path only
    p = reader.read(text)
    diags: list[Diagnostic] = []
    list(compensate_with_profile(p.moves, HEIDENHAIN, None, diags))
    assert (
        diags and diags[0].code == "HH-TOOL-RADIUS-TOO-LARGE" and diags[0].severity is Severity.ERROR
    )
