"""The ``optimal`` corner strategy: G2 transitions chosen by optimisation, never slower than arcs.

Each corner gets a G2-continuous quintic (``Poly`` segment, role ``corner``, span of the following
block) chosen by :class:`~trcopt.optimize.corners.qp.CornerBlendProblem` (SQP of OSQP QPs: least
peak curvature, material left ≤ ε, no gouge). A run of ≥ 3 consecutive corners of ≤ 20° joined by
short lines (CAM polylines) is replaced as a whole by one G2 smoothing spline
(:mod:`~trcopt.optimize.corners.chain`), which may leave ε between the vertices and so follows the
curve the chords approximate instead of turning at every vertex. Under the ``jerk`` objective the
G450 transition circles and the other curvature jumps get G2 splines too.

With ``select`` the plan is timed against the same-ε circular blends and a per-corner mix of both
(:func:`~trcopt.optimize.corners.selection.fastest`) and the fastest kept.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

from trcopt.geometry import Arc, Line
from trcopt.modes import CornerObjective, TransitionKind
from trcopt.optimize.corners.arc import arc_transitions
from trcopt.optimize.corners.assemble import TARGET_MARGIN, Spline, TransitionPlan, fit_tolerance, kept_jump
from trcopt.optimize.corners.chain import (
    ChainSite,
    ChainSolution,
    PartContour,
    find_chains,
    knot_site,
    solve_chain,
)
from trcopt.optimize.corners.curves import joint_turn
from trcopt.optimize.corners.fillet import FilletSpec, blend_joints, fillet_path
from trcopt.optimize.corners.free_runs import run_splines
from trcopt.optimize.corners.qp import CornerBlendProblem, CornerSolution
from trcopt.optimize.corners.records import CornerRecord, CornerResult
from trcopt.optimize.corners.selection import fastest
from trcopt.optimize.corners.sites import TANGENT_TOL_RAD, CornerSite, curvature_jump_joints, find_corner_sites
from trcopt.optimize.corners.strategies import CornerJob
from trcopt.optimize.corners.time_model import RUN_SPLINE_MARGIN, quicker
from trcopt.path import Segment
from trcopt.progress import iterate
from trcopt.verify.contour import part_contour

__all__ = ["PARALLEL_MIN_CORNERS", "optimal_transitions"]

PARALLEL_MIN_CORNERS = 8  # fewer corner problems are solved in-process (a pool costs ~1 s to start)
CIRCLE_REASON = "circular blend: no transition within ε has a larger smallest radius (G2 quintics not solved)"

CornerTask = tuple[int, CornerSite, float, tuple[float, float] | None]  # joint, site, ε (mm), jerk limits


def optimal_transitions(job: CornerJob) -> CornerResult:
    """``job``'s path with G2 transitions within its tolerance (see the module description); the
    corners of uncompensated lines (G40 CAM output) get the largest circular blend within the
    tolerance first — under acceleration limits no transition within the same distance from the
    path has a larger smallest radius."""
    if job.tolerance_mm <= 0:
        result = job.unchanged()
    else:
        free = _free_blends(job)
        if free.blended and job.chains:
            free = _with_run_splines(job, free)
        if free.blended:
            result = _g2_transitions(replace(job, toolpath=free.segments))
            result = _renumber(free, result)
        else:
            result = _g2_transitions(job)
    result.objective = job.objective  # reported with the plan, also when nothing was blended
    return result


def _free_blends(job: CornerJob) -> CornerResult:
    """Circular blends at the corners of uncompensated feed lines (the path's own tolerance);
    curvature-continuous B-spline transitions between lines under the ``jerk`` objective."""
    segs = list(job.toolpath)
    specs = {
        k: FilletSpec((1.0 - TARGET_MARGIN) * job.tolerance_at(k), job.kind)
        for k in blend_joints(segs)
        if segs[k].radius == 0.0
    }
    # under jerk limits the corners between lines get curvature-continuous B-spline transitions
    g2 = job.objective is CornerObjective.JERK
    return fillet_path(segs, specs, job.strategy, g2=g2) if specs else job.unchanged()


def _with_run_splines(job: CornerJob, circles: CornerResult) -> CornerResult:
    """The uncompensated path's circular blends ``circles``, or the plan with G2 splines across its
    runs of CAM chords (:func:`~trcopt.optimize.corners.free_runs.run_splines`) where there are
    such runs and — with ``select`` — it times faster (by the cycle-time model where the two differ
    by more than :data:`~trcopt.optimize.corners.time_model.RUN_SPLINE_MARGIN`)."""
    splines = run_splines(job)
    if splines is None:
        return circles
    if not job.select:
        return splines
    from trcopt.config import DEFAULT_MACHINE

    m = job.machine or DEFAULT_MACHINE
    return splines if not quicker(circles.segments, splines.segments, m, RUN_SPLINE_MARGIN) else circles


def _renumber(first: CornerResult, second: CornerResult) -> CornerResult:
    """``second`` (run on ``first``'s path) with its records' joints numbered on the exact path
    and ``first``'s records added."""
    origin = first.origin or list(range(len(first.segments)))
    moved = [replace(c, index=origin[c.index]) for c in second.corners]
    second.corners = sorted(first.corners + moved, key=lambda r: r.index)
    second.max_deviation_mm = max(first.max_deviation_mm, second.max_deviation_mm)
    return second


def _g2_transitions(job: CornerJob) -> CornerResult:
    """G2 quintics and splines fitted to ``job``'s tolerance, then the selection by time."""
    segs = list(job.toolpath)
    # under jerk limits the G450 transition circles and the other curvature jumps (line↔arc, arcs
    # of different curvature) are worth replacing as well
    jumps = job.objective is CornerObjective.JERK
    sites = find_corner_sites(segs, job.programmed, tolerance_mm=job.tolerance_mm, transition_circles=jumps)
    # a small margin for the difference between the per-corner and the global sampling
    plan = TransitionPlan(segs, sites, {k: (1.0 - TARGET_MARGIN) * job.tolerance_mm for k, _ in sites})
    # runs of small-deflection corners (CAM polylines): one G2 spline across each run; curvature
    # jumps: one G2 spline across each jump
    # the largest circle within ε has the largest smallest radius of any transition between two
    # lines within ε (a G2 quintic's curvature must also rise from zero): under acceleration limits
    # a quintic gained at most 0.2 % of the cycle time on the corner problems, for 10–60 times the
    # planning time, so with ``select`` no quintic is solved there (docs/continuous_path.md)
    circles_win = job.select and job.objective is CornerObjective.CURVATURE
    circles = arc_transitions(job) if circles_win else None
    flatter = None
    if circles is not None:
        peak = {c.index: c.max_curvature for c in circles.corners if c.blended}
        flatter = lambda chain: _spline_may_be_flatter(segs, chain, peak)  # noqa: E731
    plan.splines, plan.kept = _solve_chains(
        segs,
        job.programmed,
        sites,
        job.tolerance_mm,
        runs=job.chains,
        knots=jumps and job.chains,
        keep=flatter,
        workers=job.workers,
    )
    if circles is not None and not plan.splines and all(_two_lines(site) for _, site in sites):
        return _with_reason(circles)

    def solve_quintics(current: TransitionPlan) -> None:
        # the sites without a G2 quintic at their current tolerance: all at first, then the tightened
        eps = current.eps
        tasks = [
            (k, site, eps[k], job.jerk_limits)
            for k, site in current.single
            if (k, eps[k]) not in current.solved and not (circles_win and _two_lines(site))
        ]
        _solve_sites(tasks, current.solved, job.workers)

    result = fit_tolerance(plan, job.programmed, job.tolerance_mm, job.strategy, solve_quintics)
    if circles_win:
        result = _with_reason(result)
    if job.select and (result.count(TransitionKind.QUINTIC) or result.count(TransitionKind.SPLINE)):
        result = fastest(job, plan, result, circles)
    if plan.kept:
        result.corners = sorted(result.corners + plan.kept, key=lambda r: r.index)
    return result


def _solve_chains(
    segs: list[Segment],
    programmed: Sequence[Segment],
    sites: list[tuple[int, CornerSite]],
    tolerance_mm: float,
    *,
    runs: bool = True,
    knots: bool = False,
    keep: Callable[[ChainSite], bool] | None = None,
    workers: int = 1,
) -> tuple[list[Spline], list[CornerRecord]]:
    """G2 splines across the runs of small-deflection corners (``runs``) and across the curvature
    jumps (``knots``): the feasible ones, and records of the curvature jumps that keep the exact
    path."""
    plain = [k for k, site in sites if site.min_cut == 0.0]
    owned = {k for k, _ in sites} | {k + 1 for k, site in sites if site.min_cut > 0.0}
    jumps = curvature_jump_joints(segs, owned) if knots else []
    owned |= set(jumps)
    contour = PartContour(
        [p.geometry for p in part_contour(programmed, segs) if isinstance(p.geometry, Line | Arc) and not p.is_rapid]
    )
    eps = (1.0 - TARGET_MARGIN) * tolerance_mm
    out, kept = [], []
    found = find_chains(segs, plain, owned, contour) if runs else []
    if keep is not None:
        found = [chain for chain in found if keep(chain)]
    if knots:
        # curvature jumps: each line↔arc joint, and each G450 transition circle between two lines
        # as a whole (its two joints); a feasible spline takes the place of the circle's site
        runs_k = [[k] for k in jumps] + [[k, k + 1] for k, site in sites if site.min_cut > 0.0]
        found += [knot_site(segs, run, owned, contour, eps) for run in runs_k]
    for chain, sol in zip(found, _chain_solutions(found, eps, workers), strict=True):
        if sol.ok:
            out.append((chain, sol, eps))
        elif chain.max_turn <= TANGENT_TOL_RAD and len(chain.joints) == 1:  # (a circle keeps its site)
            kept.append(kept_jump(segs, chain, f"spline infeasible ({sol.message})"))
    return out, kept


def _solve_chain_task(task: tuple[ChainSite, float]) -> ChainSolution:
    return solve_chain(*task)


def _chain_solutions(found: list[ChainSite], eps: float, workers: int) -> list[ChainSolution]:
    """The spline of every run in ``found`` at ``eps``, in order: in ``workers`` processes when
    there are several runs (each is an independent sequence of QPs)."""
    tasks = [(chain, eps) for chain in found]
    if workers > 1 and len(tasks) > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=min(workers, len(tasks))) as pool:
            return list(iterate(pool.map(_solve_chain_task, tasks), "corner splines", len(tasks)))
    return list(iterate(map(_solve_chain_task, tasks), "corner splines", len(tasks)))


def _with_reason(result: CornerResult) -> CornerResult:
    """The circular blends without a G2 solution say why they are circular."""
    result.corners = [
        replace(c, reason=CIRCLE_REASON)
        if c.transition is TransitionKind.ARC and c.solution is None and not c.reason
        else c
        for c in result.corners
    ]
    return result


def _spline_may_be_flatter(segs: list[Segment], chain: ChainSite, peak: dict[int, float | None]) -> bool:
    """Whether a spline across ``chain`` could have a smaller peak curvature than the circular
    blends at its joints (``peak``, 1/mm, by joint): the spline turns by the run's net turn Θ over
    about the run's length S, so its peak curvature is at least Θ/S; where the circles are already
    flatter than that, the spline cannot carry more speed and is not solved."""
    kappa = [
        peak.get(k) for k in chain.joints if abs(joint_turn(segs[k].geometry, segs[k + 1].geometry)) > TANGENT_TOL_RAD
    ]  # type: ignore[arg-type]
    if any(x is None for x in kappa):
        return True
    kappa += [1.0 / e.radius for e in chain.full[1:-1] if isinstance(e, Arc)]  # the arcs it replaces
    if not kappa:
        return True
    theta = abs(sum(joint_turn(segs[k].geometry, segs[k + 1].geometry) for k in chain.joints))  # type: ignore[arg-type]
    length = sum(e.plane_length for e in chain.full)
    return length <= 0.0 or max(kappa) > theta / length  # type: ignore[type-var]


def _two_lines(site: CornerSite) -> bool:
    """A corner between two lines (not a G450 transition circle): its circular blend is closed form."""
    return site.min_cut == 0.0 and isinstance(site.a, Line) and isinstance(site.b, Line)


def _solve_one(task: CornerTask) -> tuple[tuple[int, float], CornerSolution]:
    k, site, eps, limits = task
    return (k, eps), CornerBlendProblem(site, eps, limits=limits).solve()


def _solve_sites(tasks: list[CornerTask], solved: dict[tuple[int, float], CornerSolution], workers: int) -> None:
    """Solve the corner problems of ``tasks`` into ``solved`` (keyed by corner index and ε)."""
    if workers > 1 and len(tasks) >= PARALLEL_MIN_CORNERS:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=workers) as pool:
            chunks = max(1, len(tasks) // (4 * workers))
            solved.update(iterate(pool.map(_solve_one, tasks, chunksize=chunks), "corner problems", len(tasks)))
    else:
        solved.update(iterate(map(_solve_one, tasks), "corner problems", len(tasks)))
