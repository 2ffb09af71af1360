"""Malformed Klartext found by the fuzz run: an error with its place, never a traceback."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.codes import Code
from trcopt.controllers.heidenhain.tooltable import tool_table_from_dict
from trcopt.errors import ConfigError
from trcopt.pipeline import PlanOptions, plan

ROOT = Path(__file__).resolve().parents[3]
H05 = (ROOT / "problems" / "heidenhain" / "h05_appr_dep_ln.h").read_text()


@pytest.mark.parametrize(
    ("old", "new", "line", "block", "word"),
    [
        ("10 DEP LN LEN+10 F500", "10 DEP LEN12 F500", 11, "10", "DEP"),
        ("4 APPR LN X+0 Y+20 LEN+10 RL F200", "4 APPR X+0 Y+20 LEN+10 RL F200", 5, "4", "APPR"),
        ("10 DEP LN LEN+10 F500", "10 DEP", 11, "10", "DEP"),
    ],
)
def test_appr_dep_without_its_kind_is_a_syntax_error(old: str, new: str, line: int, block: str, word: str) -> None:
    assert old in H05
    result = plan(H05.replace(old, new), file="p.h", options=PlanOptions(timing=False))
    err = result.errors[0]
    assert err.code is Code.HH_SYNTAX
    assert (err.span.line, err.span.block) == (line, block)
    assert err.span.column >= 1
    assert f"{word} needs its kind" in err.message


def test_a_negative_tool_def_radius_is_an_error_at_tool_def() -> None:
    result = plan(H05.replace("R+5", "R-5"), file="p.h", options=PlanOptions(timing=False))
    err = result.errors[0]
    assert err.code is Code.NC_TOOL_RADIUS
    assert (err.span.line, err.span.block) == (2, "1")
    assert H05.splitlines()[1][err.span.column - 1 :].startswith("R+5")


@pytest.mark.parametrize(("row", "words"), [({"R": -3.0}, "cannot be negative"), ({"R": float("nan")}, "finite")])
def test_a_negative_or_non_finite_tool_table_radius_is_invalid(row: dict, words: str) -> None:
    with pytest.raises(ConfigError, match=words):
        tool_table_from_dict({"tool": {"3": row}}, "tools.toml")


def test_a_dep_after_a_dep_is_a_syntax_error_not_an_internal_one() -> None:
    h06 = (ROOT / "problems" / "heidenhain" / "h06_appr_dep_ct.h").read_text()
    dep = next(line for line in h06.splitlines() if " DEP " in line)
    lines = h06.splitlines()
    at = lines.index(dep)
    text = "\n".join([*lines[: at + 1], dep, *lines[at + 1 :]]) + "\n"
    result = plan(text, file="p.h", options=PlanOptions(timing=False))
    err = result.errors[0]
    assert err.code is Code.HH_SYNTAX and "not another DEP" in err.message
    assert err.span.line == at + 2
