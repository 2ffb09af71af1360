"""APPR/DEP CT/LCT radius (spec heidenhain_trc.md R9, revised): ``R`` is the radius of the
tool-centre arc by default, as the TNC 426/430 manual's example programs need (tool R10 with
``APPR LCT … R5``); the contour reading stays a setting (PlanOptions and ``--appr-radius``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.pipeline import PlanOptions, plan

# in the style of the manual's "CIRCULAR" example: a tool of radius 10, an approach arc of 5
PROGRAM = """0 BEGIN PGM CIRC MM
1 TOOL DEF 1 L+0 R+10
2 TOOL CALL 1 Z S3000
3 L X+50 Y+50 Z+2 R0 FMAX
4 L Z-5 F1000
5 CC X+50 Y+50
6 APPR LCT X+80 Y+50 R5 RL F300
7 C X+80 Y+50 DR+
8 DEP LCT X+50 Y+50 R5
9 L Z+2 R0 FMAX
10 END PGM CIRC MM
"""


def test_the_default_reading_plans_the_manual_style_approach():
    r = plan(PROGRAM, file="circ.h", options=PlanOptions(timing=False))
    assert r.ok, [d.message for d in r.errors]
    arcs = [s for s in r.toolpath if s.kind == "arc" and s.span.block == "6"]
    assert arcs and abs(arcs[0].geometry.radius - 5.0) < 1e-9  # the tool centre runs on R5


def test_the_contour_reading_is_a_setting():
    r = plan(PROGRAM, file="circ.h", options=PlanOptions(timing=False, appr_radius="contour"))
    assert not r.ok
    assert any(d.code == "HH-TOOL-RADIUS-TOO-LARGE" and d.span.block == "6" for d in r.errors)
    with pytest.raises(ValueError, match="valid: contour, centre"):
        PlanOptions(appr_radius="tool")


def test_the_command_line_chooses_the_reading(tmp_path: Path, capsys):
    prog = tmp_path / "circ.h"
    prog.write_text(PROGRAM)
    assert main(["plan", str(prog), "--no-timing"]) == 0
    capsys.readouterr()
    assert main(["plan", str(prog), "--no-timing", "--appr-radius", "contour"]) == 1
    out = capsys.readouterr()
    assert "HH-TOOL-RADIUS-TOO-LARGE" in out.out + out.err
