"""Lead family 1: a straight line tangent into a circular arc ending at P4c (Dubins-like, with the
arc radius a variable), solved with CasADi/IPOPT for either turning sense."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.optimize.leads.context import LeadContext
from trcopt.optimize.leads.records import Element
from trcopt.solution import Solution, SolveStatus, ipopt_options

__all__ = ["N_ARC", "N_LINE", "solve_line_arc"]

N_LINE, N_ARC = 8, 16  # constraint samples on the line and on the arc


def _line_arc_guess(ctx: LeadContext, c: int, rho: float) -> tuple[float, float]:
    """(ρ, φ) of the unconstrained tangent line + arc for turning sense ``c``."""
    C = (ctx.p4c2[0] + c * rho * ctx.n[0], ctx.p4c2[1] + c * rho * ctx.n[1])
    a4 = math.atan2(ctx.p4c2[1] - C[1], ctx.p4c2[0] - C[0])
    d = math.dist(ctx.p0[:2], C)
    if d <= rho:
        return rho, math.pi
    g = math.atan2(ctx.p0[1] - C[1], ctx.p0[0] - C[0])
    b = math.acos(rho / d)
    for th in (g + b, g - b):
        A = (C[0] + rho * math.cos(th), C[1] + rho * math.sin(th))
        tA = (-c * math.sin(th), c * math.cos(th))
        if (A[0] - ctx.p0[0]) * tA[0] + (A[1] - ctx.p0[1]) * tA[1] >= 0.0:
            phi = (c * (a4 - th)) % (2.0 * math.pi)
            return rho, phi
    return rho, math.pi


def _line_arc_elements(ctx: LeadContext, c: int, rho: float, phi: float) -> tuple[Element, ...]:
    C = (ctx.p4c2[0] + c * rho * ctx.n[0], ctx.p4c2[1] + c * rho * ctx.n[1])
    a4 = math.atan2(ctx.p4c2[1] - C[1], ctx.p4c2[0] - C[0])
    w0, w4 = ctx.p0[2], ctx.p4[2]
    if phi * rho <= 1e-9:
        return (Line(ctx.p0, ctx.p4c),)
    thA = a4 - c * phi
    A = (C[0] + rho * math.cos(thA), C[1] + rho * math.sin(thA), w0)
    arc = Arc(C, rho, thA, c * phi, w0, w4)
    if math.dist(A[:2], ctx.p0[:2]) <= 1e-9:
        return (arc,)
    return (Line(ctx.p0, A), arc)


def solve_line_arc(ctx: LeadContext, c: int, rho_lb: float) -> tuple[Solution[Any], tuple[Element, ...], float, float]:
    """The shortest line + arc lead turning with sense ``c`` (+1 left, −1 right) whose arc radius
    is ≥ ``rho_lb`` (mm): (solution, elements, arc radius mm, sweep rad)."""
    import casadi as ca

    opti = ca.Opti()
    rho = opti.variable()
    phi = opti.variable()
    Cx = ctx.p4c2[0] + c * rho * ctx.n[0]
    Cy = ctx.p4c2[1] + c * rho * ctx.n[1]
    a4 = math.atan2(-c * ctx.n[1], -c * ctx.n[0])
    thA = a4 - c * phi
    Ax, Ay = Cx + rho * ca.cos(thA), Cy + rho * ca.sin(thA)
    tAx, tAy = -c * ca.sin(thA), c * ca.cos(thA)
    dx, dy = Ax - ctx.p0[0], Ay - ctx.p0[1]
    tang = dx * tAy - dy * tAx
    groups: dict[str, list[Any]] = {"tangency": [tang], "curvature": [rho - rho_lb], "sweep": []}
    opti.subject_to(tang == 0)
    opti.subject_to(dx * tAx + dy * tAy >= 0)
    opti.subject_to(rho >= rho_lb)
    opti.subject_to(opti.bounded(0.0, phi, 2.0 * math.pi - 1e-3))
    pts = [ca.vertcat(ctx.p0[0] + lam * dx, ctx.p0[1] + lam * dy) for lam in np.linspace(0.0, 1.0, N_LINE)[1:]]
    for u in np.linspace(0.0, 1.0, N_ARC)[1:]:
        th = thA + c * phi * u
        pts.append(ca.vertcat(Cx + rho * ca.cos(th), Cy + rho * ca.sin(th)))
    groups.update(ctx.add_constraints(opti, pts, skip_last_contact=max(2, N_ARC // 6)))
    length = ca.sqrt(dx**2 + dy**2 + 1e-12) + rho * phi
    opti.minimize(length)
    r0, p0 = _line_arc_guess(ctx, c, rho_lb)
    opti.set_initial(rho, r0)
    opti.set_initial(phi, p0)
    opti.solver("ipopt", ipopt_options(tol=1e-9, max_iter=300))
    t0 = time.perf_counter()
    try:
        sol = opti.solve()
        val, stats, status = sol.value, sol.stats(), SolveStatus.OPTIMAL
    except RuntimeError:
        val, stats, status = opti.debug.value, opti.stats(), SolveStatus.FAILED
    dt = time.perf_counter() - t0
    r, f = float(val(rho)), float(val(phi))
    viol = {
        k: max((max(0.0, -float(val(e))) if k != "tangency" else abs(float(val(e))) for e in v), default=0.0)
        for k, v in groups.items()
    }
    msg = str(stats.get("return_status", ""))
    if "Infeasible" in msg:
        status = SolveStatus.INFEASIBLE
    sol_obj: Solution[Any] = Solution(
        status, float(val(length)), int(stats.get("iter_count", 0)), dt, (r, f), viol, msg
    )
    return sol_obj, _line_arc_elements(ctx, c, r, f), r, f
