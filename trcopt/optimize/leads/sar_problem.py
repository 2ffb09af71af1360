"""SINUMERIK smooth approach/retraction (SAR) geometry posed as a constrained problem.

The points P1, P2, P3 (programmed), the circle centre M, the programmed radius ρp and the
tool-centre points P3c, P4c are decision variables of a ``casadi.Opti``; the constraints are the
spec's (``sinumerik_trc.md`` R37–R42), written with the constraint model's vocabulary:

* **radius** — |P3 − M| = |P4 − M| = ρp, ρp = DISR + s·σ·R (circles), |P3c − M| = DISR
  (tool-centre radius), |P4c − P4| = |P3c − P3| = R (tool centre at the radius, lines);
  line length |P4 − P3| = L = DISR + R (G147/G148);
* **tangency** — the radius M→P4 is normal to t; P4c lies on the normal of t at P4 on the
  compensation side; a straight lead runs along t;
* **sweep** — quadrant: (P3 − M) ⟂ (P4 − M) turning with sense σ; semicircle: P3, M, P4
  collinear with P3 opposite P4;
* **levels** — w2 = w4 + DISCL (or AC), w1 = w0 (or DISRP), P1, P2, P3 share the plane position,
  G340 / G341 segmentation;
* **no_reversal** — w1 → w2 → w3 → w4 monotonic (R42).

The problem is a feasibility problem (cost 0); it is solved by IPOPT from a deliberately poor
start and must reproduce the analytic construction (that is a test). Plane coordinates (u, v, w),
mm; ``t`` is the unit plane tangent at P4 (start tangent of the contour on approach, end tangent
on retraction).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from trcopt.errors import GeometryError
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import LeadSegmentation, LeadSide, SarContour, Side, parse_enum
from trcopt.optimize.leads.sar_geometry import SarGeometry
from trcopt.solution import Solution, SolveStatus, ipopt_options

__all__ = ["SarProblem"]


def _unit(t: tuple[float, float]) -> Vec2:
    n = math.hypot(t[0], t[1])
    if n == 0.0:
        raise GeometryError("SAR tangent at P4 has zero length (alarm 10744: no direction derivable)")
    return (t[0] / n, t[1] / n)


@dataclass
class SarProblem:
    """SAR geometry as a ``casadi.Opti`` feasibility problem (inspect ``.opti`` before solving).

    Parameters
    ----------
    contour:
        ``G147``…``G348`` (:class:`~trcopt.nc.model.SarContour` or its name).
    p0:
        Start point (approach) or programmed end point (retraction), plane coords (u, v, w), mm.
    p4:
        Contour start (approach) / end (retraction), mm.
    tangent:
        Plane tangent of the contour at P4 (normalised here).
    trc_side:
        Compensation side in force (:class:`~trcopt.nc.model.Side` or ``left``/``right``/``off``).
    radius:
        Effective compensation radius R ≥ 0 (tool radius + OFFN), mm.
    disr:
        DISR, mm (circles: tool-centre radius; lines: distance of the cutter edge).
    side:
        G140…G143 (side of approach for circles, R37).
    discl, disrp:
        ``(value, absolute)`` or None, mm.
    segmentation:
        G340 (spatial) / G341 (plane).
    """

    contour: SarContour | str
    p0: Vec3
    p4: Vec3
    tangent: Vec2
    trc_side: Side | str = Side.LEFT
    radius: float = 0.0
    disr: float | None = None
    side: LeadSide | str = LeadSide.FROM_COMPENSATION
    discl: tuple[float, bool] | None = None
    disrp: tuple[float, bool] | None = None
    segmentation: LeadSegmentation | str = LeadSegmentation.SPATIAL
    opti: Any = field(init=False, repr=False)
    variables: dict[str, Any] = field(init=False, repr=False)
    groups: dict[str, list[Any]] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.contour = parse_enum(SarContour, self.contour)
        self.side = parse_enum(LeadSide, self.side)
        self.segmentation = parse_enum(LeadSegmentation, self.segmentation)
        self.trc_side = parse_enum(Side, self.trc_side)
        self.tangent = _unit(self.tangent)
        if self.disr is None:
            raise GeometryError(f"{self.contour.value}: DISR is not programmed (R38)")
        self._build()

    # ---- derived data (spec R37, R38) ------------------------------------------------------
    @property
    def s(self) -> int:
        """Compensation side sign: +1 G41, −1 G42, 0 G40 or R = 0."""
        return self.trc_side.sign if self.radius > 0.0 else 0  # type: ignore[union-attr]

    @property
    def q(self) -> int:
        """Side of approach (R37): +1 left, −1 right."""
        side = self.side
        if side is LeadSide.LEFT:
            return 1
        if side is LeadSide.RIGHT:
            return -1
        if side is LeadSide.FROM_COMPENSATION and self.trc_side is not Side.OFF:
            return self.trc_side.sign  # type: ignore[union-attr]
        t = self.tangent
        c = t[0] * (self.p0[1] - self.p4[1]) - t[1] * (self.p0[0] - self.p4[0])
        return 1 if c > 0.0 else -1

    @property
    def is_line(self) -> bool:
        return self.contour in (SarContour.G147, SarContour.G148)

    @property
    def approach(self) -> bool:
        return self.contour.is_approach  # type: ignore[union-attr]

    # ---- the problem -----------------------------------------------------------------------
    def _build(self) -> None:
        import casadi as ca

        opti = ca.Opti()
        V = {
            "P1": opti.variable(3),
            "P2": opti.variable(3),
            "P3": opti.variable(3),
            "M": opti.variable(2),
            "rho_p": opti.variable(),
            "P3c": opti.variable(2),
            "P4c": opti.variable(2),
        }
        P1, P2, P3, M, rho, P3c, P4c = (V[k] for k in ("P1", "P2", "P3", "M", "rho_p", "P3c", "P4c"))
        p0 = ca.DM(self.p0)
        p4 = ca.DM(self.p4)
        p4u = p4[:2]
        t = ca.DM(self.tangent)
        R, s, q, disr = self.radius, self.s, self.q, float(self.disr)  # type: ignore[arg-type]

        def cross(a: Any, b: Any) -> Any:
            return a[0] * b[1] - a[1] * b[0]

        def dot(a: Any, b: Any) -> Any:
            return a[0] * b[0] + a[1] * b[1]

        g: dict[str, list[Any]] = {
            "radius": [],
            "tangency": [],
            "sweep": [],
            "levels": [],
            "no_reversal": [],
        }
        ineq: dict[str, list[Any]] = {"radius": [], "tangency": [], "sweep": [], "no_reversal": []}
        # tool centre at P4: on the normal of t at P4 (tangency), at signed distance s·R (radius)
        g["tangency"].append(dot(P4c - p4u, t))
        g["radius"].append(cross(t, P4c - p4u) - s * R)
        if self.is_line:
            L = disr + R if s != 0 else disr
            d = (p4u - P3[:2]) if self.approach else (P3[:2] - p4u)
            g["tangency"].append(cross(t, d))
            g["radius"].append(dot(t, d) - L)  # line length: cutter edge DISR before P4
            g["radius"].append(rho - L)
            opti.subject_to(M == p4u)  # unused for lines; pinned so the problem stays regular
            g["tangency"].append(dot(P3c - P3[:2], t))
            g["radius"].append(cross(t, P3c - P3[:2]) - s * R)
        else:
            sigma = q
            g["radius"].append(rho - (disr + s * sigma * R))
            ineq["radius"].append(rho)  # ρp > 0 (alarm otherwise, R38)
            # centre: the radius M → P4 is normal to t (tangency at P4), M on side q at ρp
            g["tangency"].append(dot(M - p4u, t))
            g["radius"].append(cross(t, M - p4u) - q * rho)
            r3 = P3[:2] - M
            r4 = p4u - M
            if self.contour in (SarContour.G247, SarContour.G248):
                # quarter turn with sense σ: approach P3 → P4, retraction P4 → P3
                k = sigma if self.approach else -sigma
                g["sweep"] += [r3[0] - k * r4[1], r3[1] + k * r4[0]]
            else:
                g["sweep"] += [r3[0] + r4[0], r3[1] + r4[1]]  # half turn: P3 opposite P4
            # tool-centre point at P3: on the ray M → P3 at the tool-centre radius DISR
            g["radius"] += [
                rho * (P3c[0] - M[0]) - disr * r3[0],
                rho * (P3c[1] - M[1]) - disr * r3[1],
            ]
        # levels (R41): P1, P2, P3 share the plane position
        g["levels"] += [P1[0] - P3[0], P1[1] - P3[1], P2[0] - P3[0], P2[1] - P3[1]]
        w0, w4 = self.p0[2], self.p4[2]
        if self.disrp is None:
            g["levels"].append(P1[2] - w0)
        else:
            v, absolute = self.disrp
            g["levels"].append(P1[2] - (v if absolute else w4 + v))
        discl_zero = self.discl is None or (not self.discl[1] and self.discl[0] == 0.0)
        if discl_zero:
            if self.segmentation is LeadSegmentation.SPATIAL:
                g["levels"] += [P2[2] - P1[2], P3[2] - P1[2]]  # §D-3: the contour descends from w1
            else:
                g["levels"] += [P2[2] - w4, P3[2] - w4]
        else:
            v, absolute = self.discl  # type: ignore[misc]
            g["levels"].append(P2[2] - (v if absolute else w4 + v))
            if self.segmentation is LeadSegmentation.SPATIAL:
                g["levels"].append(P3[2] - P2[2])
            else:
                g["levels"].append(P3[2] - w4)
        # no reversal of the infeed axis: w1 → w2 → w3 → w4 monotonic, direction from w1 to w4
        direction = 1.0 if w4 >= self._w1_value() else -1.0
        ws: list[Any] = [P1[2], P2[2], P3[2], w4]
        for i in range(3):
            ineq["no_reversal"].append(direction * (ws[i + 1] - ws[i]))

        eq_only = opti.copy()
        for exprs in g.values():
            for e in exprs:
                opti.subject_to(e == 0)
                eq_only.subject_to(e == 0)
        for exprs in ineq.values():
            for e in exprs:
                opti.subject_to(e >= 0)
        opti.minimize(0)
        eq_only.minimize(0)
        self.opti, self.variables = opti, V
        self._eq_only = eq_only
        self.groups = {k: list(v) for k, v in g.items()}
        self._ineq = ineq
        self._p0 = p0

    def _w1_value(self) -> float:
        if self.disrp is None:
            return self.p0[2]
        v, absolute = self.disrp
        return v if absolute else self.p4[2] + v

    def describe(self) -> str:
        """Variables and constraint groups, for inspection before solving."""
        n_eq = sum(len(v) for v in self.groups.values())
        n_in = sum(len(v) for v in self._ineq.values())
        return (
            f"SarProblem {self.contour.value} ({'approach' if self.approach else 'retraction'}), "  # type: ignore[union-attr]
            f"side q={self.q:+d}, TRC s={self.s:+d}, R={self.radius}, DISR={self.disr}; "
            f"variables {', '.join(self.variables)}; {n_eq} equality groups "
            f"({', '.join(f'{k}:{len(v)}' for k, v in self.groups.items())}), {n_in} inequalities"
        )

    def poor_start(self) -> dict[str, Any]:
        """A deliberately poor initial guess: every point far from its answer, unit radius."""
        u0, v0, w0 = self.p0
        off = (37.0, -23.0, 11.0)
        return {
            "P1": [u0 + off[0], v0 + off[1], w0 + off[2]],
            "P2": [u0 - off[1], v0 + off[0], w0 - off[2]],
            "P3": [u0 + off[2], v0 - off[0], w0 + 2 * off[2]],
            "M": [u0 - 19.0, v0 + 41.0],
            "rho_p": 1.0,
            "P3c": [u0 + 5.0, v0 + 3.0],
            "P4c": [self.p4[0] + 13.0, self.p4[1] - 17.0],
        }

    def solve(self, initial: dict[str, Any] | None = None, tol: float = 1e-12) -> Solution[SarGeometry]:
        """Solve with IPOPT from ``initial`` (default: :meth:`poor_start`).

        When IPOPT finds no feasible point, the problem is solved again with the equality
        constraints only (they define the geometry); the inequality group violated there
        (``radius``: ρp ≤ 0, ``no_reversal``: DISCL reversal) is the binding constraint.
        """
        sol = self._solve(self.opti, initial, tol)
        if sol.ok:
            return sol
        relaxed = self._solve(self._eq_only, initial, tol)
        violation = dict(relaxed.constraint_violation)
        if relaxed.ok or max(violation.values()) > 0.0:
            return Solution(
                SolveStatus.INFEASIBLE,
                0.0,
                sol.iterations,
                sol.solve_time_s + relaxed.solve_time_s,
                relaxed.geometry,
                violation,
                sol.message,
            )
        return sol

    def _solve(self, base: Any, initial: dict[str, Any] | None, tol: float) -> Solution[SarGeometry]:
        opti = base.copy()
        start = self.poor_start() if initial is None else initial
        for k, v in start.items():
            opti.set_initial(self.variables[k], v)
        opti.solver("ipopt", ipopt_options(tol=tol))
        t0 = time.perf_counter()
        try:
            sol = opti.solve()
            val = sol.value
            stats = sol.stats()
            status = SolveStatus.OPTIMAL
        except RuntimeError:
            val = opti.debug.value
            stats = opti.stats()
            status = SolveStatus.FAILED
        elapsed = time.perf_counter() - t0
        message = str(stats.get("return_status", ""))
        if status is not SolveStatus.OPTIMAL and "Infeasible" in message:
            status = SolveStatus.INFEASIBLE
        violation = {
            name: max((float(np.max(np.abs(np.asarray(val(e), float)))) for e in exprs), default=0.0)
            for name, exprs in self.groups.items()
        }
        for name, exprs in self._ineq.items():
            worst = max((max(0.0, -float(np.min(np.asarray(val(e), float)))) for e in exprs), default=0.0)
            violation[name] = max(violation.get(name, 0.0), worst)
        geom = self._decode(val)
        if status is SolveStatus.OPTIMAL and max(violation.values()) > 1e-7:
            status = SolveStatus.FAILED
        return Solution(status, 0.0, int(stats.get("iter_count", 0)), elapsed, geom, violation, message)

    def _decode(self, val: Any) -> SarGeometry:
        V = self.variables

        def p3(name: str) -> Vec3:
            a = np.asarray(val(V[name]), float).ravel()
            return (float(a[0]), float(a[1]), float(a[2]))

        def p2(name: str) -> Vec2:
            a = np.asarray(val(V[name]), float).ravel()
            return (float(a[0]), float(a[1]))

        P3 = p3("P3")
        c3, c4 = p2("P3c"), p2("P4c")
        rho_p = float(val(V["rho_p"]))
        return SarGeometry(
            contour=self.contour,  # type: ignore[arg-type]
            p0=self.p0,
            p1=p3("P1"),
            p2=p3("P2"),
            p3=P3,
            p4=self.p4,
            center=None if self.is_line else p2("M"),
            rho_p=rho_p,
            rho_c=float(self.disr) if not self.is_line else rho_p,  # type: ignore[arg-type]
            p3c=(c3[0], c3[1], P3[2]),
            p4c=(c4[0], c4[1], self.p4[2]),
            sense=self.q,
        )

    # ---- from a part program ---------------------------------------------------------------
    @classmethod
    def from_moves(cls, moves: Any, index: int | None = None) -> SarProblem:
        """The SAR problem of the ``index``-th SAR block of interpreted moves (first by default).

        Approach: P4 is the SAR block's end if it programs a plane axis, else the end of the next
        traversing block (R45); ``t`` is the start tangent of the block after that. Retraction: P4
        is the SAR block's start, ``t`` the end tangent of the block before, P0 the block's end.
        """
        sar_idx = [i for i, m in enumerate(moves) if getattr(m, "sar", None) is not None]
        if not sar_idx:
            raise GeometryError("no SAR block (G147…G348) in the program")
        i = sar_idx[0 if index is None else index]
        m = moves[i]
        plane = m.plane
        uvw = plane.to_uvw

        def traversing(j: int) -> bool:
            mv = moves[j]
            a, b = uvw(mv.start), uvw(mv.end)
            return mv.kind.value != "none" and math.hypot(b[0] - a[0], b[1] - a[1]) > 1e-12

        def tangent_at_start(mv: Any) -> Vec2:
            a, b = uvw(mv.start), uvw(mv.end)
            if mv.center is not None:
                c = uvw(mv.center)
                r = (a[0] - c[0], a[1] - c[1])
                k = 1.0 if mv.ccw else -1.0
                return (-r[1] * k, r[0] * k)
            return (b[0] - a[0], b[1] - a[1])

        def tangent_at_end(mv: Any) -> Vec2:
            a, b = uvw(mv.start), uvw(mv.end)
            if mv.center is not None:
                c = uvw(mv.center)
                r = (b[0] - c[0], b[1] - c[1])
                k = 1.0 if mv.ccw else -1.0
                return (-r[1] * k, r[0] * k)
            return (b[0] - a[0], b[1] - a[1])

        spec = m.sar
        comp = m.comp
        if spec.contour.is_approach:
            p0 = uvw(m.start)
            j = i
            if not m.plane_programmed:
                j = next(k for k in range(i + 1, len(moves)) if traversing(k))
            p4 = uvw(moves[j].end)  # the applicate in force at the P4-defining block's end (R45)
            nxt = next(k for k in range(j + 1, len(moves)) if traversing(k))
            t = tangent_at_start(moves[nxt])
            side = moves[j].comp.side if j != i else comp.side
            radius = moves[j].comp.radius if j != i else comp.radius
        else:
            p4 = uvw(m.start)
            p0 = uvw(m.end)
            prv = next(k for k in range(i - 1, -1, -1) if traversing(k))
            t = tangent_at_end(moves[prv])
            side = moves[prv].comp.side
            radius = moves[prv].comp.radius
        return cls(
            spec.contour,
            p0,
            p4,
            t,
            trc_side=side,
            radius=abs(radius),
            disr=spec.disr,
            side=spec.side,
            discl=spec.discl,
            disrp=spec.disrp,
            segmentation=spec.segmentation,
        )
