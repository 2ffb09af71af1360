"""SINUMERIK R-parameters, DEF variables and arithmetic: values in words,
operator priority and functions against hand-computed values, a compensated contour written with
parameters planning to the same tool-centre path as with literal numbers, and located errors."""

from __future__ import annotations

import math

import pytest

from trcopt.controllers import read_program
from trcopt.controllers.siemens.expr import ExprError, evaluate
from trcopt.errors import Severity
from trcopt.nc import MoveKind
from trcopt.pipeline import PlanOptions, plan


def read(text):
    return read_program(text, file="p.mpf")


def moves(text):
    prog = read(text + "\nM30\n")
    errs = [d.format() for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert errs == []
    return [m for m in prog.moves if m.kind is not MoveKind.NONE]


def error_of(text):
    prog = read(text)
    errs = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert len(errs) == 1, [d.format() for d in prog.diagnostics]
    return errs[0]


# ---------------------------------------------------------------- values in words
def test_parameters_in_coordinates_feed_and_incremental_modes():
    ms = moves("R1=5 R[2*3]=R1*2\nG1 X=R1*2+3 Y=R6 F=R1*60\nX=AC(R1) Y=IC(R1-1)")
    assert ms[0].end == (13.0, 10.0, 0.0)
    assert ms[0].feed_mm_s == pytest.approx(5.0)  # F300 mm/min
    assert ms[1].end == (5.0, 14.0, 0.0)


def test_assignments_act_in_block_order_and_spaces_around_operators():
    (m,) = moves("R1=2 R2=R1 * 3 R1=R1 + 1 G1 X=R1 Y=R2 F100")
    assert m.end == (3.0, 6.0, 0.0)


def test_def_variables_in_words_with_types():
    ms = moves(
        "DEF REAL LEN=12.5, WID\nDEF INT NUM=2.5\nDEF BOOL FLAG=7\nDEF REAL TAB[3]\n"
        "TAB[1]=LEN/5 WID=LEN-NUM\nG1 X=WID Y=TAB[1] Z=FLAG F100"
    )
    assert ms[-1].end == (9.5, 2.5, 1.0)  # INT rounds 2.5 to 3, BOOL stores 1


def test_cr_with_parameter():
    (m,) = moves("R3=10\nG2 X20 Y0 CR=R3 F100")
    assert m.center == pytest.approx((10.0, 0.0, 0.0))


def test_centre_with_ac_parameter():
    (m,) = moves("R1=5\nG3 X10 Y0 I=AC(R1) J=AC(R1-R1) F100")
    assert m.center == pytest.approx((5.0, 0.0, 0.0))


def test_tool_table_from_parameters():
    prog = read("R4=2.5 R5=1\n$TC_DP1[R5,1]=120 $TC_DP6[1,R5]=R4*2\nT1 D1\nM30")
    assert not [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert prog.extras["tools"][(1, 1)].radius == 5.0 and prog.extras["tools"][(1, 1)].type == 120


# ---------------------------------------------------------------- arithmetic
@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1+2*3", 7.0),
        ("(1+2)*3", 9.0),
        ("10-4-3", 3.0),  # left to right
        ("12/3/2", 2.0),
        ("-2*3+8", 2.0),
        ("7 DIV 2", 3.0),
        ("-7 DIV 2", -3.0),  # truncated towards zero
        ("7 MOD 3", 1.0),
        ("-7 MOD 3", -1.0),  # sign of the dividend
        ("7.5 MOD 2", 1.5),
        ("1+7 DIV 2*2", 7.0),  # DIV has the priority of *
        ("2EX3", 2000.0),
        ("1.5EX-1", 0.15),
        ("3 == 3", 1.0),
        ("3 <> 3", 0.0),
        ("2 < 3", 1.0),
        ("3 <= 3", 1.0),
        ("2 >= 3", 0.0),
        ("1 == 1 AND 0", 0.0),  # comparison has the lowest priority: 1 == (1 AND 0)
        ("(1 == 1) AND (2 > 1)", 1.0),
        ("1 OR 0 AND 0", 1.0),  # AND before OR
        ("1 XOR 1", 0.0),
        ("NOT 0", 1.0),
        ("NOT 2 + 1", 1.0),  # NOT binds first: (NOT 2) + 1
        ("6 B_AND 3", 2.0),
        ("6 B_OR 3", 7.0),
        ("6 B_XOR 3", 5.0),
        ("TRUE + TRUE", 2.0),
        ("0.1 + 0.2 == 0.3", 1.0),  # relative equality
    ],
)
def test_operators_and_priority(text, value):
    assert evaluate(text) == value


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("SIN(30)", 0.5),
        ("SIN(-390)", -0.5),
        ("COS(60)", 0.5),
        ("COS(180)", -1.0),
        ("TAN(45)", 1.0),
        ("ASIN(0.5)", 30.0),
        ("ACOS(-1)", 180.0),
        ("ATAN2(1, 1)", 45.0),
        ("ATAN2(1, -1)", 135.0),
        ("ATAN2(-1, 0)", -90.0),
        ("SQRT(2)", math.sqrt(2.0)),
        ("POT(-3)", 9.0),
        ("ABS(-2.5)", 2.5),
        ("TRUNC(-2.7)", -2.0),
        ("TRUNC(2.7)", 2.0),
        ("ROUND(2.5)", 3.0),
        ("ROUND(-2.5)", -3.0),
        ("ROUND(2.4999)", 2.0),
        ("MINVAL(3, -1)", -1.0),
        ("MAXVAL(3, -1)", 3.0),
        ("LN(EXP(2))", 2.0),
        ("SQRT(POT(3)+POT(4))*2", 10.0),
    ],
)
def test_functions_in_degrees(text, value):
    assert evaluate(text) == pytest.approx(value, abs=1e-12)


def test_expression_in_a_word_is_exact_double_arithmetic():
    (m,) = moves("R1=0.1 R2=0.2\nG1 X=R1+R2 Y=10*SIN(30) F100")
    assert m.end[0] == 0.1 + 0.2 and m.end[1] == 10 * math.sin(math.radians(30.0))


@pytest.mark.parametrize(
    ("text", "kind", "offset"),
    [("1/0", "arithmetic", 1), ("2 MOD 0", "arithmetic", 2), ("SQRT(-1)", "arithmetic", 0),
     ("ASIN(2)", "arithmetic", 0), ("TAN(90)", "arithmetic", 0), ("1+", "syntax", 2), ("(1", "syntax", 2),
     ("FOO(1)", "undefined", 0), ("ATAN2(1)", "syntax", 0), ("1 2", "syntax", 2)],
)  # fmt: skip
def test_expression_errors_have_a_kind_and_an_offset(text, kind, offset):
    with pytest.raises(ExprError) as info:
        evaluate(text)
    assert (info.value.kind, info.value.offset) == (kind, offset)


# ---------------------------------------------------------------- compensated contour
LITERAL = """N10 $TC_DP1[1,1]=120 $TC_DP6[1,1]=4
N20 T1 D1
N30 G17 G90 G0 X-20 Y-20 Z5
N40 G1 Z-2 F500
N50 G41 X0 Y0 F800
N60 X60
N70 G3 X80 Y20 CR=20
N80 G1 Y50
N90 G2 X60 Y70 I=AC(60) J=AC(50)
N100 G1 X0
N110 Y0
N120 G40 X-20 Y-20
N130 M30
"""

WITH_PARAMETERS = """N5 DEF REAL LEN=60, RAD=20, TOOL_R=8
N6 DEF INT EDGE=1
N10 $TC_DP1[1,EDGE]=120 $TC_DP6[1,EDGE]=TOOL_R/2
N15 R1=-20 R2=R1+R1 R[10]=LEN+RAD
N20 T1 D=EDGE
N30 G17 G90 G0 X=R1 Y=R1 Z=5
N40 G1 Z=-2 F=R10*25/4
N50 G41 X=0 Y=0 F=4*(R10+120)
N60 X=LEN
N70 G3 X=R10 Y=RAD CR=RAD
N80 G1 Y=LEN-10
N90 G2 X=LEN Y=LEN+10 I=AC(LEN) J=AC(R10 - 30)
N100 G1 X=0
N110 Y=R2 - 2 * R1
N120 G40 X=R1 Y=SIN(-90)*20
N130 M30
"""


def _path(text):
    r = plan(text, file="c.mpf", options=PlanOptions(timing=False))
    assert r.ok, [d.format() for d in r.errors]
    return [(s.kind, s.span.block, s.start_xyz, s.end_xyz, s.center_xyz) for s in r.toolpath]


def test_compensated_contour_with_parameters_matches_literal_numbers():
    literal, parametric = _path(LITERAL), _path(WITH_PARAMETERS)
    assert len(literal) == len(parametric) > 6
    for a, b in zip(literal, parametric, strict=True):
        assert a[:2] == b[:2]
        for pa, pb in zip(a[2:], b[2:], strict=True):
            assert (pa is None) == (pb is None)
            if pa is not None:
                assert max(abs(u - v) for u, v in zip(pa, pb, strict=True)) <= 1e-9


# ---------------------------------------------------------------- located errors
@pytest.mark.parametrize(
    ("text", "code", "line", "column", "block", "fragment"),
    [
        ("N10 G1 X=LEN F100\nM30", "12550", 1, 10, "N10", "LEN"),
        ("N10 R1=5\nN20 G1 X=R1+DEPTH F100\nN30 DEF REAL DEPTH\nM30", "12550", 2, 13, "N20", "DEPTH"),
        ("N10 R1=5\nN20 DEF REAL DEPTH\nM30", "14500", 2, 5, "N20", "DEF"),
        ("N10 G0 X0\nN20 DEF INT K1\nM30", "14500", 2, 5, "N20", "DEF"),
        ("N10 R1=0\nN20 G1 X=10/R1 F100\nM30", "NC-EXPRESSION", 2, 12, "N20", "division by zero"),
        ("N10 R1=2\nN20 R2=5 MOD (R1-2)\nM30", "NC-EXPRESSION", 2, 10, "N20", "division by zero"),
        ("N10 G1 X=10/0 F100\nM30", "NC-EXPRESSION", 1, 12, "N10", "division by zero"),
        ("N10 DEF REAL AA=1/0\nM30", "NC-EXPRESSION", 1, 18, "N10", "division by zero"),
        ("N10 G1 X=R7 F100\nM30", "NC-PARAM-UNSET", 1, 10, "N10", "R7"),
        ("N10 R1=SQRT(R1)\nM30", "NC-PARAM-UNSET", 1, 13, "N10", "R1"),
        ("N10 G1 X=SQRT(-4) F100\nM30", "NC-EXPRESSION", 1, 10, "N10", "SQRT"),
        ("N10 G1 X=2*(3 F100\nM30", "NC-SYNTAX", 1, 8, "N10", "unbalanced"),
        ("N10 DEF REAL X\nM30", "NC-SYNTAX", 1, 14, "N10", "name X"),
        ("N10 DEF REAL DISR\nM30", "NC-SYNTAX", 1, 14, "N10", "keyword"),
        ("N10 DEF LONG AB\nM30", "NC-SYNTAX", 1, 9, "N10", "data type"),
        ("N10 DEF REAL AB, AB\nM30", "NC-SYNTAX", 1, 18, "N10", "twice"),
        ("N10 DEF REAL TT[2]\nN20 TT[2]=1\nM30", "NC-SYNTAX", 2, 5, "N20", "outside"),
        ("N10 AX[X]=10\nM30", "NC-UNSUPPORTED", 1, 5, "N10", "indexed"),
    ],
)
def test_errors_are_located(text, code, line, column, block, fragment):
    err = error_of(text)
    assert (err.code, err.span.line, err.span.column, err.span.block) == (code, line, column, block), err.format()
    assert fragment in err.message


def test_nothing_after_an_error_is_planned():
    r = plan(
        "N10 $TC_DP1[1,1]=120 $TC_DP6[1,1]=3\nN20 T1 D1 G0 X0 Y0 Z5\nN30 R1=0\nN40 G1 Z=-50/R1 F100\nN50 X10\nM30\n",
        file="e.mpf",
        options=PlanOptions(timing=False),
    )
    assert not r.ok and r.errors[0].code == "NC-EXPRESSION"
    assert all(seg.span.line < 4 for seg in r.toolpath)


def test_a_jump_to_a_missing_label_is_alarm_14080():
    err = error_of("R1=1\nGOTOF END\nM30")
    assert err.alarm == 14080 and "END" in err.message and err.span.line == 2
