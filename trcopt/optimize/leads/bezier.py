"""Lead family 2: a quintic Bézier curve into P4c whose end curvature matches the contour offset's
(G2 entry, a clothoid-like transition), solved with CasADi/IPOPT."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.geometry import Line, Poly
from trcopt.optimize.leads.context import LeadContext
from trcopt.optimize.leads.records import Element
from trcopt.solution import Solution, SolveStatus, ipopt_options

__all__ = ["N_POLY", "poly_guess", "solve_poly"]

N_POLY = 24  # collocation samples of the curve


_BINOM = (1, 5, 10, 10, 5, 1)


def _bezier(Q: list[Any], u: float, der: int = 0) -> Any:
    n = 5
    if der == 0:
        return sum(_BINOM[i] * u**i * (1 - u) ** (n - i) * Q[i] for i in range(n + 1))
    if der == 1:
        D = [n * (Q[i + 1] - Q[i]) for i in range(n)]
        return sum(math.comb(n - 1, i) * u**i * (1 - u) ** (n - 1 - i) * D[i] for i in range(n))
    D2 = [n * (n - 1) * (Q[i + 2] - 2 * Q[i + 1] + Q[i]) for i in range(n - 1)]
    return sum(math.comb(n - 2, i) * u**i * (1 - u) ** (n - 2 - i) * D2[i] for i in range(n - 1))


def _poly_controls(ctx: LeadContext, psi: Any, a: Any, q2: Any, f: Any, d: Any, lib: Any) -> list[Any]:
    t, n = ctx.t, ctx.n
    P0 = lib.vertcat(ctx.p0[0], ctx.p0[1]) if lib is not np else np.array(ctx.p0[:2])
    P5 = lib.vertcat(*ctx.p4c2) if lib is not np else np.array(ctx.p4c2)
    e = lib.vertcat(lib.cos(psi), lib.sin(psi)) if lib is not np else np.array([math.cos(psi), math.sin(psi)])
    T = lib.vertcat(*t) if lib is not np else np.array(t)
    N = lib.vertcat(*n) if lib is not np else np.array(n)
    h = ctx.kappa0 * d * d / 0.8  # end curvature equals the contour offset's (G2 entry)
    Q4 = P5 - d * T
    Q3 = Q4 - f * T + h * N
    return [P0, P0 + a * e, q2, Q3, Q4, P5]


def _poly_element(ctx: LeadContext, x: Sequence[float]) -> Poly:
    psi, a, q2u, q2v, f, d = x
    Q = _poly_controls(ctx, psi, a, np.array([q2u, q2v]), f, d, np)
    approx = sum(float(np.linalg.norm(Q[i + 1] - Q[i])) for i in range(5))
    n = int(min(4000, max(64, approx / math.sqrt(8e-3 * ctx.rho_min) + 1)))
    us = np.linspace(0.0, 1.0, n)
    pts2 = np.array([_bezier(Q, u) for u in us])
    cum2 = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts2, axis=0).T))])
    w0, w4 = ctx.p0[2], ctx.p4[2]
    ws = w0 + (w4 - w0) * (cum2 / cum2[-1]) ** 1 if cum2[-1] > 0 else np.full(n, w0)
    pts = [(float(p[0]), float(p[1]), float(w)) for p, w in zip(pts2, ws, strict=True)]
    cum = [0.0]
    for p, q in zip(pts, pts[1:], strict=False):
        cum.append(cum[-1] + math.dist(p, q))
    dw = (w4 - w0) / cum2[-1] if cum2[-1] > 0 else 0.0
    tans = []
    for u in us:
        d1 = _bezier(Q, u, 1)
        d1 = d1 / float(np.linalg.norm(d1))
        v = np.array([d1[0], d1[1], dw])
        v = v / float(np.linalg.norm(v))
        tans.append((float(v[0]), float(v[1]), float(v[2])))
    pts[-1] = ctx.p4c
    return Poly(tuple(pts), tuple(tans), tuple(cum), "lead")


def solve_poly(ctx: LeadContext, guess: tuple[float, ...]) -> tuple[Solution[Any], tuple[Element, ...]]:
    """The quintic Bézier lead of least ``length + 2·ρmin·∫κ² ds`` from ``guess`` (the decision
    vector ψ, a, q2u, q2v, f, d of :func:`poly_guess`): (solution, the one ``Poly`` element)."""
    import casadi as ca

    opti = ca.Opti()
    x = opti.variable(6)
    psi, a, q2u, q2v, f, d = (x[i] for i in range(6))
    Q = _poly_controls(ctx, psi, a, ca.vertcat(q2u, q2v), f, d, ca)
    us = 0.5 * (1.0 - np.cos(np.linspace(0.0, math.pi, N_POLY)))  # denser at the ends
    pts = [_bezier(Q, float(u)) for u in us]
    groups: dict[str, list[Any]] = {"curvature": [], "regularity": []}
    gl_u, gl_w = np.polynomial.legendre.leggauss(24)
    speed = [ca.norm_2(_bezier(Q, 0.5 * (float(u) + 1.0), 1)) for u in gl_u]
    length = sum(0.5 * float(w) * s for w, s in zip(gl_w, speed, strict=True))
    bend = 0
    for u in us:
        d1, d2 = _bezier(Q, float(u), 1), _bezier(Q, float(u), 2)
        cr = d1[0] * d2[1] - d1[1] * d2[0]
        sp2 = d1[0] ** 2 + d1[1] ** 2
        g = 0.98 * sp2**1.5 / ctx.rho_min - ca.fabs(cr)  # 2 % margin for between-sample curvature
        opti.subject_to(g >= 0)
        opti.subject_to(sp2 >= 1e-2)
        groups["curvature"].append(g)
        groups["regularity"].append(sp2 - 1e-2)
        bend = bend + cr**2 / (sp2**2.5 + 1e-9) / N_POLY
    groups.update(ctx.add_constraints(opti, pts[1:-1], skip_last_contact=N_POLY // 8))
    opti.subject_to(a >= 0.2 * ctx.rho_min)  # handles: no cusp-like turns between samples
    opti.subject_to(d >= 0.2 * ctx.rho_min)
    opti.subject_to(f >= 0.0)
    opti.minimize(length + 2.0 * ctx.rho_min * bend)
    opti.set_initial(x, list(guess))
    opti.solver("ipopt", ipopt_options(tol=1e-8, max_iter=400))
    t0 = time.perf_counter()
    try:
        sol = opti.solve()
        val, stats, status = sol.value, sol.stats(), SolveStatus.OPTIMAL
    except RuntimeError:
        val, stats, status = opti.debug.value, opti.stats(), SolveStatus.FAILED
    dt = time.perf_counter() - t0
    xv = [float(v) for v in np.asarray(val(x)).ravel()]
    viol = {k: max((max(0.0, -float(val(e))) for e in v), default=0.0) for k, v in groups.items()}
    # curvature between the collocation samples, on a fine grid (1/mm)
    Qn = _poly_controls(ctx, xv[0], xv[1], np.array(xv[2:4]), xv[4], xv[5], np)
    kmax = 0.0
    for u in np.linspace(0.0, 1.0, 801):
        d1, d2 = _bezier(Qn, float(u), 1), _bezier(Qn, float(u), 2)
        sp = float(np.hypot(d1[0], d1[1]))
        kmax = max(kmax, abs(float(d1[0] * d2[1] - d1[1] * d2[0])) / max(sp, 1e-12) ** 3)
    viol["curvature"] = max(viol.get("curvature", 0.0), (kmax - 1.0 / ctx.rho_min) * ctx.rho_min * ctx.rho_min)
    msg = str(stats.get("return_status", ""))
    if "Infeasible" in msg:
        status = SolveStatus.INFEASIBLE
    return Solution(status, float(val(length)), int(stats.get("iter_count", 0)), dt, tuple(xv), viol, msg), (
        _poly_element(ctx, xv),
    )


def poly_guess(ctx: LeadContext, elements: Sequence[Element] | None) -> tuple[float, ...]:
    """Start of :func:`solve_poly`: leave P0 along the first line of ``elements`` (the best line +
    arc lead, if any) or towards a point before P4c, handles of a fifth of the distance."""
    p0 = np.array(ctx.p0[:2])
    p5 = np.array(ctx.p4c2)
    t = np.array(ctx.t)
    D = max(float(np.linalg.norm(p5 - p0)), ctx.rho_min)
    target = p5 - 0.5 * D * t
    if elements and isinstance(elements[0], Line) and elements[0].plane_length > 1e-9:
        e = np.array(elements[0].direction2())
    else:
        e = (target - p0) / max(float(np.linalg.norm(target - p0)), 1e-9)
    q2 = p0 + 0.4 * (target - p0) + 0.2 * D * e
    return (math.atan2(e[1], e[0]), D / 5, float(q2[0]), float(q2[1]), D / 5, D / 5)
