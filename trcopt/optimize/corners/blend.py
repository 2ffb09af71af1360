"""Tolerance-bounded corner transitions of the tool-centre path: the entry point.

With exact geometry the tool stops at every tangent discontinuity of the tool-centre path. Given a
contour tolerance ε (mm), :func:`blend_corners` replaces each such corner by the transition of a
corner strategy looked up by name in :mod:`~trcopt.optimize.corners.strategies` (``exact``,
``arc``, ``optimal``, or one registered at run time); :func:`optimize_corners` returns the new path
only.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.errors import ConfigError
from trcopt.modes import CornerObjective, ToleranceKind, parse_enum
from trcopt.optimize.corners import strategies
from trcopt.optimize.corners.records import CornerResult
from trcopt.path import Segment

if TYPE_CHECKING:
    from trcopt.optimize.corners.fillet import FilletSpec

__all__ = ["blend_corners", "optimize_corners"]


def blend_corners(
    toolpath: Sequence[Segment],
    programmed: Sequence[Segment],
    *,
    tolerance_mm: float,
    machine: Machine | None = None,
    mode: str = "optimal",
    workers: int = 1,
    select: bool = True,
    objective: CornerObjective | str = CornerObjective.CURVATURE,
    chains: bool = True,
    kind: ToleranceKind | str = ToleranceKind.CONTOUR,
    tolerances: Mapping[int, float] | None = None,
    program: Mapping[int, FilletSpec] | None = None,
) -> CornerResult:
    """Replace tangent discontinuities by transitions within the contour tolerance.

    Parameters
    ----------
    toolpath:
        Exact tool-centre path (output of compensation).
    programmed:
        The programmed (uncompensated) path: the no-gouge and deviation reference.
    tolerance_mm:
        Contour tolerance ε, mm: material left beyond the exact cut ≤ ε. A tolerance ≤ 0 leaves
        every corner as it is.
    machine:
        Axis limits for the choice between G2 and circular transitions (``select``) and for the
        ``jerk`` objective (the default machine when omitted).
    mode:
        The corner strategy's registry name (:func:`trcopt.optimize.corners.strategies.names`):
        ``"optimal"`` (G2 quintics by SQP), ``"arc"`` (largest same-ε circular blends, G1),
        ``"exact"`` (unchanged), or one registered at run time.
    workers:
        Processes for the per-corner problems (independent; ``1`` solves in this process).
    select:
        ``optimal`` only: time the G2 plan, the same-ε circular blends and a per-corner mix of
        both on ``machine`` and return the fastest, so the result is never slower than the
        circular blends. ``False`` keeps the G2 transitions wherever they are feasible (wanted
        under jerk limits, where curvature continuity pays).
    objective:
        ``optimal`` only: ``"curvature"`` minimises the peak curvature (the speed limit under
        acceleration limits); ``"jerk"`` minimises the larger of the curvature and the curvature
        equivalent of the curvature rate under the machine's X/Y jerk limit
        (:meth:`~trcopt.optimize.corners.qp.CornerBlendProblem.objective_samples`), for
        jerk-limited timing, and also smooths the G450 transition circles and curvature jumps.
    chains:
        ``optimal`` only: replace each run of ≥ 3 consecutive corners of ≤ 20° joined by lines
        ≤ 5 mm (CAM polylines) by one G2 spline (:mod:`trcopt.optimize.corners.chain`) instead of
        per-corner transitions; a run whose spline is infeasible keeps per-corner transitions.
    kind:
        How ε is measured at a corner of an uncompensated path: ``contour`` (distance from the
        programmed path) or ``vertex`` (from the corner point).
    tolerances:
        ε by joint index where the program sets its own (its path-control mode).
    program:
        The blends of the program's path-control modes by joint (the ``program`` strategy;
        :func:`trcopt.optimize.corners.program.path_control_plan`).

    Raises
    ------
    ValueError
        An unknown strategy or objective (the message lists the valid ones).
    ConfigError
        The ``jerk`` objective on a machine without X/Y jerk limits.
    """
    strategy = strategies.get(mode)
    objective = parse_enum(CornerObjective, objective, "corner objective")
    jerk_limits = None
    if objective is CornerObjective.JERK:
        m = machine or DEFAULT_MACHINE
        jx, jy = m.axis("X").jmax_mm_s3, m.axis("Y").jmax_mm_s3
        if jx is None or jy is None:
            raise ConfigError(f"machine {m.name!r}: the jerk objective needs jmax_mm_s3 on X and Y")
        jerk_limits = (min(m.axis(k).amax_mm_s2 for k in "XY"), float(min(jx, jy)))
    job = strategies.CornerJob(
        strategy=strategy.name,
        toolpath=toolpath,
        programmed=programmed,
        tolerance_mm=tolerance_mm,
        machine=machine,
        workers=workers,
        select=select,
        objective=objective,
        jerk_limits=jerk_limits,
        chains=chains,
        kind=parse_enum(ToleranceKind, kind, "tolerance kind"),
        tolerances=tolerances,
        program=program,
    )
    return strategy.load()(job)


def optimize_corners(
    toolpath: Sequence[Segment],
    programmed: Sequence[Segment],
    *,
    tolerance_mm: float,
    machine: Machine | None = None,
    mode: str = "optimal",
    workers: int = 1,
) -> list[Segment]:
    """New tool-centre path with tolerance-bounded corner transitions (see :func:`blend_corners`)."""
    return blend_corners(
        toolpath, programmed, tolerance_mm=tolerance_mm, machine=machine, mode=mode, workers=workers
    ).segments
