"""The RS274NGC language of LinuxCNC's interpreter: parameters, expressions, O-word
control flow, subroutines (also from a file beside the program) and their errors.

Every expected value below is a fact measured with LinuxCNC's own ``rs274`` (a build of LinuxCNC
commit 5c41560e, ``rs274 -t sim.tbl -g PROGRAM.ngc``) on these very programs: the end points of
its STRAIGHT_TRAVERSE/STRAIGHT_FEED/ARC_FEED calls, and the first line of its error output. The
tests run without rs274; where it is installed (``$RS274`` or ``/tmp/lcnc/bin/rs274``),
``test_stored_values_are_rs274s`` re-measures them.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from trcopt.controllers.linuxcnc import ngc_flow
from trcopt.controllers.linuxcnc.reader import read_rs274
from trcopt.errors import Severity
from trcopt.nc.model import MoveKind
from trcopt.pipeline import PlanOptions, plan, plan_file

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_lcnc_pairs import PEER, TOL, segment_deviation  # noqa: E402

RS274 = os.environ.get("RS274") or shutil.which("rs274") or "/tmp/lcnc/bin/rs274"
SIM_TBL = PEER / "_default-tooltable" / "sim.tbl"

PROGRAMS = {
    "params": "G21 F100\n#1=5 G1 X#1\nG1 X#1 Y2\n#1=1 #1=2 #2=#1\nG1 X#1 Y#2\n#<a>=3 #<_g>=[#<a>+1]\n#<a>=7\n"
    "G1 X#<a> Y#<_g>\n#3=2\nG1 X##3 Y#[1+2] Z-#1\n#<Mixed Case>=4\n"
    "G1 X#<mixedcase> Y[EXISTS[#<nope>]] Z[EXISTS[#<mixed case>]]\nM2\n",
    "exprs": "G21 F100\nG1 X[1+2*3-4/2] Y[2**3**2] Z[-2**2]\nG1 X[10 MOD 3] Y[-7 MOD 3] Z[7.5 MOD -2]\n"
    "G1 X[1 OR 0 AND 0] Y[1+2 LT 4] Z[3 XOR 0]\nG1 X[1 EQ 1.0000001] Y[2 GE 2.0000001] Z[2 GT 2]\n"
    "G1 X[SIN[30]] Y[COS[60]] Z[TAN[45]]\nG1 X[ASIN[0.5]] Y[ACOS[0.5]] Z[ATAN[1]/[-1]]\n"
    "G1 X[ABS[-3.5]] Y[EXP[1]] Z[LN[10]]\nG1 X[SQRT[2]] Y[ROUND[2.5]] Z[ROUND[-2.5]]\n"
    "G1 X[FIX[-2.5]] Y[FUP[-2.5]] Z[FIX[2.7]]\nG1 X-[1+1] Y[-[2]] Z[--1]\n"
    "G1 X[[1+2]*[3+4]] Y[2*3**2] Z[1 NE 2 AND 3 LE 3]\nG1 X[ATAN[0]/[-1]] Y[ATAN[-1]/[0]] Z[1 LT 2 LT 3]\n"
    "g1 x[abs[-1]] y[sin[90]*2] z0\nG1 X 1 . 5 Y - 2 Z0\nM2\n",
    "ifs": "G21 F100\n#1=2\no1 if [#1 EQ 1]\nG1 X1\no1 elseif [#1 EQ 2]\nG1 X2\no1 elseif [#1 GT 1]\nG1 X3\n"
    "o1 else\nG1 X4\no1 endif\no2 if [#1 LT 0]\nG1 Y1\no2 else\nG1 Y2\no2 endif\no3 if [0]\nG1 Z9\n"
    "o3 endif\no4 if [1]\no5 if [0]\nG1 X9\no5 else\nG1 X5\no5 endif\no4 endif\nM2\n",
    "whiles": "G21 F100\n#1=0\no1 while [#1 LT 5]\n#1=[#1+1]\no2 if [#1 EQ 2]\no1 continue\no2 endif\n"
    "o3 if [#1 EQ 4]\no1 break\no3 endif\nG1 X#1\no1 endwhile\nG1 Y1\n#2=0\no4 while [#2 LT 3]\n#3=0\n"
    "o5 while [#3 LT 2]\nG1 X#2 Y#3\n#3=[#3+1]\no5 endwhile\n#2=[#2+1]\no4 endwhile\no6 while [0]\nG1 Z9\n"
    "o6 endwhile\nM2\n",
    "dowhile": "G21 F100\n#1=0\no1 do\n#1=[#1+1]\nG1 X#1\no1 while [#1 LT 3]\n#1=10\no2 do\nG1 Y#1\n"
    "o2 while [#1 LT 3]\n#1=0\no3 do\n#1=[#1+1]\no4 if [#1 EQ 2]\no3 break\no4 endif\nG1 Z#1\n"
    "o3 while [#1 LT 5]\nM2\n",
    "repeats": "G21 F100\n#1=0\no1 repeat [3]\n#1=[#1+1]\nG1 X#1\no1 endrepeat\no2 repeat [2.5]\nG1 Y#1\n"
    "#1=[#1+1]\no2 endrepeat\no3 repeat [0]\nG1 Z9\no3 endrepeat\no4 repeat [2]\no5 repeat [2]\nG1 Z#1\n"
    "#1=[#1-1]\no5 endrepeat\no4 endrepeat\nM2\n",
    "subs": "G21 F100\n#1=7 #2=8\n#<loc>=1\no<sq> sub\n#<loc>=[#1*2]\nG1 X#1 Y#2\nG1 X#<loc> Y#3\n"
    "o<sq> endsub\no100 sub\no<sq> call [#1+1] [#2] [#<_k>]\no100 return [#1*10]\no100 endsub\n#<_k>=3\n"
    "o<sq> call [1] [2]\nG1 X#1 Y#2 Z#<loc>\no100 call [4] [5]\nG1 X#<_value> Y#1 Z#<_value_returned>\n"
    "o<sq> call\nG1 X#1 Y#2\nM2\n",
    "recursion": "G21 F100\no<fact> sub\no1 if [#1 LE 1]\no<fact> return [1]\no1 endif\no<fact> call [#1-1]\n"
    "o<fact> return [#1*#<_value>]\no<fact> endsub\no<fact> call [5]\nG1 X#<_value>\no<tri> sub\n"
    "o2 if [#1 GT 0]\nG1 X#1 Y[#1*#1]\no<tri> call [#1-1]\no2 endif\no<tri> endsub\no<tri> call [3]\nM2\n",
    "forward": "G21 F100\no<later> call [3] [4]\nG1 Z1\nM2\no<later> sub\nG1 X#1 Y#2\no<later> endsub\n",
}

# rs274's end points (mm) of every motion of PROGRAMS, in order
ENDS = {
    "params": [(0.0, 0.0, 0.0), (5.0, 2.0, 0.0), (2.0, 5.0, 0.0), (7.0, 1.0, 0.0), (5.0, 2.0, -2.0), (4.0, 0.0, 1.0)],
    "exprs": [(5.0, 64.0, 4.0), (1.0, 2.0, 1.5), (0.0, 1.0, 1.0), (1.0, 1.0, 0.0), (0.5, 0.5, 1.0),
              (30.0, 60.0, 135.0), (3.5, 2.7183, 2.3026), (1.4142, 3.0, -3.0), (-3.0, -2.0, 2.0),
              (-2.0, -2.0, 1.0), (21.0, 18.0, 1.0), (180.0, -90.0, 1.0), (1.0, 2.0, 0.0), (1.5, -2.0, 0.0)],
    "ifs": [(2.0, 0.0, 0.0), (2.0, 2.0, 0.0), (5.0, 2.0, 0.0)],
    "whiles": [(1.0, 0.0, 0.0), (3.0, 0.0, 0.0), (3.0, 1.0, 0.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0),
               (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (2.0, 0.0, 0.0), (2.0, 1.0, 0.0)],
    "dowhile": [(1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (3.0, 0.0, 0.0), (3.0, 10.0, 0.0), (3.0, 10.0, 1.0)],
    "repeats": [(1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (3.0, 0.0, 0.0), (3.0, 3.0, 0.0), (3.0, 4.0, 0.0),
                (3.0, 4.0, 5.0), (3.0, 4.0, 4.0), (3.0, 4.0, 3.0), (3.0, 4.0, 2.0)],
    "subs": [(1.0, 2.0, 0.0), (2.0, 0.0, 0.0), (7.0, 8.0, 1.0), (5.0, 5.0, 1.0), (10.0, 3.0, 1.0),
             (40.0, 7.0, 1.0), (0.0, 0.0, 1.0), (0.0, 0.0, 1.0), (7.0, 8.0, 1.0)],
    "recursion": [(120.0, 0.0, 0.0), (3.0, 9.0, 0.0), (2.0, 4.0, 0.0), (1.0, 1.0, 0.0)],
    "forward": [(3.0, 4.0, 0.0), (3.0, 4.0, 1.0)],
}  # fmt: skip

# program (G21 F100 first) -> rs274's message, the line trcopt reports, its code
ERRORS = {
    "G1 X1\n#1=0\nN40 G1 X[2/#1]\nM2\n": ("Attempt to divide by zero", 4, "LCNC-EXPRESSION"),
    "G1 X1\nG1 Y#<nope>\nM2\n": ("Named parameter #<nope> not defined", 3, "LCNC-PARAMETER"),
    "G1 X#5602\nM2\n": ("Parameter number out of range", 2, "LCNC-PARAMETER"),
    "G1 X1\no<nothere> call [1]\nG1 X2\nM2\n": (
        "EOF in file:{name} seeking o-word: o<nothere> from line: 3", 5, "LCNC-OWORD"),
    "o100 sub\nG1 X1\nM2\n": ("File ended with no percent sign (%) or program end (M2)", 2, "LCNC-OWORD"),
    "o1 if [0]\nG1 X1\nM2\n": ("File ended with no percent sign (%) or program end (M2)", 2, "LCNC-OWORD"),
    "G1 X[ACOS[1.5]]\nM2\n": ("Argument to acos out of range", 2, "LCNC-EXPRESSION"),
    "G1 X[LN[0]]\nM2\n": ("Zero or negative argument to ln", 2, "LCNC-EXPRESSION"),
    "G1 X[SQRT[-1]]\nM2\n": ("Negative argument to sqrt", 2, "LCNC-EXPRESSION"),
    "G1 X[[-2]**0.5]\nM2\n": ("Attempt to raise negative to non integer power", 2, "LCNC-EXPRESSION"),
    "G1 X[5 MOD 0]\nM2\n": ("Calculation resulted in 'not a number'", 2, "LCNC-EXPRESSION"),
    "G1 X[ATAN[1]]\nM2\n": ("Slash missing after first atan argument", 2, "NC-SYNTAX"),
    "G1 X1\no1 endwhile\nM2\n": ("3: undefined O-word label: 'o1 endwhile'", 3, "LCNC-OWORD"),
    "o1 if [1]\nG1 X1\no1 endif\no1 if [1]\nG1 X2\no1 endif\nM2\n": (
        "5: duplicate O-word label - already defined in line 2: 'o1 if [1]'", 5, "LCNC-OWORD"),
    "o1 endsub\nM2\n": ("2: not in a subroutine definition: 'o1 endsub'", 2, "LCNC-OWORD"),
    "o1 sub\no2 sub\no2 endsub\no1 endsub\nM2\n": ("Nested subroutine definition", 3, "LCNC-OWORD"),
    "o1 sub\no1 call\no1 endsub\no1 call\nM2\n": ("Too many subroutine levels", 3, "LCNC-OWORD"),
    "o1 frobnicate\nM2\n": ("Unknown control command in o word", 2, "LCNC-OWORD"),
    "#1 5\nM2\n": ("Equal sign missing in parameter setting", 2, "NC-SYNTAX"),
    "G1 X[1 F10\nM2\n": ("Unknown operation", 2, "NC-SYNTAX"),
    "G1 X[FOO[1]]\nM2\n": ("Unknown word starting with f", 2, "NC-SYNTAX"),
    "o1 while [0]\no1 endwhile\no1 else\nM2\n": (
        "4: no matching 'if' label: 'o1 else' (found 'while' in line 2)", 4, "LCNC-OWORD"),
    "o1 if [1]\no1 break\no1 endif\nM2\n": (
        "3: no matching while/do label: 'o1 break' (found 'if' in line 2)", 3, "LCNC-OWORD"),
    "o1 sub\no1 endsub\no1 call" + "".join(f"[{i}]" for i in range(31)) + "\nM2\n": (
        "Too many subroutine parameters", 4, "LCNC-OWORD"),
    "o1 if 1\no1 endif\nM2\n": ("Left bracket missing after 'if'", 2, "LCNC-OWORD"),
    "o1 if [1] G1\no1 endif\nM2\n": ("Unexpected character after O-word", 2, "NC-SYNTAX"),
    "G1 X1 (a (b) c)\nM2\n": ("Nested comment found", 2, "NC-SYNTAX"),
    "G1 X#1.5\nM2\n": ("Non integer value for integer", 2, "LCNC-EXPRESSION"),
    "o<a> call\no<a> sub\nG1 X1\no<a> endsub\nM2\n": (
        "File:{name} line:3 sub: o|a| found in illegal location", 3, "LCNC-OWORD"),
    "o<a> sub\no<a> endsub\no<a> sub\no<a> endsub\nM2\n": (
        "File:{name} line:4 redefining sub: o|a| already defined in file:{name}", 4, "LCNC-OWORD"),
}  # fmt: skip

# compensated contours written with a loop: rs274's tool-centre end points (program units)
POLYGON_41 = (
    "G21 G17 G90 F300\n#<n>=6 #<r>=20\nG0 X[#<r>+10] Y0\nG41.1 D4\nG1 X#<r> Y0\n#<i>=1\n"
    "o1 while [#<i> LE #<n>]\nG1 X[#<r>*COS[360*#<i>/#<n>]] Y[#<r>*SIN[360*#<i>/#<n>]]\n#<i>=[#<i>+1]\n"
    "o1 endwhile\nG40 G1 X[#<r>+10] Y0\nM2\n"
)
POLYGON_41_ENDS = [(30.0, 0.0), (20.0, -2.0), (18.2679, -1.0), (8.8453, 15.3205), (-8.8453, 15.3205),
                   (-17.6906, 0.0), (-8.8453, -15.3205), (8.8453, -15.3205), (18.2679, 1.0), (30.0, 0.0)]  # fmt: skip
POLYGON_42 = (
    "G20 G17 G90 F30\nT1 M6\n#<n>=5\nG0 X2 Y-2\nG42 D1\nG1 X1 Y0\no<k> repeat [#<n>]\n#<i>=[#<i>+1]\n"
    "G1 X[COS[360*#<i>/#<n>]] Y[SIN[360*#<i>/#<n>]]\no<k> endrepeat\nG40 G0 X2 Y2\nM2\n"
)
POLYGON_42_ENDS = [(2.0, -2.0), (1.0559, 0.028), (1.0506, 0.0367), (0.3596, 0.9878), (0.2897, 1.0105),
                   (-0.8283, 0.6472), (-0.8715, 0.5878), (-0.8715, -0.5878), (-0.8283, -0.6472),
                   (0.2897, -1.0105), (0.3596, -0.9878), (1.0506, -0.0367), (2.0, 2.0)]  # fmt: skip


def _ends(text: str, file: str = "t.ngc") -> list[tuple[float, ...]]:
    prog = read_rs274(text, file=file)
    errors = [d.format() for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert not errors, errors
    return [m.end for m in prog.moves if m.kind is not MoveKind.NONE]


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_program_reads_as_rs274_does(name: str) -> None:
    ours = _ends(PROGRAMS[name])
    assert len(ours) == len(ENDS[name])
    for got, want in zip(ours, ENDS[name], strict=True):
        assert got == pytest.approx(want, abs=1e-4)


def test_a_blocks_settings_take_effect_after_the_block() -> None:
    # LinuxCNC reads every value of the line before any of its settings: X, Y and #2 see the old
    # #1 and #2 (rs274: the same two end points)
    assert _ends("#1=3\n#1=5 #2=#1 G1 X#1 Y#2 F1\nG1 X#1 Y#2\n") == [(3.0, 0.0, 0.0), (5.0, 3.0, 0.0)]


@pytest.mark.parametrize("text", sorted(ERRORS))
def test_errors_are_linuxcncs(text: str, tmp_path: Path) -> None:
    message, line, code = ERRORS[text]
    path = tmp_path / "e.ngc"
    path.write_text("G21 F100\n" + text)
    prog = read_rs274(path.read_text(), file=str(path))
    errors = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert errors, "no error"
    err = errors[0]
    assert (err.message, err.span.line, err.code) == (message.format(name=path.name), line, code)
    assert err.span.file == str(path) and err.span.column >= 1


def test_error_points_at_the_word_and_carries_the_block_number() -> None:
    prog = read_rs274("G21 F100\nN30 G1 X1 Y[1/0]\n", file="p.ngc")
    err = prog.diagnostics[0]
    assert (err.span.line, err.span.column, err.span.block) == (2, 12, "N30")
    assert err.message == "Attempt to divide by zero"


def test_subroutine_file_beside_the_program(tmp_path: Path) -> None:
    main = tmp_path / "main.ngc"
    main.write_text("G21 F100\n#<_depth>=-1\no<pocket> call [10] [5]\nG1 X0 Y0\no<pocket> call [2] [3]\nM2\n")
    (tmp_path / "pocket.ngc").write_text("o<pocket> sub\nG1 X#1 Y#2 Z#<_depth>\nG1 X[#1+#2]\no<pocket> endsub\nM2\n")
    ends = _ends(main.read_text(), file=str(main))
    # rs274 (run in that directory): the same five end points
    assert ends == [(10.0, 5.0, -1.0), (15.0, 5.0, -1.0), (0.0, 0.0, -1.0), (2.0, 3.0, -1.0), (5.0, 3.0, -1.0)]
    (tmp_path / "pocket.ngc").write_text("o<pocket> sub\nG1 X[1/0]\no<pocket> endsub\n")
    err = read_rs274(main.read_text(), file=str(main)).diagnostics[0]
    assert (err.span.file, err.span.line, err.message) == (str(tmp_path / "pocket.ngc"), 2, "Attempt to divide by zero")


def test_an_endless_loop_stops_at_the_stated_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(ngc_flow, "LOOP_LIMIT", 50)
    prog = read_rs274("F10\n#1=0\no1 while [1]\n#1=[#1+1]\no1 endwhile\nM2\n", file="x.ngc")
    err = prog.diagnostics[0]
    assert err.code == "NC-LOOP-LIMIT" and "50" in err.message and err.span.line == 5
    # a loop that ends is not affected however often it runs in total
    loops = "F10\n#2=0\no2 repeat [3]\n#1=0\no1 while [#1 LT 40]\n#1=[#1+1]\no1 endwhile\n#2=[#2+#1]\no2 endrepeat\n"
    ends = _ends(loops + "G1 X#2\n")
    assert ends == [(120.0, 0.0, 0.0)]
    # a finished loop whose end is met again (a duplicated endrepeat) restarts without end: the
    # limit on all jumps back stops it
    monkeypatch.setattr(ngc_flow, "TOTAL_JUMP_LIMIT", 300)
    again = "F10\no3 repeat [1]\nG91 G1 X1\no3 endrepeat\nG90 G1 Y1\no3 endrepeat\nM2\n"
    err = read_rs274(again, file="x.ngc").diagnostics[0]
    assert err.code == "NC-LOOP-LIMIT" and "300 jumps" in err.message and err.span.line in (4, 6)


@pytest.mark.parametrize(
    ("text", "ends", "unit"), [(POLYGON_41, POLYGON_41_ENDS, 1.0), (POLYGON_42, POLYGON_42_ENDS, 25.4)]
)
def test_compensated_contour_written_with_a_loop(text: str, ends: list, unit: float, tmp_path: Path) -> None:
    tbl = tmp_path / "tools.tbl"
    tbl.write_text("T1 P1 D0.125 Z0.511\n")  # sim.tbl's T1
    opts = PlanOptions(dialect="rs274", timing=False, tool_table=str(tbl), tool_unit="inch")
    result = plan(text, file="poly.ngc", options=opts)
    assert result.ok, [d.format() for d in result.errors]
    ours = [s.end_xyz for s in result.toolpath]
    assert len(ours) == len(ends)
    for got, want in zip(ours, ends, strict=True):
        assert (got[0] / unit, got[1] / unit) == pytest.approx(want, abs=TOL)


needs_peer = pytest.mark.skipif(not PEER.is_dir(), reason="LinuxCNC peer data not found")


@needs_peer
def test_cam_nisley_runs_as_linuxcnc() -> None:
    """O-word do/while and if loops, parameters and functions, G42 with an inch tool table in a
    G21 program: every motion as LinuxCNC's expected output (its two zero-length moves aside)."""
    import json

    folder = PEER / "interp-cam-nisley"
    expected = json.loads((folder / "expected.segments.json").read_text())
    expected = [e for e in expected if e["start"] != e["end"] or e["type"] == "arc"]
    opts = PlanOptions(dialect="rs274", timing=False, tool_table=str(folder / "test.tbl"), tool_unit="inch")
    result = plan_file(folder / "cam.ngc", opts)
    assert result.ok, [d.format() for d in result.errors]
    assert len(result.toolpath) == len(expected) == 315
    worst = max(segment_deviation(s, e, 1.0) for s, e in zip(result.toolpath, expected, strict=True))
    assert worst <= TOL


@pytest.mark.skipif(not os.path.exists(RS274) or not SIM_TBL.exists(), reason="rs274 not installed")
def test_stored_values_are_rs274s(tmp_path: Path) -> None:
    """Re-measures ENDS and the ERRORS messages with rs274 (optional: needs a LinuxCNC build)."""
    move = re.compile(r"(STRAIGHT_FEED|STRAIGHT_TRAVERSE|ARC_FEED)\(([^)]*)\)")
    for name, text in PROGRAMS.items():
        path = tmp_path / f"{name}.ngc"
        path.write_text(text)
        out = subprocess.run([RS274, "-t", str(SIM_TBL), "-g", path.name], capture_output=True, text=True,
                             cwd=tmp_path, timeout=30).stdout  # fmt: skip
        ends = []
        for m in move.finditer(out):
            v = [float(x) for x in m.group(2).split(",")]
            ends.append(tuple(v[:3]) if m.group(1) != "ARC_FEED" else (v[0], v[1], v[5]))
        assert len(ends) == len(ENDS[name]), name
        for got, want in zip(ends, ENDS[name], strict=True):
            assert got == pytest.approx(want, abs=1e-4), name
    for text, (message, _, _) in ERRORS.items():
        path = tmp_path / "e.ngc"
        path.write_text("G21 F100\n" + text)
        run = subprocess.run([RS274, "-t", str(SIM_TBL), "-g", path.name], capture_output=True, text=True,
                             cwd=tmp_path, timeout=30)  # fmt: skip
        assert message.format(name=path.name) in run.stdout + run.stderr, text


def test_d0_leaves_every_move_as_programmed_and_a_plane_change_keeps_the_position() -> None:
    """LinuxCNC compensates only with a radius > 0: with ``G41.1 D0`` an arc–arc concave corner
    is no error and every move is the programmed one; a later G18 block starts where the tool is."""
    text = (
        "G21 G17 G90 G0 X0 Y0 Z0\nG41.1 D0\nG1 X10 Y0 F100\nG3 X20 Y10 I0 J10\n"
        "G2 X5 Y10 I-7.5 J0\nG40 G1 X0 Y7\nG18\nG0 X5 Z3\nM2\n"
    )
    result = plan(text, file="d0.ngc", options=PlanOptions(dialect="rs274", timing=False))
    assert result.ok, [d.format() for d in result.errors]
    prog = [(s.start_xyz, s.end_xyz) for s in result.programmed]
    tool = [(s.start_xyz, s.end_xyz) for s in result.toolpath]
    assert len(tool) == len(prog)
    for (a0, a1), (b0, b1) in zip(tool, prog, strict=True):
        assert math.dist(a0, b0) < 1e-9 and math.dist(a1, b1) < 1e-9
    last = result.toolpath[-1]
    # the G18 move starts at X0 Y7 Z0 (the position kept across the plane change, not read as G18's
    # own coordinates) and ends at X5 Y7 Z3
    assert math.dist(last.start_xyz, (0.0, 7.0, 0.0)) < 1e-9 and math.dist(last.end_xyz, (5.0, 7.0, 3.0)) < 1e-9
