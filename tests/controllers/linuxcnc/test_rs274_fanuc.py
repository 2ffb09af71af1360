"""Fanuc-style programs in the rs274 reader: ``O100`` … ``M99`` called by ``M98 P100 [L n]``.

The expected end points and messages are rs274's (LinuxCNC's interpreter built from source, run on
the same programs: ``rs274 -t sim.tbl -g prog.ngc``), copied here as facts."""

from __future__ import annotations

import pytest

from trcopt import PlanOptions, plan

OPTS = PlanOptions(timing=False, corners="exact")

CASES = {
    # called once and twice (L2), the program after M30 found by searching forward
    "calls": (
        "G21 G90\nG0 X0 Y0 Z5\nM98 P100\nG0 X50\nM98 P100 L2\nG0 Y7\nM30\nO100\nG91 G1 X10 F100\nG90\nM99\n%\n",
        [(0, 0, 5), (10, 0, 5), (50, 0, 5), (60, 0, 5), (70, 0, 5), (70, 7, 5)],
    ),
    # nested: O100 calls O200; M99 in the main program ends it
    "nested": (
        "G21 G90\nG0 X0 Y0 Z5\nM98 P100\nG0 X50\nM99\nO100\nM98 P200\nG91 G1 Y10 F100\nG90\nM99\n"
        "O200\nG91 G1 X10 F100\nG90\nM99\n%\n",
        [(0, 0, 5), (10, 0, 5), (10, 10, 5), (50, 10, 5)],
    ),
    # #1…#30 shared with the caller (the called program changes #1), named locals its own
    "parameters": (
        "G21 G90\nG0 X0 Y0 Z5\n#1=3\nM98 P7 L2\nG0 X[#1]\nM2\nO7\n#<loc>=2\nG91 G1 X#<loc> Y#1 F100\nG90\n"
        "#1=[#1+1]\nM99\n%\n",
        [(0, 0, 5), (2, 3, 5), (4, 7, 5), (5, 7, 5)],
    ),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_fanuc_programs_run_as_rs274_runs_them(name: str) -> None:
    text, expected = CASES[name]
    result = plan(text, file=f"{name}.ngc", options=OPTS)
    assert result.ok, [d.format() for d in result.errors]
    ends = [tuple(round(c, 6) for c in s.geometry.end) for s in result.toolpath]
    assert ends == [tuple(float(c) for c in p) for p in expected]


@pytest.mark.parametrize(
    ("text", "code", "message", "line"),
    [
        # rs274: "EOF in file:m1.ngc seeking o-word: o<200> from line: 3"
        ("G21 G90\nG0 X0 Y0 Z5\nM98 P200\nM30\n%\n", "LCNC-OWORD", "seeking o-word: o<200> from line: 3", None),
        # rs274: an M99 closing an O-word sub
        (
            "G21 G90\nG0 X0 Y0 Z5\no100 sub\nG1 X1 F10\nM99\no100 endsub\no100 call\nM2\n%\n",
            "LCNC-OWORD",
            "'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine definition",
            5,
        ),
        # not modelled: said so, with the place
        ("G21 G90\nG0 X0 Y0 Z5\nM98 P100 L0\nM30\nO100\nM99\n%\n", "NC-UNSUPPORTED", "M98 L0", 3),
        ("G21 G90\nG0 X0 Y0 Z5\nM98 P100 G1 X3 F100\nM30\nO100\nM99\n%\n", "NC-UNSUPPORTED", "other words", 3),
    ],
)
def test_fanuc_program_errors(text: str, code: str, message: str, line: int | None) -> None:
    result = plan(text, file="m.ngc", options=OPTS)
    assert not result.ok
    err = result.errors[0]
    assert err.code == code and message in err.message
    if line is not None:
        assert err.span.line == line
