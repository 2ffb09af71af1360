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
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.errors import GeometryError, SolverError, SourceSpan
from trcopt.geometry import Arc, Line, Plane, Poly
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import Side, parse_enum
from trcopt.path import Role, Segment
from trcopt.solution import Solution, SolveStatus, ipopt_options
from trcopt.verify.model import ca_point_element_distance, element_distance, points_distance

Element = Line | Arc | Poly

__all__ = ["LeadCandidate", "LeadResult", "SarShape", "optimal_lead", "lead_time", "offset_start"]

RHO_SCAN = (1.0, 2.0, 4.0)
N_LINE, N_ARC, N_POLY = 8, 16, 24


@dataclass(frozen=True, slots=True)
class SarShape:
    """The lead expressed as SINUMERIK SAR words (when it has a SAR shape)."""

    contour: str  # G147 / G247 / G347
    disr: float
    discl: float  # incremental, mm (G340)
    side: str  # G141 / G142


@dataclass(frozen=True, slots=True)
class LeadCandidate:
    """One solved lead family member."""

    kind: str
    elements: tuple[Element, ...]
    length: float
    time_s: float
    min_clearance: float  # exact, to the contour elements not meeting P4, mm
    contact_clearance: float  # exact, to the elements meeting at P4, mm
    solution: Solution[Any]
    rho: float | None = None
    sweep: float | None = None


@dataclass(frozen=True, slots=True)
class LeadResult:
    """The optimal lead and everything it was chosen from.

    ``elements`` are tool-centre elements in plane coordinates from P0 to P4c; ``segments``
    the same as approach :class:`~trcopt.path.Segment` values (absolute coordinates via
    ``plane``); ``time_s`` is the objective value (traverse time over lead + first contour
    element, s, or the surrogate in mm when ``objective == "surrogate"``).
    """

    best: LeadCandidate
    candidates: tuple[LeadCandidate, ...]
    objective: str
    p0: Vec3
    p4: Vec3
    p4c: Vec3
    tangent: Vec2
    radius: float
    side: Side
    plane: Plane
    feed_mm_s: float
    sar: SarShape | None
    first_contour: Element
    solve_time_s: float = 0.0
    rho_min: float = 2.0
    safety: float = 1.0
    notes: list[str] = field(default_factory=list)

    @property
    def kind(self) -> str:
        return self.best.kind

    @property
    def elements(self) -> tuple[Element, ...]:
        return self.best.elements

    @property
    def length(self) -> float:
        return self.best.length

    @property
    def time_s(self) -> float:
        return self.best.time_s

    @property
    def segments(self) -> list[Segment]:
        return _segments(self.elements, self.plane, self.feed_mm_s, self.side, self.radius)

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "objective": self.objective,
            "time_s": self.time_s,
            "length_mm": self.length,
            "min_clearance_mm": self.best.min_clearance,
            "contact_clearance_mm": self.best.contact_clearance,
            "radius": self.radius,
            "side": self.side.value,
            "rho": self.best.rho,
            "sweep_deg": None if self.best.sweep is None else math.degrees(self.best.sweep),
            "sar": None
            if self.sar is None
            else {"contour": self.sar.contour, "disr": self.sar.disr, "discl": self.sar.discl, "side": self.sar.side},
            "segments": [s.to_json() for s in self.segments],
            "candidates": [
                {
                    "kind": c.kind,
                    "time_s": c.time_s,
                    "length_mm": c.length,
                    "rho": c.rho,
                    "status": c.solution.status.value,
                    "iterations": c.solution.iterations,
                }
                for c in self.candidates
            ],
        }


# --------------------------------------------------------------------------------------------


def _segments(elements: Sequence[Element], plane: Plane, feed: float, side: Side, radius: float) -> list[Segment]:
    span = SourceSpan(file="<lead>", block="LEAD")
    return [Segment(e, plane, Role.APPROACH, span, feed, side, radius) for e in elements]


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
) -> tuple[float, str]:
    """Traverse time (s) of the lead plus the first contour element with the timing stage, or the
    documented surrogate ``length + 2·ρmin·∫κ² ds`` (mm) when the timing stage is missing."""
    els = [*elements, first_contour]
    try:
        from trcopt.timing import time_parameterize
    except ImportError:
        length = sum(e.length for e in els)
        bend = sum(abs(e.sweep) / e.radius for e in els if isinstance(e, Arc))
        return length + 2.0 * rho_min * bend, "surrogate"
    segs = _segments(els, plane, feed_mm_s, Side.OFF, 0.0)
    return float(time_parameterize(segs, machine).duration), "time"


def _unit(v: Sequence[float]) -> Vec2:
    n = math.hypot(v[0], v[1])
    return (v[0] / n, v[1] / n)


def _convex_halfplanes(region: Sequence[Vec2]) -> list[tuple[Vec2, Vec2]]:
    pts = [(float(p[0]), float(p[1])) for p in region]
    if len(pts) >= 2 and pts[0] == pts[-1]:
        pts = pts[:-1]
    if len(pts) < 3:
        raise GeometryError("the allowed region needs at least 3 vertices")
    area = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(pts, pts[1:] + pts[:1], strict=True))
    if area < 0:
        pts = pts[::-1]
    edges = list(zip(pts, pts[1:] + pts[:1], strict=True))
    for (a, b), (c, d) in zip(edges, edges[1:] + edges[:1], strict=True):
        if (b[0] - a[0]) * (d[1] - c[1]) - (b[1] - a[1]) * (d[0] - c[0]) < -1e-12:
            raise GeometryError("the allowed region must be a convex polygon")
    return edges


def _inside_margin(p: Vec2, edges: list[tuple[Vec2, Vec2]]) -> float:
    return min(((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / math.dist(a, b) for a, b in edges)


def _symbolic(g: Any) -> bool:
    import casadi as ca

    return isinstance(g, (ca.MX, ca.SX)) and not g.is_constant()


class _Context:
    """Shared data of one lead problem (plane coordinates)."""

    def __init__(
        self,
        p0: Vec3,
        contour: Sequence[Element],
        radius: float,
        side: Side,
        rho_min: float,
        safety: float,
        region: Sequence[Vec2] | None,
    ) -> None:
        self.p0 = p0
        self.contour = list(contour)
        first = self.contour[0]
        self.p4 = first.start
        self.t = _unit(first.start_tangent())
        self.n = (-self.t[1], self.t[0])
        self.s = side.sign
        self.R = radius
        self.p4c2 = (self.p4[0] + self.s * radius * self.n[0], self.p4[1] + self.s * radius * self.n[1])
        self.p4c = (self.p4c2[0], self.p4c2[1], self.p4[2])
        self.rho_min = rho_min
        self.safety = safety
        self.edges = _convex_halfplanes(region) if region is not None else []
        # elements that meet at P4 need only R (contact), the others R + safety
        self.contact = [
            i
            for i, e in enumerate(self.contour)
            if math.dist(e.start[:2], self.p4[:2]) <= 1e-9 or math.dist(e.end[:2], self.p4[:2]) <= 1e-9
        ]
        # first-element curvature of the tool-centre offset at P4c (signed, left positive)
        if isinstance(first, Arc):
            off = first.offset(self.s * radius)
            self.kappa0 = first.sense / off.radius if off.radius > 0 else 0.0
        else:
            self.kappa0 = 0.0
        reach = math.dist(p0[:2], self.p4c2) + 8.0 * rho_min * max(RHO_SCAN) + radius + safety
        self.near = [
            i
            for i, e in enumerate(self.contour)
            if i in self.contact or float(points_distance(e, np.array([self.p4c2]))[0]) <= reach
        ]

    def required(self, i: int) -> float:
        return self.R if i in self.contact else self.R + self.safety

    def add_constraints(self, opti: Any, pts: list[Any], skip_last_contact: int = 0) -> dict[str, list[Any]]:
        """Clearance and region constraints at sample points; returns the expressions by group."""
        groups: dict[str, list[Any]] = {"clearance": [], "region": []}
        for k, p in enumerate(pts):
            for i in self.near:
                if i in self.contact and k >= len(pts) - skip_last_contact:
                    continue  # the last samples touch the contour at P4c
                g = ca_point_element_distance(p, self.contour[i]) - self.required(i)
                if not _symbolic(g):
                    continue  # the fixed start point is checked before solving
                opti.subject_to(g >= 0)
                groups["clearance"].append(g)
            for a, b in self.edges:
                ln = math.dist(a, b)
                g = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / ln
                if not _symbolic(g):
                    continue
                opti.subject_to(g >= 0)
                groups["region"].append(g)
        return groups

    def exact_check(self, elements: Sequence[Element]) -> dict[str, float]:
        """Exact violations (mm) of clearance, contact, region, curvature and tangency."""
        out = {"clearance": 0.0, "region": 0.0, "curvature": 0.0, "tangency": 0.0}
        self.last_min_clear = math.inf
        self.last_contact = math.inf
        for i, e in enumerate(self.contour):
            d = min(element_distance(el, e)[0] for el in elements)
            if i in self.contact:
                self.last_contact = min(self.last_contact, d)
                out["clearance"] = max(out["clearance"], self.R - d - 1e-9)
            else:
                self.last_min_clear = min(self.last_min_clear, d)
                out["clearance"] = max(out["clearance"], self.R + self.safety - d - 1e-7)
        for el in elements:
            pts = [el.point2(u) for u in np.linspace(0.0, 1.0, 64)]
            if self.edges:
                out["region"] = max(out["region"], max(-_inside_margin(p, self.edges) for p in pts) - 1e-7)
            if isinstance(el, Arc):
                out["curvature"] = max(out["curvature"], self.rho_min - el.radius - 1e-9)
        last = elements[-1]
        te = _unit(last.end_tangent())
        out["tangency"] = abs(te[0] * self.t[1] - te[1] * self.t[0]) + max(
            0.0, -(te[0] * self.t[0] + te[1] * self.t[1])
        )
        out["tangency"] += math.dist(last.end[:2], self.p4c2)
        return {k: max(0.0, v) for k, v in out.items()}


# --------------------------------------------------------------------------------------------
# family 1: line + arc (Dubins-like, with the arc radius a variable)
# --------------------------------------------------------------------------------------------


def _line_arc_guess(ctx: _Context, c: int, rho: float) -> tuple[float, float]:
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


def _line_arc_elements(ctx: _Context, c: int, rho: float, phi: float) -> tuple[Element, ...]:
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


def _solve_line_arc(ctx: _Context, c: int, rho_lb: float) -> tuple[Solution[Any], tuple[Element, ...], float, float]:
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


# --------------------------------------------------------------------------------------------
# family 2: quintic Bézier (clothoid-like: curvature continuous into the contour)
# --------------------------------------------------------------------------------------------

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


def _poly_controls(ctx: _Context, psi: Any, a: Any, q2: Any, f: Any, d: Any, lib: Any) -> list[Any]:
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


def _poly_element(ctx: _Context, x: Sequence[float]) -> Poly:
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


def _solve_poly(ctx: _Context, guess: tuple[float, ...]) -> tuple[Solution[Any], tuple[Element, ...]]:
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


def _poly_guess(ctx: _Context, elements: Sequence[Element] | None) -> tuple[float, ...]:
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


# --------------------------------------------------------------------------------------------


def _sar_shape(ctx: _Context, c: int, rho: float, phi: float, elements: Sequence[Element]) -> SarShape | None:
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
    ctx = _Context(p0, els, radius, side_e, rho_min, safety, region)
    if ctx.edges and _inside_margin(ctx.p4c2, ctx.edges) < -1e-9:
        raise SolverError("no lead fits: binding constraint 'region' (the contour start P4c lies outside it)")
    if ctx.edges and _inside_margin(p0[:2], ctx.edges) < -1e-9:
        raise SolverError("no lead fits: binding constraint 'region' (the start point lies outside it)")
    for i, e in enumerate(els):
        d0 = float(points_distance(e, np.array([p0[:2]]))[0])
        if d0 < ctx.required(i) - 1e-9:
            raise SolverError(
                f"no lead fits: binding constraint 'clearance' (the start point is {d0:.4g} mm from contour "
                f"element {i + 1}, less than R{'' if i in ctx.contact else ' + safety'} = {ctx.required(i):.4g} mm)",
                code="SOLVER-INFEASIBLE",
            )
    first_tc = offset_start(els[0], radius, side_e)
    candidates: list[LeadCandidate] = []
    failures: list[tuple[str, Solution[Any], dict[str, float]]] = []
    objective = "time"

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
        t, objective = lead_time(elements, first_tc, machine, feed_mm_s, plane, rho_min)
        candidates.append(
            LeadCandidate(
                kind, elements, sum(e.length for e in elements), t, ctx.last_min_clear, ctx.last_contact, sol, rho, phi
            )
        )

    best_la: tuple[Element, ...] | None = None
    if "line_arc" in families:
        for c in (1, -1):
            for k in RHO_SCAN:
                sol, elements, r, f = _solve_line_arc(ctx, c, k * rho_min)
                consider("line_arc", sol, elements, r, f)
        if candidates:
            best_la = min(candidates, key=lambda c: c.time_s).elements
    if "poly" in families:
        sol, elements = _solve_poly(ctx, _poly_guess(ctx, best_la))
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
            code="SOLVER-INFEASIBLE",
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
