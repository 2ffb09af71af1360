"""The public API is importable from ``trcopt`` and each name is the stage's own object."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import trcopt

ROOT = Path(__file__).resolve().parents[1]
STAGES = {
    "plan": "trcopt.pipeline",
    "plan_file": "trcopt.pipeline",
    "PlanOptions": "trcopt.pipeline",
    "PlanResult": "trcopt.pipeline",
    "read_program": "trcopt.controllers",
    "compensate": "trcopt.compensation.engine",
    "time_parameterize": "trcopt.timing.solve",
    "Trajectory": "trcopt.trajectory",
    "Side": "trcopt.modes",
}


@pytest.mark.parametrize("name", sorted(STAGES))
def test_public_names(name: str) -> None:
    assert name in trcopt.__all__ and name in dir(trcopt)
    assert getattr(trcopt, name).__module__ == STAGES[name]


def test_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no_such_name"):
        trcopt.no_such_name  # noqa: B018


def test_plan_through_the_top_level_names() -> None:
    program = ROOT / "problems" / "siemens" / "ex02_square_g450.mpf"
    result = trcopt.plan_file(program, trcopt.PlanOptions(timing=True))
    assert result.ok and isinstance(result.timing, trcopt.Trajectory)
    nc = trcopt.read_program(program)  # a path: read from the file, the controller by its suffix
    assert nc.dialect == "siemens" and len(nc.moves) == len(result.nc.moves) > 0
    diagnostics: list[trcopt.Diagnostic] = []
    toolpath = list(trcopt.compensate(nc.moves, trcopt.TrcSettings(), diagnostics))
    assert [s.geometry for s in toolpath] == [s.geometry for s in result.toolpath] and diagnostics == []
    timed = trcopt.time_parameterize(toolpath, trcopt.DEFAULT_MACHINE)
    assert timed.duration == pytest.approx(result.duration)


def test_stage_names_load_on_first_use() -> None:
    code = (
        "import sys, trcopt\n"
        "assert 'trcopt.pipeline' not in sys.modules\n"
        "trcopt.plan\n"
        "print('trcopt.pipeline' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"
