"""The $TC_CARR data block: assignments, TOML carrier files, alarm 14153, defaults, warnings."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from trcopt.errors import AlarmError, ConfigError, Severity, SourceSpan
from trcopt.kinematics import (
    Carrier,
    KinematicType,
    carrier_from_assignments,
    load_carrier_toml,
    resulting_tool_length,
    solve_orientation,
)

PROBLEMS = Path(__file__).resolve().parents[2] / "problems" / "toolholder"


def test_assignments_fill_every_field() -> None:
    values: dict[int, float | str] = {n: float(n) for n in range(1, 21) if n not in (13, 14)}
    values.update({13: 13.5, 14: -14.5, 21: "C", 22: 0, 23: "p", 24: 24.0, 25: 25.0})
    values.update({26: 1.25, 27: 0.5, 28: 2.5, 29: 5.0, 30: -30.0, 31: -31.0, 32: 32.0, 33: 33.0})
    values.update({34: "fork", 35: "C1", 36: "A1", 37: 7, 38: 1.0, 39: 2.0, 40: 3.0})
    values.update({41: 0.1, 46: 0.6, 55: 0.01, 60: 0.06, 64: 0.5, 65: -0.5})
    c = carrier_from_assignments(values, 3)
    assert c.number == 3
    assert c.l1 == (1.0, 2.0, 3.0) and c.l2 == (4.0, 5.0, 6.0)
    assert c.v1 == (7.0, 8.0, 9.0) and c.v2 == (10.0, 11.0, 12.0)
    assert (c.angle1, c.angle2) == (13.5, -14.5)
    assert c.l3 == (15.0, 16.0, 17.0) and c.l4 == (18.0, 19.0, 20.0)
    assert c.axis_ref1 == "C" and c.axis_ref2 is None
    assert c.kinematic_type is KinematicType.P
    assert c.axis_offsets == (24.5, 24.5)
    assert c.hirth(1) == (1.25, 2.5) and c.hirth(2) == (0.5, 5.0)
    assert c.limits(1) == (-30.0, 32.0) and c.limits(2) == (-31.0, 33.0)
    assert (c.name, c.axis_name1, c.axis_name2, c.identifier) == ("fork", "C1", "A1", 7)
    assert c.position == (1.0, 2.0, 3.0)
    l1, l2, l3, l4 = c.offsets
    np.testing.assert_allclose(l1, (1.1, 2.0, 3.0))
    np.testing.assert_allclose(l2, (4.0, 5.0, 6.6))
    np.testing.assert_allclose(l3, (15.01, 16.0, 17.0))
    np.testing.assert_allclose(l4, (18.0, 19.0, 20.06))
    # round trip through the assignment form
    again = carrier_from_assignments(c.to_assignments(), 3)
    assert again == c


def test_fine_offsets_can_be_disabled() -> None:
    values: dict[int, float | str] = {3: 10.0, 43: 0.5, 24: 90.0, 64: 1.0}
    c = carrier_from_assignments(values, 1, fine_offsets_enabled=False)
    np.testing.assert_allclose(c.offsets[0], (0, 0, 10.0))
    assert c.axis_offsets == (90.0, 0.0)


def test_defaults_are_the_controls() -> None:
    c = carrier_from_assignments({}, 1)
    assert c.kinematic_type is KinematicType.T
    assert c.has_axis == (False, False)
    assert c.limits(1) is None and c.hirth(1) is None
    # no axis: only the identity orientation, and the tool length unchanged
    np.testing.assert_allclose(resulting_tool_length(c, 0, 0, (0, 0, 100)), (0, 0, 100))
    sel = solve_orientation(c)
    assert sel.chosen == (0.0, 0.0)
    with pytest.raises(AlarmError):
        solve_orientation(c, direction=(0, 1, 1))


@pytest.mark.parametrize("kin", ["t", "P", "m", " M "])
def test_kinematic_type_case_insensitive(kin: str) -> None:
    assert carrier_from_assignments({23: kin}, 1).kinematic_type.value == kin.strip().upper()


@pytest.mark.parametrize("kin", ["X", "", "TP", 1.0])
def test_invalid_kinematic_type_alarm_14153(kin: object) -> None:
    span = SourceSpan("prog.mpf", 12, 5, "N120")
    with pytest.raises(AlarmError) as ei:
        carrier_from_assignments({23: kin}, 4, span)  # type: ignore[dict-item]
    d = ei.value.diagnostic
    assert d.alarm == 14153 and d.code == "14153" and d.severity is Severity.ERROR
    assert "toolholder 4" in d.message and "$TC_CARR23[4]" in d.message
    assert d.span.line == 12 and d.span.block == "N120"
    assert d.format().startswith("prog.mpf:12:5: error 14153 (N120):")


@pytest.mark.parametrize("n", [0, 47, 50, 54, 61, 63, 66])
def test_undefined_indices_rejected(n: int) -> None:
    with pytest.raises(AlarmError) as ei:
        carrier_from_assignments({n: 1.0}, 2)
    assert ei.value.diagnostic.code == "TH-UNDEFINED-PARAM"
    assert f"$TC_CARR{n}[2]" in ei.value.diagnostic.message


def test_wrong_value_type_rejected() -> None:
    with pytest.raises(AlarmError) as ei:
        carrier_from_assignments({7: "one"}, 1)
    assert ei.value.diagnostic.code == "TH-VALUE"


def test_warnings_for_ignored_vectors_and_open_chain() -> None:
    t = Carrier(l4=(0, 0, 1))
    codes = {d.code for d in t.warnings()}
    assert codes == {"TH-IGNORED-L4"}
    p = Carrier(kinematic_type=KinematicType.P, l1=(1, 0, 0), l2=(0, 0, 5))
    codes = [d.code for d in p.warnings()]
    assert "TH-IGNORED-L1" in codes and "TH-CHAIN-OPEN" in codes
    assert all(d.severity is Severity.WARNING for d in p.warnings())
    closed = Carrier(l1=(0, -20, -200), l2=(0, 20, 50), l3=(0, 0, 150))
    assert closed.warnings() == []


def test_open_chain_is_a_constant_offset() -> None:
    # both axes zero: l1, l2 act as an extra tool offset that the plane does not permute
    c = Carrier(l1=(1.0, 2.0, 3.0), l2=(0.5, 0.0, 0.0))
    np.testing.assert_allclose(resulting_tool_length(c, 0, 0, (0, 0, 100)), (1.5, 2.0, 103.0))


# ---- TOML ---------------------------------------------------------------------------------------


def test_toml_loader_uses_system_variable_keys(tmp_path: Path) -> None:
    f = tmp_path / "head.toml"
    f.write_text(
        'number = 5\nTC_CARR9 = 1.0\nTC_CARR10 = 1\nTC_CARR17 = 150.0\ntc_carr23 = "t"\n'
        "TC_CARR30 = -10.0\nTC_CARR32 = 110.0\nTC_CARR21 = \"C\"\nfine_offsets_enabled = false\n"
    )
    c = load_carrier_toml(f)
    assert c.number == 5 and c.v1 == (0.0, 0.0, 1.0) and c.v2 == (1.0, 0.0, 0.0)
    assert c.l3 == (0.0, 0.0, 150.0) and c.kinematic_type is KinematicType.T
    assert c.limits(1) == (-10.0, 110.0) and c.axis_ref1 == "C"
    assert not c.fine_offsets_enabled


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("TC_CARR7 = 1.0\nTC_CAR8 = 1.0\n", "TC_CAR8"),
        ("speed = 3\n", "speed"),
        ("TC_CARR50 = 1.0\n", "TC_CARR50"),
        ("TC_CARR66 = 1.0\n", "TC_CARR66"),
        ("TC_CARR7 = \"x\"\n", "TC_CARR7"),
        ("TC_CARR7 = [1, 2]\n", "TC_CARR7"),
        ("number = \"one\"\n", "number"),
    ],
)
def test_toml_bad_keys_name_the_key(tmp_path: Path, text: str, key: str) -> None:
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(ConfigError) as ei:
        load_carrier_toml(f)
    assert key in str(ei.value)


def test_toml_invalid_kinematic_type_is_14153(tmp_path: Path) -> None:
    f = tmp_path / "bad.toml"
    f.write_text('TC_CARR23 = "Q"\n')
    with pytest.raises(ConfigError) as ei:
        load_carrier_toml(f)
    assert ei.value.code == "14153"
    assert "TC_CARR23" in str(ei.value)


def test_toml_missing_file_and_invalid_syntax(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="cannot read"):
        load_carrier_toml(tmp_path / "absent.toml")
    f = tmp_path / "broken.toml"
    f.write_text("TC_CARR7 = = 1\n")
    with pytest.raises(ConfigError, match="invalid TOML"):
        load_carrier_toml(f)


@pytest.mark.parametrize("path", sorted(PROBLEMS.glob("*.toml")), ids=lambda p: p.stem)
def test_problem_carrier_files_load_and_are_closed(path: Path) -> None:
    c = load_carrier_toml(path)
    assert [d.code for d in c.warnings()] == []


def test_problem_e2_file_reproduces_the_example() -> None:
    c = load_carrier_toml(PROBLEMS / "e2_ac_fork_head.toml")
    sel = solve_orientation(c, frame=(30, 0, 0))
    np.testing.assert_allclose(sel.chosen, (0, 30), atol=1e-9)
    np.testing.assert_allclose(
        resulting_tool_length(c, *sel.chosen, (0, 0, 100)), (0, -125, 66.5064), atol=1e-4
    )
