"""The 15 worked examples E0–E14 of spec/toolholder.md §11 with their numbers.

Angles are asserted to 1e-9 deg where the spec gives exact values, to the printed digits
otherwise; every returned exact solution is forward-evaluated back to the requested direction
(|d_rel − d| < 1e-9, REQ-TH-08).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from trcopt.errors import AlarmError, TrcoptError
from trcopt.kinematics import (
    Carrier,
    KinematicType,
    SolutionKind,
    carrier_from_assignments,
    inverse_solutions,
    machine_position,
    relative_direction,
    resulting_tool_length,
    rpy_matrix,
    solve_orientation,
    table_offset,
    tcoabs_angles,
    tool_length_vector,
)

Z = np.array([0.0, 0.0, 1.0])
L100 = (0.0, 0.0, 100.0)

E2 = Carrier(
    v1=(0, 0, 1), v2=(1, 0, 0), l3=(0, 0, 150), l2=(0, 20, 50), l1=(0, -20, -200)
)
E3 = Carrier(
    kinematic_type=KinematicType.P,
    v1=(0, 1, 0),
    v2=(0, 0, 1),
    l2=(50, 0, -80),
    l3=(0, 0, 30),
    l4=(-50, 0, 50),
)
E4 = Carrier(v1=(0, 0, 1), v2=(0, 1, 1))
E5 = Carrier(
    kinematic_type=KinematicType.M,
    v1=(0, 1, 0),
    v2=(0, 0, 1),
    l1=(0, 0, -120),
    l2=(0, 0, 120),
    l3=(100, 50, -200),
    l4=(-100, -50, 200),
)


def assert_forward_exact(carrier: Carrier, inv, base=Z) -> None:
    """Every exact pair maps forward to the requested direction to 1e-9."""
    d = np.asarray(inv.direction)
    for p in inv.pairs:
        got = relative_direction(carrier, p.angle1, p.angle2, base)
        assert np.linalg.norm(got - d) < 1e-9, (p, got, d)


def pairs(sel) -> list[tuple[float, float]]:
    return [p.angles for p in sel.ordered]


# ---- E0, E1: validation against the manual -----------------------------------------------------


def test_e0_mixed_cutmod_turning_tool_g18() -> None:
    c = carrier_from_assignments({8: 1.0, 12: 1.0, 13: 30.0, 23: "M"}, 1)
    sel = tcoabs_angles(c)
    assert sel.chosen == (30.0, 0.0)
    lt = tool_length_vector((12.0, 1.0), "G18", "turning")
    np.testing.assert_allclose(lt, (12.0, 0.0, 1.0), atol=1e-12)
    res = resulting_tool_length(c, *sel.chosen, lt)
    exact = (12 * math.cos(math.radians(30)) + 0.5, 0.0, -6.0 + math.cos(math.radians(30)))
    np.testing.assert_allclose(res, exact, atol=1e-12)
    np.testing.assert_allclose(res, (10.892, 0.0, -5.134), atol=5e-4)


def test_e1_rotary_table_program_zero_shift_and_position() -> None:
    c = carrier_from_assignments(
        {23: "P", 7: 1.0, 11: 1.0, 6: -15.0, 20: 15.0, 13: 0.0, 14: 45.0}, 1
    )
    sel = tcoabs_angles(c)
    delta = table_offset(c, *sel.chosen)
    h = 15 * math.sqrt(0.5)
    np.testing.assert_allclose(delta, (h, 0.0, h - 15.0), atol=1e-12)
    np.testing.assert_allclose(delta, (10.6066, 0.0, -4.3934), atol=1e-4)
    pos = machine_position(c, *sel.chosen, (0.0, 10.0, 0.0), (0.0, 0.0, 13.0))
    np.testing.assert_allclose(pos, (10.607, 10.000, 8.607), atol=5e-4)


def test_e1_without_closure_gives_the_other_offset() -> None:
    c = Carrier(kinematic_type=KinematicType.P, v1=(1, 0, 0), v2=(0, 1, 0), l4=(0, 0, 15))
    np.testing.assert_allclose(table_offset(c, 0, 45), (10.6066, 0.0, 10.6066), atol=1e-4)


# ---- E2: A/C fork head --------------------------------------------------------------------------


def test_e2_fork_head_two_solutions_and_tool_vectors() -> None:
    sel = solve_orientation(E2, frame=(30, 0, 0))
    np.testing.assert_allclose(sel.inverse.direction, (0, -0.5, math.sqrt(3) / 2), atol=1e-15)
    assert sel.inverse.kind is SolutionKind.TWO
    np.testing.assert_allclose(pairs(sel), [(0, 30), (180, -30)], atol=1e-9)
    assert_forward_exact(E2, sel.inverse)
    np.testing.assert_allclose(
        resulting_tool_length(E2, 0, 30, L100), (0, -125.0, 66.5064), atol=1e-4
    )
    np.testing.assert_allclose(
        resulting_tool_length(E2, 180, -30, L100), (0, -165.0, 66.5064), atol=1e-4
    )
    np.testing.assert_allclose(resulting_tool_length(E2, 0, 0, L100), L100, atol=1e-12)
    np.testing.assert_allclose(sel.p_tcang, (0, 30, 180, -30), atol=1e-9)
    assert sel.tcang0 == 2 and sel.tcsol == 2 and not sel.swapped


def test_e2_reference_flips_the_order() -> None:
    sel = solve_orientation(E2, frame=(30, 0, 0), reference=(170, -20))
    np.testing.assert_allclose(pairs(sel), [(180, -30), (0, 30)], atol=1e-9)
    np.testing.assert_allclose(sel.chosen, (180, -30), atol=1e-9)


# ---- E3: B/C trunnion table ---------------------------------------------------------------------


def test_e3_trunnion_table() -> None:
    sel = solve_orientation(E3, frame=(0, 40, 30))
    np.testing.assert_allclose(sel.inverse.direction, (0.556670, 0.321394, 0.766044), atol=1e-6)
    np.testing.assert_allclose(pairs(sel), [(-40, -30), (40, 150)], atol=1e-9)
    assert_forward_exact(E3, sel.inverse)
    np.testing.assert_allclose(table_offset(E3, -40, -30), (-34.5937, 25.0, -46.5500), atol=1e-4)
    np.testing.assert_allclose(table_offset(E3, 40, 150), (134.5937, -25.0, -46.5500), atol=1e-4)
    # the part rotates, the tool does not: L_res = L_tool for type P
    np.testing.assert_allclose(resulting_tool_length(E3, -40, -30, L100), L100)


# ---- E4: nutating head --------------------------------------------------------------------------


def _tilt_y(deg: float) -> np.ndarray:
    return rpy_matrix(0, deg, 0) @ Z


def test_e4_nutating_head_tilt_60() -> None:
    inv = inverse_solutions(E4, _tilt_y(60))
    assert inv.kind is SolutionKind.TWO
    got = sorted(p.angles for p in inv.pairs)
    c = math.degrees(math.atan(1 / math.sqrt(2)))  # 35.2644 deg
    np.testing.assert_allclose(got, [(-180 + c, -90), (-c, 90)], atol=1e-9)
    np.testing.assert_allclose(got, [(-144.7356, -90), (-35.2644, 90)], atol=1e-4)
    assert_forward_exact(E4, inv)
    # the spec's check: R(v2, 90)·ez = (0.7071, 0.5, 0.5)
    from trcopt.kinematics import rotation

    np.testing.assert_allclose(rotation((0, 1, 1), 90) @ Z, (math.sqrt(0.5), 0.5, 0.5), atol=1e-15)


def test_e4_boundary_tilt_90_single_solution() -> None:
    inv = inverse_solutions(E4, (1.0, 0.0, 0.0))
    assert inv.kind is SolutionKind.ONE and inv.count == 1
    np.testing.assert_allclose(inv.pairs[0].angles, (-90, 180), atol=1e-9)
    assert_forward_exact(E4, inv)
    sel = solve_orientation(E4, direction=(1, 0, 0))
    assert sel.tcang0 == 1 and sel.tcsol == 1
    assert math.isnan(sel.p_tcang[2]) and math.isnan(sel.p_tcang[3])


def test_e4_tilt_120_unreachable() -> None:
    inv = inverse_solutions(E4, _tilt_y(120))
    assert inv.kind is SolutionKind.NONE and inv.pairs == ()
    assert inv.gamma2 < 0
    with pytest.raises(AlarmError) as ei:
        solve_orientation(E4, direction=_tilt_y(120))
    assert ei.value.diagnostic.code == "TH-UNREACHABLE"
    assert "toolholder 1" in ei.value.diagnostic.message


# ---- E5: mixed head + table ---------------------------------------------------------------------


def test_e5_mixed_kinematics() -> None:
    sel = solve_orientation(E5, frame=(30, 0, 45))
    np.testing.assert_allclose(sel.inverse.direction, (0.353553, -0.353553, 0.866025), atol=1e-6)
    np.testing.assert_allclose(pairs(sel), [(30, 45), (-30, -135)], atol=1e-9)
    assert_forward_exact(E5, sel.inverse)
    np.testing.assert_allclose(
        resulting_tool_length(E5, 30, 45, L100), (110, 0, 70.5256), atol=1e-4
    )
    np.testing.assert_allclose(table_offset(E5, 30, 45), (64.6447, -56.0660, 0), atol=1e-4)
    np.testing.assert_allclose(
        resulting_tool_length(E5, -30, -135, L100), (-110, 0, 70.5256), atol=1e-4
    )
    np.testing.assert_allclose(table_offset(E5, -30, -135), (135.3553, 156.0660, 0), atol=1e-4)


# ---- E6: singular poses -------------------------------------------------------------------------


def test_e6_free_angle_kept_at_specified() -> None:
    sel = solve_orientation(E2, direction=(0, 0, 1), reference=(37, 5))
    assert sel.inverse.kind is SolutionKind.FREE and sel.tcang0 == 1
    p = sel.inverse.pairs[0]
    assert p.free1 and not p.free2
    assert sel.chosen[0] == 37.0
    assert sel.chosen[1] == pytest.approx(0.0, abs=1e-9)
    assert_forward_exact(E2, sel.inverse)


def test_e6_parallel_axes_infinite_and_none() -> None:
    par = Carrier(v1=(0, 0, 1), v2=(0, 0, 2))
    inv = inverse_solutions(par, Z, reference=(12.0, -7.0))
    assert inv.kind is SolutionKind.INFINITE and inv.count == 1
    assert inv.pairs[0].angle1 == 12.0  # kept at the specified angle
    assert_forward_exact(par, inv)
    inv = inverse_solutions(par, rpy_matrix(10, 0, 0) @ Z)
    assert inv.kind is SolutionKind.NONE


def test_parallel_axes_infinite_with_tilt_solves_the_sum() -> None:
    # two parallel tilting axes (about Y): only α1 + α2 is fixed
    par = Carrier(v1=(0, 1, 0), v2=(0, -3, 0))
    d = rpy_matrix(0, 50, 0) @ Z
    inv = inverse_solutions(par, d, reference=(20.0, 0.0))
    assert inv.kind is SolutionKind.INFINITE
    a1, a2 = inv.pairs[0].angles
    assert a1 == 20.0
    assert a2 == pytest.approx(-30.0, abs=1e-9)  # v2 points along −Y
    assert_forward_exact(par, inv)


# ---- E7: 360° shift -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("computed", "specified", "expected"), [(10, 750, 730), (-170, 200, 190), (190, -100, -170)]
)
def test_e7_shift_toward_specified(computed: float, specified: float, expected: float) -> None:
    from trcopt.kinematics import shift_toward

    assert shift_toward(computed, specified) == expected


def test_e7_seed_10_to_730_through_the_solver() -> None:
    head = Carrier(v1=(0, 0, 1), v2=(1, 0, 0), angle1=750.0)
    d = rpy_matrix(30, 0, 10) @ Z  # C = 10, A = 30
    sel = solve_orientation(head, direction=d)
    np.testing.assert_allclose(sel.chosen, (730, 30), atol=1e-9)
    np.testing.assert_allclose(sel.p_tcang[:2], (730, 30), atol=1e-9)
    assert any("750" in r and "730" in r for r in sel.reasons)


# ---- E8: limits and swap ------------------------------------------------------------------------


def _e3_with(**limits: float) -> Carrier:
    from dataclasses import replace

    return replace(E3, **limits)


def test_e8_first_pair_outside_second_used_and_swapped() -> None:
    c = _e3_with(min1=0.0, max1=100.0)
    sel = solve_orientation(c, frame=(0, 40, 30))
    np.testing.assert_allclose(sel.chosen, (40, 150), atol=1e-9)
    np.testing.assert_allclose(sel.p_tcang, (40, 150, -40, -30), atol=1e-9)
    assert sel.swapped and sel.tcsol == 1 and sel.tcang0 == 2


def test_e8_shift_inside_the_limits() -> None:
    c = _e3_with(min1=-100.0, max1=100.0, min2=0.0, max2=360.0)
    sel = solve_orientation(c, frame=(0, 40, 30))
    np.testing.assert_allclose(sel.chosen, (-40, 330), atol=1e-9)
    assert not sel.swapped and sel.tcsol == 2


def test_e8_no_valid_solution() -> None:
    c = _e3_with(min1=-100.0, max1=100.0, min2=-200.0, max2=-100.0)
    with pytest.raises(AlarmError) as ei:
        solve_orientation(c, frame=(0, 40, 30))
    d = ei.value.diagnostic
    assert d.code == "TH-NO-VALID-SOLUTION"
    assert "toolholder 1" in d.message


def test_e8_head_falls_back_to_second_solution() -> None:
    from dataclasses import replace

    c = replace(E2, min2=-10.0, max2=110.0)
    sel = solve_orientation(c, frame=(30, 0, 0), reference=(170, -20))
    np.testing.assert_allclose(sel.chosen, (0, 30), atol=1e-9)
    np.testing.assert_allclose(sel.p_tcang, (0, 30, 180, -30), atol=1e-9)
    assert sel.swapped


# ---- E9: rotary-axis offset ---------------------------------------------------------------------


E9 = Carrier(v1=(1, 0, 0), axis_offset1=90.0)


@pytest.mark.parametrize(
    ("a", "expected"), [(90, (0, 0, 100)), (120, (0, -50, 86.60254)), (0, (0, 100, 0))]
)
def test_e9_tcoabs_with_axis_offset(a: float, expected: tuple[float, float, float]) -> None:
    from dataclasses import replace

    sel = tcoabs_angles(replace(E9, angle1=a))
    np.testing.assert_allclose(resulting_tool_length(E9, *sel.chosen, L100), expected, atol=1e-5)


def test_e9_tcofr_with_axis_offset() -> None:
    np.testing.assert_allclose(solve_orientation(E9).chosen, (90, 0), atol=1e-9)
    sel = solve_orientation(E9, frame=(30, 0, 0))
    np.testing.assert_allclose(sel.chosen, (120, 0), atol=1e-9)
    assert_forward_exact(E9, sel.inverse)


# ---- E10: Hirth ---------------------------------------------------------------------------------


def test_e10_hirth_grid() -> None:
    c = Carrier(v1=(0, 1, 0), hirth_increment1=2.5)
    sel = solve_orientation(c, direction=(2, 0, 3))
    exact = math.degrees(math.atan2(2, 3))
    assert exact == pytest.approx(33.6901, abs=1e-4)
    assert sel.inverse.pairs[0].angle1 == pytest.approx(exact, abs=1e-9)
    assert sel.chosen[0] == pytest.approx(32.5, abs=1e-12)
    assert sel.tcdiff[0] == pytest.approx(32.5 - exact, abs=1e-9)
    assert sel.tcdiff[0] == pytest.approx(-1.1901, abs=1e-4)
    np.testing.assert_allclose(
        relative_direction(c, *sel.chosen, Z), (0.5373, 0, 0.8434), atol=1e-4
    )
    assert sel.orientation_error_deg == pytest.approx(1.1901, abs=1e-4)


def test_e10_hirth_offset() -> None:
    c = Carrier(v1=(0, 1, 0), hirth_increment1=2.5, hirth_offset1=1.25)
    sel = solve_orientation(c, direction=(2, 0, 3))
    assert sel.chosen[0] == pytest.approx(33.75, abs=1e-12)
    assert sel.tcdiff[0] == pytest.approx(0.0599, abs=1e-4)


def test_hirth_tie_goes_toward_specified() -> None:
    from trcopt.kinematics import hirth_round

    assert hirth_round(11.25, 0.0, 2.5, 0.0) == 10.0
    assert hirth_round(11.25, 0.0, 2.5, 100.0) == 12.5
    assert hirth_round(11.0, 0.0, 2.5, 100.0) == 10.0
    assert hirth_round(11.0, 0.0, 0.0, 100.0) == 11.0  # grid off


# ---- E11: plane change --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("plane", "lt", "expected"),
    [
        ("G17", (5, 0, 100), (5, -125, 66.506)),
        ("G18", (0, 100, 5), (0, 9.103, 34.234)),
        ("G19", (100, 5, 0), (100, -70.670, -17.596)),
    ],
)
def test_e11_plane_change_permutes_only_the_tool(plane, lt, expected) -> None:
    ltool = tool_length_vector((100.0, 0.0, 5.0), plane)
    np.testing.assert_allclose(ltool, lt, atol=1e-12)
    np.testing.assert_allclose(resulting_tool_length(E2, 0, 30, ltool), expected, atol=1e-3)


# ---- E12: one rotary axis -----------------------------------------------------------------------


def test_e12_one_rotary_axis() -> None:
    c = Carrier(v1=(0, 1, 0))
    sel = solve_orientation(c, frame=(0, 25, 0))
    assert sel.inverse.kind is SolutionKind.ONE
    np.testing.assert_allclose(sel.chosen, (25, 0), atol=1e-9)
    assert_forward_exact(c, sel.inverse)
    with pytest.raises(AlarmError) as ei:
        solve_orientation(c, frame=(10, 0, 0))
    assert ei.value.diagnostic.code == "TH-UNREACHABLE"
    assert isinstance(ei.value, TrcoptError)


# ---- E13: TCOABS limit monitoring ---------------------------------------------------------------


def test_e13_tcoabs_limit_alarm() -> None:
    c = Carrier(v1=(1, 0, 0), min1=-30.0, max1=95.0, angle1=100.0)
    with pytest.raises(AlarmError) as ei:
        tcoabs_angles(c)
    assert ei.value.diagnostic.code == "TH-LIMIT"
    assert "$TC_CARR30/32" in ei.value.diagnostic.message


def test_e13_tcoabs_shifted_inside() -> None:
    c = Carrier(v1=(1, 0, 0), min1=-30.0, max1=95.0, angle1=-300.0)
    sel = tcoabs_angles(c)
    assert sel.chosen == (60.0, 0.0)
    # same orientation as −300
    np.testing.assert_allclose(
        relative_direction(c, 60, 0, Z), relative_direction(c, -300, 0, Z), atol=1e-12
    )


# ---- E14: general skew axes ---------------------------------------------------------------------


def test_e14_skew_axes() -> None:
    c = Carrier(v1=(0, 0, 1), v2=(1, 0, 1))
    inv = inverse_solutions(c, (0.3, -0.5, 0.8))
    np.testing.assert_allclose(inv.direction, (0.303046, -0.505076, 0.808122), atol=1e-6)
    got = sorted((p.angles for p in inv.pairs), reverse=True)
    np.testing.assert_allclose(got, [(11.9521, 51.9576), (-130.0246, -51.9576)], atol=1e-4)
    assert_forward_exact(c, inv)
