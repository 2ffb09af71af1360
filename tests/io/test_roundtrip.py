"""Round trip: trcopt's own G-code, planned again, runs at the cycle time the plan reported.

The transitions leave as arc splines with the flavour's continuous-path word; re-planning the
written program (its path-control mode read back) must give the reported cycle time within 2 %.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt import PlanOptions, controllers, plan, plan_file
from trcopt.io.gcode import toolpath_to_gcode

CORNERS = Path(__file__).resolve().parents[2] / "problems" / "corners"


@pytest.mark.parametrize(
    ("problem", "flavor", "suffix"),
    [
        ("corner_30deg", "siemens", ".mpf"),
        ("pocket_square", "linuxcnc", ".ngc"),
        ("cam_quarter_circle", "siemens", ".mpf"),
    ],
)
def test_replanned_output_keeps_the_reported_cycle_time(problem: str, flavor: str, suffix: str) -> None:
    planned = plan_file(CORNERS / f"{problem}.mpf", PlanOptions(corners="optimal"))
    assert planned.ok and planned.extra["corners"]["blended"] > 0
    text = toolpath_to_gcode(planned.toolpath, flavor=controllers.get(flavor).gcode, program_name=problem)
    again = plan(text, file=f"{problem}{suffix}")
    assert again.ok and not [d for d in again.diagnostics if d.code.startswith("VERIFY")]
    assert again.timing.duration == pytest.approx(planned.timing.duration, rel=0.02)
    # and the same path: every written point lies on the planned path to the output resolution
    assert again.path_length == pytest.approx(planned.path_length, abs=0.01)


def test_a_plan_without_transitions_is_written_without_a_continuous_path_word() -> None:
    planned = plan_file(CORNERS / "pocket_square.mpf", PlanOptions(corners="exact"))
    text = toolpath_to_gcode(planned.toolpath, flavor=controllers.get("linuxcnc").gcode)
    assert "G64" not in text
    again = plan(text, file="p.ngc")
    assert again.timing.duration == pytest.approx(planned.timing.duration, rel=0.02)
