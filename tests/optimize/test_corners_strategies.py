"""The registry of corner strategies: names from one place, unknown names rejected with the valid
ones, a strategy added at run time with one registration line, no numerical library to name them."""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.errors import TrcoptError
from trcopt.modes import CornerObjective
from trcopt.optimize.corners import CornerRecord, CornerResult, find_corner_sites, strategies
from trcopt.optimize.corners.strategies import CornerJob, CornerStrategy
from trcopt.pipeline import PlanOptions, plan_file

ROOT = Path(__file__).resolve().parents[2]
CORNER = ROOT / "problems" / "corners" / "corner_30deg.mpf"

JOBS: list[CornerJob] = []  # what the toy strategy was asked to do


def record_only(job: CornerJob) -> CornerResult:
    """A toy strategy: every corner stays as it is, and is recorded."""
    JOBS.append(job)
    segs = list(job.toolpath)
    sites = find_corner_sites(segs, job.programmed, tolerance_mm=job.tolerance_mm)
    records = [
        CornerRecord(k, math.degrees(site.turn), site.inside, False, job.tolerance_mm, reason="toy: left as it is")
        for k, site in sites
    ]
    return CornerResult(segs, records, 0.0, job.strategy)


@pytest.fixture
def toy() -> Iterator[CornerStrategy]:
    JOBS.clear()
    # the one line that adds a strategy (a built-in one goes into strategies._BUILTIN instead)
    strategy = strategies.register(CornerStrategy("toy", __name__, "record_only", "leaves every corner, records it"))
    try:
        yield strategy
    finally:
        strategies.unregister("toy")


def test_builtin_names_in_registration_order() -> None:
    assert strategies.names() == ("program", "exact", "optimal", "arc")
    assert strategies.get(" Optimal ").name == "optimal" and strategies.EXACT == "exact"
    assert PlanOptions().corners == "program" and PlanOptions(corners="ARC").corners == "arc"


def test_unknown_name_is_rejected_with_the_valid_ones() -> None:
    message = "unknown corner strategy 'smooth'; valid: program, exact, optimal, arc"
    with pytest.raises(ValueError, match=f"^{message}$"):
        strategies.get("smooth")
    with pytest.raises(TrcoptError, match=f"^--corners: {message}$") as exc:
        PlanOptions(corners="smooth")
    assert exc.value.code == "USAGE"


def test_registry_guards_its_names_and_the_builtins(toy: CornerStrategy) -> None:
    with pytest.raises(ValueError, match="'toy' is registered"):
        strategies.register(toy)
    with pytest.raises(ValueError, match="lower case"):
        strategies.register(CornerStrategy("Toy 2", __name__, "record_only", ""))
    with pytest.raises(ValueError, match="'arc' is a built-in"):
        strategies.unregister("arc")


def test_a_strategy_registered_at_run_time_runs_through_the_pipeline(toy: CornerStrategy) -> None:
    assert strategies.names() == ("program", "exact", "optimal", "arc", "toy")
    exact = plan_file(CORNER, PlanOptions(timing=False))
    result = plan_file(CORNER, PlanOptions(corners="toy", tolerance_mm=0.05, timing=False))
    (job,) = JOBS
    assert job.strategy == "toy" and job.tolerance_mm == 0.05 and job.objective is CornerObjective.CURVATURE
    assert result.toolpath == exact.toolpath
    report = dict(result.extra["corners"])
    listed = report.pop("corners")
    assert listed and not any(c["blended"] for c in listed)  # the toy strategy's records, none blended
    assert report == {
        "mode": "toy",
        "tolerance_mm": 0.05,
        "tolerance_kind": "contour",
        "path_control": [],
        "objective": None,
        "blended": 0,
        "quintic": 0,
        "spline": 0,
        "curvature_jumps": 0,
        "arc": 0,
        "max_deviation_mm": 0.0,
        "max_vertex_mm": None,
        "max_contour_mm": None,
    }
    assert "corners toy within 0.05 mm: 0 blended" in result.summary()
    strategies.unregister("toy")
    try:
        with pytest.raises(TrcoptError, match="valid: program, exact, optimal, arc$"):
            PlanOptions(corners="toy")
    finally:
        strategies.register(toy)  # the fixture unregisters it


def test_the_command_line_offers_the_registered_strategies(toy: CornerStrategy, tmp_path: Path, capsys) -> None:
    out = tmp_path / "plan.json"
    assert main(["plan", str(CORNER), "--no-timing", "--corners", "toy", "--json", str(out)]) == 0
    assert json.loads(out.read_text())["corners"]["mode"] == "toy" and len(JOBS) == 1
    with pytest.raises(SystemExit) as exc:
        main(["plan", str(CORNER), "--corners", "smooth"])
    assert exc.value.code == 2
    assert "(choose from 'program', 'exact', 'optimal', 'arc', 'toy')" in capsys.readouterr().err
