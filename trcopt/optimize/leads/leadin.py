"""Optimal lead-in: the tool-centre path from a start point into the contour, by optimisation.

Given the start point P0 (tool centre), the programmed part contour (its first element starts at
P4), the tool radius R and side, and the machine, :func:`optimal_lead` chooses the lead that
minimises the traverse time subject to the constraint model (design.md §4):

* **tangency** at the contour start: the lead ends at P4c = P4 + s·R·n with the contour's tangent;
* **curvature** ≤ 1/ρmin (``rho_min``, a machine setting, mm);
* **clearance** ≥ R + ``safety`` from every element of the whole part contour, ≥ R (no gouge)
  from the elements that meet at P4 (the lead must touch the contour there);
* **no reversal** of the infeed axis: the applicate moves monotonically from w0 to w4 (the lead
  runs at w0 and descends on its curved part, a helix — the shape of SAR G340 with
  DISCL = w0 − w4);
* **region**: optionally every lead point inside a convex polygon (tool centre).

Two families are solved with CasADi/IPOPT: ``line_arc`` (a straight line tangent into a circular
arc ending at P4c; both turning senses) and ``poly`` (a quintic Bézier curve with curvature matched
to the contour at P4c, a clothoid-like transition). The objective is the **traverse time** from
:func:`trcopt.timing.time_parameterize` over the lead plus the first contour element at the
contour feed (the arc radius is scanned over ρmin·{1, 2, 4} and the best time kept); if
the timing stage is not importable, the surrogate ``length + λ·∫κ² ds`` with λ = 2·ρmin (mm²) is
used instead (stated in ``LeadResult.objective``). Every candidate is re-checked with the exact
closed-form distances of :mod:`trcopt.verify.model` (no sampling gaps). No feasible lead is a
:class:`~trcopt.errors.SolverError` naming the binding constraint, never a silent fallback.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.errors import GeometryError, SolverError, TimingError
from trcopt.geometry import Arc, Line, Plane
from trcopt.geometry.vec import Vec2
from trcopt.modes import LeadObjective, Side, parse_enum
from trcopt.optimize.leads.bezier import poly_guess, solve_poly
from trcopt.optimize.leads.context import RHO_SCAN, LeadContext, inside_margin
from trcopt.optimize.leads.line_arc import solve_line_arc
from trcopt.optimize.leads.records import Element, LeadCandidate, LeadResult, SarShape, lead_segments
from trcopt.path import Segment
from trcopt.solution import Solution
from trcopt.verify.model import points_distance

__all__ = ["lead_time", "offset_start", "optimal_lead"]


def offset_start(first: Element, radius: float, side: Side) -> Element:
    """Tool-centre offset of the first contour element (left positive)."""
    d = side.sign * radius
    if isinstance(first, (Line, Arc)):
        return first.offset(d)
    raise GeometryError("the contour must start with a line or an arc")


def lead_time(
    elements: Sequence[Element],
    first_contour: Element,
    machine: Machine,
    feed_mm_s: float,
    plane: Plane = Plane.G17,
    rho_min: float = 1.0,
) -> tuple[float, LeadObjective]:
    """Traverse time (s) of the lead plus the first contour element with the timing stage, or the
    documented surrogate ``length + 2·ρmin·∫κ² ds`` (mm) when the timing stage is missing."""
    els = [*elements, first_contour]
    try:
        from trcopt.timing import time_parameterize
    except ImportError:
        length = sum(e.length for e in els)
        bend = sum(abs(e.sweep) / e.radius for e in els if isinstance(e, Arc))
        return length + 2.0 * rho_min * bend, LeadObjective.SURROGATE
    segs = lead_segments(els, plane, feed_mm_s, Side.OFF, 0.0)
    return float(time_parameterize(segs, machine).duration), LeadObjective.TIME


def _sar_shape(ctx: LeadContext, c: int, rho: float, phi: float, elements: Sequence[Element]) -> SarShape | None:
    """SAR words when the lead is a SAR shape: a line along t (G147), or an arc of 90°/180°
    turning on the compensation side (G247/G347)."""
    tol = 1e-6
    discl = ctx.p0[2] - ctx.p4[2]
    if len(elements) == 2 and isinstance(elements[-1], Arc):
        # SAR draws the tool-centre circle from its programmed circle ρp = DISR + s·σ·R > 0 (R38)
        if rho + ctx.s * c * ctx.R <= 0.0:
            return None
    if len(elements) == 1 and isinstance(elements[0], Line):
        return SarShape("G147", elements[0].plane_length - ctx.R, discl, "G140")
    side = "G141" if c > 0 else "G142"
    if abs(phi - math.pi / 2) <= tol:
        return SarShape("G247", rho, discl, side)
    if abs(phi - math.pi) <= tol:
        return SarShape("G347", rho, discl, side)
    return None


def optimal_lead(
    start: Sequence[float],
    contour: Sequence[Element | Segment],
    radius: float,
    side: Side | str,
    *,
    rho_min: float = 2.0,
    safety: float = 1.0,
    region: Sequence[Vec2] | None = None,
    machine: Machine = DEFAULT_MACHINE,
    feed_mm_s: float = 10.0,
    plane: Plane = Plane.G17,
    families: Sequence[str] = ("line_arc", "poly"),
) -> LeadResult:
    """The time-optimal tool-centre lead from ``start`` into the contour.

    Parameters
    ----------
    start:
        Tool-centre start point P0 (u, v, w) in plane coordinates, mm.
    contour:
        The programmed part contour in program order (elements or segments, plane coordinates);
        its first element starts at P4. The whole contour is used for clearance.
    radius:
        Tool (compensation) radius R > 0, mm.
    side:
        Compensation side, ``left`` (G41) or ``right`` (G42).
    rho_min:
        Smallest admissible radius of curvature of the lead (machine setting), mm.
    safety:
        Extra clearance beyond R from the contour away from P4, mm.
    region:
        Optional convex polygon [(u, v), ...] the tool centre must stay inside, mm.
    machine, feed_mm_s:
        Axis limits and the feed (mm/s) for the traverse-time objective.
    families:
        Lead families to try: ``line_arc``, ``poly``.

    Raises
    ------
    SolverError
        No lead satisfies the constraints; the message names the binding constraint.
    """
    t_start = time.perf_counter()
    side_e = parse_enum(Side, side)
    if side_e is Side.OFF:
        raise GeometryError("optimal lead needs a compensation side (left or right)")
    if radius <= 0.0 or rho_min <= 0.0 or safety < 0.0:
        raise GeometryError("radius and rho_min must be positive, safety non-negative")
    els = [c.geometry if isinstance(c, Segment) else c for c in contour]
    els = [e for e in els if e.plane_length > 0.0]
    if not els:
        raise GeometryError("the contour has no plane motion")
    p0 = (float(start[0]), float(start[1]), float(start[2]) if len(start) > 2 else els[0].start[2])
    ctx = LeadContext(p0, els, radius, side_e, rho_min, safety, region)
    if ctx.edges and inside_margin(ctx.p4c2, ctx.edges) < -1e-9:
        raise SolverError("no lead fits: binding constraint 'region' (the contour start P4c lies outside it)")
    if ctx.edges and inside_margin(p0[:2], ctx.edges) < -1e-9:
        raise SolverError("no lead fits: binding constraint 'region' (the start point lies outside it)")
    for i, e in enumerate(els):
        d0 = float(points_distance(e, np.array([p0[:2]]))[0])
        if d0 < ctx.required(i) - 1e-9:
            raise SolverError(
                f"no lead fits: binding constraint 'clearance' (the start point is {d0:.4g} mm from contour "
                f"element {i + 1}, less than R{'' if i in ctx.contact else ' + safety'} = {ctx.required(i):.4g} mm)",
                code=Code.SOLVER_INFEASIBLE,
            )
    first_tc = offset_start(els[0], radius, side_e)
    candidates: list[LeadCandidate] = []
    failures: list[tuple[str, Solution[Any], dict[str, float]]] = []
    objective = LeadObjective.TIME

    def consider(
        kind: str, sol: Solution[Any], elements: tuple[Element, ...], rho: float | None, phi: float | None
    ) -> None:
        nonlocal objective
        exact = ctx.exact_check(elements)
        if not sol.ok or max(exact.values()) > 1e-6 or max(sol.constraint_violation.values(), default=0.0) > 1e-5:
            merged = {**sol.constraint_violation}
            for k, v in exact.items():
                merged[k] = max(merged.get(k, 0.0), v)
            failures.append((kind, sol, merged))
            return
        try:
            t, objective = lead_time(elements, first_tc, machine, feed_mm_s, plane, rho_min)
        except TimingError as exc:
            # a candidate the timing stage cannot parameterise is not a lead the machine can run
            failures.append((kind, replace(sol, message=f"timing: {exc.message}"), {"timing": 1.0}))
            return
        candidates.append(
            LeadCandidate(
                kind, elements, sum(e.length for e in elements), t, ctx.last_min_clear, ctx.last_contact, sol, rho, phi
            )
        )

    best_la: tuple[Element, ...] | None = None
    if "line_arc" in families:
        for c in (1, -1):
            for k in RHO_SCAN:
                sol, elements, r, f = solve_line_arc(ctx, c, k * rho_min)
                consider("line_arc", sol, elements, r, f)
        if candidates:
            best_la = min(candidates, key=lambda c: c.time_s).elements
    if "poly" in families:
        sol, elements = solve_poly(ctx, poly_guess(ctx, best_la))
        consider("poly", sol, elements, None, None)
    if not candidates:
        worst: dict[str, float] = {}
        for _, _, viol in failures:
            for key, amount in viol.items():
                worst[key] = max(worst.get(key, 0.0), amount)
        # prefer the geometric constraints over solver regularisation groups
        order = ["region", "clearance", "curvature", "tangency", "sweep", "regularity"]
        name = next(
            (k for k in order if worst.get(k, 0.0) > 1e-6), max(worst, key=lambda k: worst[k]) if worst else "?"
        )
        raise SolverError(
            f"no lead fits: binding constraint '{name}' (violated by {worst.get(name, float('nan')):.4g} "
            f"mm in the best attempt; R = {radius}, safety = {safety}, rho_min = {rho_min})",
            code=Code.SOLVER_INFEASIBLE,
        )
    best = min(candidates, key=lambda c: c.time_s)
    sar = None
    if best.kind == "line_arc" and best.rho is not None and best.sweep is not None:
        c = 1 if isinstance(best.elements[-1], Arc) and best.elements[-1].sweep > 0 else -1
        sar = _sar_shape(ctx, c, best.rho, best.sweep, best.elements)
    return LeadResult(
        best,
        tuple(candidates),
        objective,
        p0,
        ctx.p4,
        ctx.p4c,
        ctx.t,
        radius,
        side_e,
        plane,
        feed_mm_s,
        sar,
        first_tc,
        time.perf_counter() - t_start,
        rho_min,
        safety,
    )
