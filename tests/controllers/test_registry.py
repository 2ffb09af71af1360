"""The controller registry: names, lookup, detection, and a toy controller added at run time that
plans end to end through the API and the command line without touching any other module."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest

from trcopt import controllers
from trcopt.cli import main
from trcopt.compensation import compensate
from trcopt.controllers.base import Controller
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry import Plane
from trcopt.io.gcode import GcodeFlavor
from trcopt.io.schema import validate_plan
from trcopt.modes import Side
from trcopt.nc.modal import ReadOptions
from trcopt.nc.model import CompState, Move, MoveKind, NcProgram
from trcopt.pipeline import PlanOptions, plan, plan_file

ROOT = Path(__file__).resolve().parents[2]


def test_builtin_names_dialects_and_lookup():
    assert controllers.names() == ("siemens", "heidenhain", "linuxcnc")
    assert controllers.dialects() == ("siemens", "heidenhain", "rs274")
    assert controllers.get("rs274") is controllers.get("LinuxCNC") is controllers.get("linuxcnc")
    with pytest.raises(ValueError, match="valid: heidenhain, linuxcnc, rs274, siemens"):
        controllers.get("fanuc")


@pytest.mark.parametrize(
    ("path", "text", "name"),
    [
        ("a.MPF", "G1 X1 (looks like rs274)", "siemens"),  # the suffix wins over the text
        ("a.spf", "", "siemens"),
        ("a.h", "", "heidenhain"),
        ("a.ngc", "", "linuxcnc"),
        ("a.txt", "0 BEGIN PGM A MM\n", "heidenhain"),
        ("a.txt", "(header)\nG0 X0\n", "linuxcnc"),
        ("a.txt", 'MSG("(not a comment)")\nG0 X0\n', "siemens"),
        (None, "G0 X0\n", "siemens"),  # nothing recognised: the first registered controller
    ],
)
def test_detect(path, text, name):
    assert controllers.detect(path, text).name == name


# --- a toy controller: "GO x y" moves, "LEFT r" / "OFF" compensation, its own output flavour -------
def _read_toy(text: str, options: ReadOptions) -> NcProgram:
    moves: list[Move] = []
    diags: list[Diagnostic] = []
    pos = (0.0, 0.0, 0.0)
    comp = CompState()
    for line, raw in enumerate(text.splitlines(), start=1):
        words = raw.split()
        span = SourceSpan(options.file, line, 1, f"L{line}")
        if not words:
            continue
        if words[0] == "LEFT":
            comp = CompState(side=Side.LEFT, radius=float(words[1]), tool_active=True, side_programmed=True)
            continue
        if words[0] == "OFF":
            comp = CompState(side=Side.OFF, tool_active=True, side_programmed=True)
            continue
        if words[0] != "GO":
            diags.append(Diagnostic(Severity.ERROR, "NC-SYNTAX", f"unknown toy word {words[0]!r}", span))
            break
        end = (float(words[1]), float(words[2]), 0.0)
        moves.append(Move(MoveKind.LINE, pos, end, Plane.G17, span, comp, feed_mm_s=10.0))
        comp = CompState(comp.side, comp.radius, comp.tool_active)  # the side word acts once
        pos = end
    return NcProgram(options.file, "toy", tuple(moves), tuple(diags), blocks=len(text.splitlines()))


def _compensate_toy(moves, settings, diagnostics, complete=True) -> Iterator:
    return compensate(moves, settings, diagnostics, complete=complete)


TOY = Controller(
    name="toy",
    dialect="toy",
    title="Toy controller",
    extensions=(".toy",),
    read=_read_toy,
    compensate=_compensate_toy,
    gcode=GcodeFlavor("toy", paren_comments=True, block_numbers=False, decimal_point=True, preamble=("G21",),
                      end="M2"),
    recognise=lambda text: text.startswith("GO "),
)

SQUARE = "GO 0 -20\nLEFT 5\nGO 0 0\nGO 40 0\nGO 40 30\nGO 0 30\nGO 0 0\nOFF\nGO 0 -20\n"


@pytest.fixture
def toy():
    controllers.register(TOY)
    yield TOY
    controllers.unregister("toy")
    assert "toy" not in controllers.names()


def test_a_registered_controller_plans_through_the_api(toy, tmp_path):
    assert controllers.names()[-1] == "toy" and controllers.detect(None, SQUARE) is toy
    result = plan(SQUARE, file="square.toy", options=PlanOptions(timing=False))
    assert result.ok and result.dialect == "toy" and result.extra["profile"] == "toy"
    # the tool centre runs 5 mm left of the contour (the square's inside): NORM selection ends
    # perpendicular to the first element, inside corners by intersection, NORM deselection
    ends = [tuple(round(v, 9) for v in s.geometry.end[:2]) for s in result.toolpath]
    assert ends == [(0.0, -20.0), (0.0, 5.0), (35.0, 5.0), (35.0, 25.0), (5.0, 25.0), (5.0, 0.0), (0.0, -20.0)]
    path = tmp_path / "square.toy"
    path.write_text(SQUARE)
    assert plan_file(path, PlanOptions(timing=False)).path_length == pytest.approx(result.path_length)


def test_a_registered_controller_is_reachable_from_the_command_line(toy, tmp_path, capsys):
    program = tmp_path / "square.toy"
    program.write_text(SQUARE)
    out_json, out_gcode = tmp_path / "p.json", tmp_path / "p.ngc"
    code = main(["plan", str(program), "--no-timing", "--json", str(out_json), "--gcode", str(out_gcode)])
    assert code == 0
    doc = json.loads(out_json.read_text())
    assert doc["dialect"] == "toy"
    validate_plan(doc)  # the plan JSON contract holds for any registered controller
    text = out_gcode.read_text()
    first_block = next(ln for ln in text.splitlines() if not ln.startswith("("))  # after the header comments
    assert first_block.startswith("G21 G17") and text.rstrip().endswith("M2")
    assert main(["plan", str(program), "--no-timing", "--profile", "toy", "-q"]) == 0


def test_a_name_is_registered_once(toy):
    with pytest.raises(ValueError, match="is registered"):
        controllers.register(TOY)
    with pytest.raises(ValueError, match="built-in"):
        controllers.unregister("siemens")
