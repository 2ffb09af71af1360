"""The corners of a planned tool path as the plan options ask for them (the pipeline's corner
stage): the program's path-control mode, exact stops, or a corner strategy, and the ``corners``
report of the plan JSON.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from trcopt.codes import Code
from trcopt.config import Machine
from trcopt.errors import TrcoptError
from trcopt.modes import CornerObjective, ToleranceKind, TransitionKind
from trcopt.nc.model import Move
from trcopt.optimize.corners import strategies as corner_strategies
from trcopt.optimize.corners.records import CornerRecord
from trcopt.path import Segment

__all__ = ["apply_corners", "check_tolerance", "corner_json"]


def apply_corners(
    toolpath: list[Segment],
    programmed: Sequence[Segment],
    moves: Sequence[Move],
    *,
    mode: str,
    tolerance_mm: float,
    tolerance_kind: ToleranceKind | None,
    machine: Machine,
    workers: int = 1,
    select: bool = True,
    objective: CornerObjective = CornerObjective.CURVATURE,
) -> tuple[list[Segment], list[Segment], dict[str, Any] | None]:
    """(the exact path with the program's exact stops, the path with the corners ``mode`` asks
    for — the same list when no corner is rounded —, the ``corners`` report or None).

    ``program`` merges collinear moves first where the mode says so (LinuxCNC ``G64 Q``), then
    rounds the corners the program's blending modes round; ``exact`` keeps every corner and the
    program's exact stops; another strategy rounds every corner within the program's tolerance
    where it sets one, else ``tolerance_mm`` (larger than half the shortest line it could blend:
    a usage error, :func:`check_tolerance`).
    """
    from trcopt.optimize.corners.program import merge_collinear, path_control_plan, with_stops

    if mode == corner_strategies.PROGRAM:
        toolpath = merge_collinear(toolpath, moves)  # LinuxCNC G64 Q: the controller's own path
    control = path_control_plan(toolpath, moves, tolerance_kind)
    if mode in (corner_strategies.PROGRAM, corner_strategies.EXACT) and (control.stops or control.smooth):
        smooth = control.smooth if mode == corner_strategies.PROGRAM else frozenset()
        toolpath = with_stops(toolpath, control.stops, smooth)
    if mode == corner_strategies.EXACT or (mode == corner_strategies.PROGRAM and not control.blends):
        return toolpath, toolpath, None
    from trcopt.optimize.corners.blend import blend_corners

    if mode != corner_strategies.PROGRAM:
        check_tolerance(toolpath, control.tolerances, tolerance_mm)
    kinds = {s.kind for s in control.blends.values() if s.kind is not ToleranceKind.DISTANCE}
    kind = tolerance_kind or (kinds.pop() if len(kinds) == 1 else ToleranceKind.CONTOUR)
    blended = blend_corners(
        toolpath,
        programmed,
        tolerance_mm=tolerance_mm,
        machine=machine,
        mode=mode,
        workers=workers,
        select=select,
        # under jerk limits the transitions minimise the curvature rate as well (needs X/Y jerk
        # limits; without them the jerk stage warns and the acceleration-limited feed is kept)
        objective=objective,
        # runs of small deflections become one G2 spline in both modes (benchmarks/JERK.md)
        chains=True,
        kind=kind,
        tolerances=control.tolerances,
        program=control.blends,
    )
    records = [c for c in blended.corners if c.blended]
    vertex = [c.vertex_mm for c in records if c.vertex_mm is not None]
    contour = [c.contour_mm for c in records if c.contour_mm is not None]
    tolerances = set(control.tolerances.values())
    report = {
        "mode": mode,
        # the program's own blending: the smallest tolerance it sets, None where it sets none
        # (LinuxCNC G64 without P: as large as the moves allow)
        "tolerance_mm": tolerance_mm if mode != corner_strategies.PROGRAM else min(tolerances, default=None),
        "tolerance_kind": kind.value,
        "path_control": list(control.words),
        "objective": None if blended.objective is None else blended.objective.value,
        "blended": blended.blended,
        "quintic": blended.count(TransitionKind.QUINTIC),
        "spline": blended.count(TransitionKind.SPLINE),
        "curvature_jumps": blended.curvature_jumps,
        "arc": blended.count(TransitionKind.ARC),
        "max_deviation_mm": blended.max_deviation_mm,
        "max_vertex_mm": max(vertex, default=None),
        "max_contour_mm": max(contour, default=None),
        "corners": [corner_json(c, toolpath) for c in blended.corners],
    }
    return toolpath, blended.segments, report


def check_tolerance(toolpath: list[Segment], program: dict[int, float], tolerance_mm: float) -> None:
    """``--tolerance`` larger than half the shortest line it could blend (a corner without a
    tolerance of the program's own) is a usage error naming the value and the line."""
    from trcopt.optimize.corners.fillet import line_joints  # numpy: only when corners are rounded

    shortest: tuple[float, Segment] | None = None
    for k in line_joints(toolpath):
        if k in program:
            continue
        for seg in (toolpath[k], toolpath[k + 1]):
            if shortest is None or seg.geometry.length < shortest[0]:
                shortest = (seg.geometry.length, seg)
    if shortest is not None and tolerance_mm > 0.5 * shortest[0]:
        length, seg = shortest
        where = f"line {seg.span.line}" + (f" ({seg.span.block})" if seg.span.block else "")
        raise TrcoptError(
            f"--tolerance {tolerance_mm:g} mm is larger than half the shortest element it could blend "
            f"({length:.6g} mm at {where}); choose at most {0.5 * length:.6g} mm",
            code=Code.USAGE,
        )


def corner_json(c: CornerRecord, toolpath: list[Segment]) -> dict[str, Any]:
    """One corner of the ``corners`` report (the joint's source block is the block that ends there)."""
    span = toolpath[c.index].span
    return {
        "joint": c.index,
        "line": span.line,
        "block": span.block,
        "turn_deg": round(c.turn_deg, 9),
        "blended": c.blended,
        "transition": None if c.transition is None else c.transition.value,
        "tolerance_mm": c.tolerance_mm,
        "radius_mm": c.radius_mm,
        "vertex_mm": c.vertex_mm,
        "contour_mm": c.contour_mm,
        "reason": c.reason,
    }
