"""TCARR / TCOABS / TCOFR in a program: the plan JSON "toolholder" entry and its diagnostics."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from trcopt.kinematics import evaluate_toolholder, scan_program

PROBLEMS = Path(__file__).resolve().parents[2] / "problems" / "toolholder"

E2 = {2: -20.0, 3: -200.0, 5: 20.0, 6: 50.0, 9: 1.0, 10: 1.0, 17: 150.0, 23: "T"}


def ev(line: int, word: str, value=None, block: str | None = None) -> dict:
    return {"line": line, "block": block or f"N{line * 10}", "word": word, "value": value}


def test_tcofr_without_frame_keeps_tool_vertical() -> None:
    out, diags = evaluate_toolholder({1: E2}, [ev(1, "TCOFR"), ev(2, "TCARR", 1)], "p.mpf",
                                     tool_lengths=(100.0,))
    assert diags == []
    assert out["active"] == 1 and out["word"] == "TCOFR" and out["kinematic_type"] == "T"
    np.testing.assert_allclose(out["angles_deg"], (0, 0), atol=1e-9)
    np.testing.assert_allclose(out["tool_direction"], (0, 0, 1), atol=1e-12)
    np.testing.assert_allclose(out["tool_vector"], (0, 0, 100), atol=1e-9)
    assert out["p_tcang"][2] is None and out["p_tcang0"] == 1
    json.dumps(out)  # JSON-able


def test_tcofr_reads_the_frame_at_selection() -> None:
    events = [ev(1, "ROT", [30, 0, 0]), ev(2, "TCOFR"), ev(3, "TCARR", 1), ev(4, "ROT", [0, 0, 0])]
    out, diags = evaluate_toolholder({1: E2}, events, "p.mpf", tool_lengths=(100.0,))
    assert diags == []
    np.testing.assert_allclose(out["angles_deg"], (0, 30), atol=1e-9)
    np.testing.assert_allclose(out["p_tcang"], (0, 30, 180, -30), atol=1e-9)
    np.testing.assert_allclose(out["tool_vector"], (0, -125, 66.5064), atol=1e-4)
    # the later ROT did not move the holder (REQ-TH-14)
    assert len(out["activations"]) == 1
    assert out["activations"][0]["line"] == 3 and out["activations"][0]["block"] == "N30"


def test_tcoabs_uses_stored_angles_and_plane_change() -> None:
    data = {**E2, 13: 0.0, 14: 30.0}
    events = [ev(1, "TCARR", 1), ev(2, "G18")]
    out, _ = evaluate_toolholder({1: data}, events, "p.mpf", tool_lengths=(100.0, 0.0, 5.0))
    assert out["word"] == "TCOABS" and out["plane"] == "G18"
    np.testing.assert_allclose(out["tool_vector"], (0, 9.103, 34.234), atol=1e-3)
    assert [a["plane"] for a in out["activations"]] == ["G17", "G18"]


def test_axis_reference_supplies_tcoabs_angle() -> None:
    data = {**E2, 21: "C", 13: 5.0, 14: 30.0}
    out, _ = evaluate_toolholder({1: data}, [ev(1, "TCARR", 1)], "p.mpf",
                                 axis_positions={"c": 90.0})
    np.testing.assert_allclose(out["angles_deg"], (90, 30))


def test_alarm_14153_with_block_and_line_stops() -> None:
    bad = {9: 1.0, 23: "X"}
    events = [ev(3, "TCARR", 2, "N30"), ev(4, "TCARR", 1)]
    out, diags = evaluate_toolholder({1: E2, 2: bad}, events, "prog.mpf")
    assert len(diags) == 1
    d = diags[0]
    assert d.alarm == 14153 and d.span.line == 3 and d.span.block == "N30"
    assert "toolholder 2" in d.message
    assert out["active"] == 0  # evaluation stopped at the alarm


def test_unknown_holder_and_limits_alarm() -> None:
    out, diags = evaluate_toolholder({}, [ev(1, "TCARR", 7)], "p.mpf")
    assert diags[0].code == "TH-UNKNOWN-HOLDER" and "7" in diags[0].message
    data = {**E2, 13: 100.0, 30: -30.0, 32: 95.0}
    out, diags = evaluate_toolholder({1: data}, [ev(5, "TCARR", 1)], "p.mpf")
    assert diags[0].code == "TH-LIMIT" and diags[0].span.line == 5


def test_unreachable_orientation_diagnostic() -> None:
    one_axis = {8: 1.0}
    events = [ev(1, "ROT", [10, 0, 0]), ev(2, "TCOFR"), ev(3, "TCARR", 4)]
    out, diags = evaluate_toolholder({4: one_axis}, events, "p.mpf")
    assert diags[0].code == "TH-UNREACHABLE" and diags[0].span.block == "N30"
    assert "toolholder 4" in diags[0].message


def test_tcarr_zero_deselects() -> None:
    out, _ = evaluate_toolholder({1: E2}, [ev(1, "TCARR", 1), ev(2, "TCARR", 0)], "p.mpf")
    assert out["active"] == 0 and out["angles_deg"] is None
    assert len(out["activations"]) == 1


def test_same_block_words_act_together() -> None:
    events = [ev(1, "ROT", [30, 0, 0]), ev(2, "TCARR", 1), ev(2, "TCOFR")]
    out, _ = evaluate_toolholder({1: E2}, events, "p.mpf")
    assert len(out["activations"]) == 1 and out["word"] == "TCOFR"
    np.testing.assert_allclose(out["angles_deg"], (0, 30), atol=1e-9)


def test_scan_program_example_file() -> None:
    path = PROBLEMS / "ac_fork_head.mpf"
    carriers, events = scan_program(path.read_text(), path.name)
    assert carriers[1][23] == "T" and carriers[1][17] == 150.0 and carriers[1][13] == 170.0
    words = [e["word"] for e in events]
    assert words == ["G17", "TCARR", "TCOABS", "ROT", "TCOFR"]
    out, diags = evaluate_toolholder(carriers, events, path.name, tool_lengths=(100.0,))
    assert diags == []
    first, last = out["activations"][0], out["activations"][-1]
    np.testing.assert_allclose(first["angles_deg"], (170, -20))
    np.testing.assert_allclose(last["angles_deg"], (180, -30), atol=1e-9)
    assert last["block"] == "N100" and last["line"] == 11
    np.testing.assert_allclose(out["tool_vector"], (0, -165, 66.5064), atol=1e-4)


def test_scan_program_bad_kinematic_type_file() -> None:
    path = PROBLEMS / "bad_kinematic_type.mpf"
    carriers, events = scan_program(path.read_text(), path.name)
    _, diags = evaluate_toolholder(carriers, events, path.name)
    assert [d.alarm for d in diags] == [14153]
    assert diags[0].format().startswith("bad_kinematic_type.mpf:4:")
    assert "(N30)" in diags[0].format()


def test_scan_program_details() -> None:
    text = (
        "N10 $TC_CARR23[3]='m' $TC_CARR21[3]=B ; comment TCARR=9\n"
        "N20 $TC_CARR1[0]=0\n"
        "N30 $TC_CARR7[2]=1.5E1 $TC_CARR34[2]=\"head\"\n"
        "N40 AROT Z=45 Y10 TCARR=2 TCOFRX\n"
        "N50 ROT\n"
    )
    carriers, events = scan_program(text)
    assert carriers == {2: {7: 15.0, 34: "head"}}
    assert [(e["word"], e["value"]) for e in events] == [
        ("AROT", [0.0, 10.0, 45.0]),
        ("TCARR", 2),
        ("TCOFRX", None),
        ("ROT", None),
    ]


@pytest.mark.parametrize("word", ["TCOFRY", "TCOFRX"])
def test_tcofr_x_y_align_the_same_axes(word: str) -> None:
    events = [ev(1, "ROT", [0, 0, 90]), ev(2, word), ev(3, "TCARR", 1)]
    out, diags = evaluate_toolholder({1: E2}, events, "p.mpf")
    assert diags == []
    # a pure C rotation of 90° turns frame x/y like the holder's C axis
    np.testing.assert_allclose(out["angles_deg"], (90, 0), atol=1e-9)
