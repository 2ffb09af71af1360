"""One corner transition as an SQP of convex quadratic programs.

A tangent discontinuity J of the tool-centre path between element ``a`` (incoming) and ``b``
(outgoing) is replaced by a quintic Hermite curve from a point A on ``a`` (arc length ``sa``
before J) to a point B on ``b`` (``sb`` after J). End conditions give G2 continuity by
construction: ``P'(0) = α·t_A``, ``P''(0) = α²·κ_A·n_A + β·t_A`` (same at B with γ, δ), so the
decision vector is ``x = (sa, α, β, sb, γ, δ)`` (mm, mm, mm, mm, mm, mm).

Constraints (all evaluated exactly on samples, linearised by finite differences):

* **no gouge** — distance of every blend sample to every nearby programmed element ≥ R;
* **cut deviation ≤ ε** — the material left beyond the exact cut boundary, measured along the
  boundary normals (:func:`~trcopt.optimize.corners.boundary.material_left`); the sampled value
  is an upper bound of the true one because the swept region of the sampled centres is a subset
  of the true swept region;
* positive end speeds, available lengths on both neighbours.

Objective: the largest |curvature| (epigraph variable), the time surrogate of a corner (speed
through it ≈ sqrt(a/κ)); under jerk limits (``limits=(amax, jmax)``) the larger of |κ| and the
curvature equivalent of the curvature rate, ``amax·(|dκ/ds|/jmax)^(2/3)`` (following a curvature
change at speed v takes jerk v³·|dκ/ds|). Each SQP step solves a QP
(:func:`~trcopt.optimize.convex.solve_qp`) in scaled variables with a proximal term and a trust
region; steps are accepted on an exact merit function.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from trcopt.optimize.convex import solve_qp
from trcopt.optimize.corners.curves import frame_back, frame_forward, quintic_basis, quintic_third_basis, rot90
from trcopt.optimize.corners.sites import CornerSite
from trcopt.solution import Solution, SolveStatus

__all__ = ["CornerBlendProblem", "CornerGeometry", "CornerSolution"]

CLEAR_TOL_MM = 1e-9
ELASTIC_WEIGHT = 100.0  # price of the elastic slack (in units of the scaled objective)


@dataclass(frozen=True)
class CornerGeometry:
    """Decoded transition: end arc lengths and the quintic Hermite end data (plane, mm)."""

    sa: float
    sb: float
    p0: tuple[float, float]
    d0: tuple[float, float]
    a0: tuple[float, float]
    a1: tuple[float, float]
    d1: tuple[float, float]
    p1: tuple[float, float]
    max_curvature: float  # 1/mm, sampled
    max_deviation: float  # mm, material left (sampled upper bound)
    min_clearance: float  # mm, smallest distance to the programmed contour


CornerSolution = Solution[CornerGeometry]


class CornerBlendProblem:
    """The transition at one corner as an inspectable SQP; each step is a convex QP.

    Build, inspect (``x0``, :meth:`evaluate`, :meth:`qp_matrices` → P, q, A, l, u of the first
    step), then :meth:`solve`.

    Parameters
    ----------
    site:
        The corner.
    tolerance_mm:
        Contour tolerance ε (material left ≤ ε), mm.
    samples:
        Blend samples for the constraints.
    limits:
        ``(amax mm/s², jmax mm/s³)``: minimise the jerk objective of :meth:`objective_samples`
        instead of the peak curvature.
    """

    N_VAR = 6

    def __init__(
        self, site: CornerSite, tolerance_mm: float, samples: int = 48, limits: tuple[float, float] | None = None
    ):
        if tolerance_mm <= 0:
            raise ValueError(f"tolerance_mm must be positive, got {tolerance_mm!r}")
        if limits is not None and not (limits[0] > 0 and limits[1] > 0):
            raise ValueError(f"limits (amax mm/s², jmax mm/s³) must be positive, got {limits!r}")
        self.site = site
        self.eps = float(tolerance_mm)
        self.limits = limits
        self.u = np.linspace(0.0, 1.0, samples)
        self.H0, self.H1, self.H2 = quintic_basis(self.u)
        self.H3 = quintic_third_basis(self.u)
        self.iterations = 0
        self.x0 = self._initial_guess()

    # ---------------------------------------------------------------- geometry
    def _initial_guess(self) -> np.ndarray:
        s = self.site
        phi = abs(s.turn)
        # circular blend with path deviation ε: tangent length r·tan(φ/2)
        c = math.cos(0.5 * phi)
        r = self.eps * c / max(1.0 - c, 1e-12)
        tl = min(r * math.tan(0.5 * phi), 0.9 * s.avail_a, 0.9 * s.avail_b)
        tl = max(tl, 1e-3 * min(s.avail_a, s.avail_b))
        chord = 2.0 * tl * math.cos(0.5 * phi)
        if s.min_cut > 0.0:
            # replacing a transition circle of radius r = min_cut/tan(φ/2): start where the line is
            # still within about ε of the circle, derivative magnitude ≈ the circle's length
            r_c = s.min_cut / math.tan(0.5 * phi)
            room = min(s.avail_a, s.avail_b) - s.min_cut
            tl = s.min_cut + min(0.5 * math.sqrt(2.0 * r_c * self.eps), 0.9 * room)
            chord = r_c * phi + 2.0 * (tl - s.min_cut)
        return np.array([tl, chord, 0.0, tl, chord, 0.0])

    def coefficients(self, x: np.ndarray) -> np.ndarray:
        """(6×2) quintic Hermite coefficients P0, D0, A0, A1, D1, P1 for ``x``."""
        s = self.site
        sa, al, be, sb, ga, de = x
        pa, ta, ka = frame_back(s.a, sa)
        pb, tb, kb = frame_forward(s.b, sb)
        na, nb = rot90(ta), rot90(tb)
        return np.stack((pa, al * ta, al * al * ka * na + be * ta, ga * ga * kb * nb + de * tb, ga * tb, pb))

    def evaluate(self, x: np.ndarray, dense: bool = False) -> dict[str, np.ndarray]:
        """Curvature (1/mm), material left (mm) and clearance (mm) at the samples for ``x``."""
        C = self.coefficients(x)
        if dense:
            H0, H1, H2 = quintic_basis(np.linspace(0.0, 1.0, 400))
        else:
            H0, H1, H2 = self.H0, self.H1, self.H2
        p, d1, d2 = H0 @ C, H1 @ C, H2 @ C
        sp = np.hypot(d1[:, 0], d1[:, 1])
        cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
        kappa = cross / np.maximum(sp, 1e-300) ** 3
        s = self.site
        dev = s.material_left(p, float(x[0]), float(x[3]), self.eps)
        clear = s.programmed_set.distance(p)
        out = {"kappa": kappa, "speed": sp, "dev": dev, "clear": clear, "points": p}
        if self.limits is not None:
            d3 = (quintic_third_basis(np.linspace(0.0, 1.0, 400)) if dense else self.H3) @ C
            spm = np.maximum(sp, 1e-300)
            # dκ/ds = (x′y‴ − y′x‴)/|P′|⁴ − 3 (x′y″ − y′x″)(P′·P″)/|P′|⁶
            dk = (d1[:, 0] * d3[:, 1] - d1[:, 1] * d3[:, 0]) / spm**4 - 3.0 * cross * np.einsum(
                "ij,ij->i", d1, d2
            ) / spm**6
            out["dkappa"] = dk
        return out

    def objective_samples(self, ev: dict[str, np.ndarray]) -> np.ndarray:
        """Per-sample cost, 1/mm: |κ| (the speed through a sample is ≤ sqrt(amax/|κ|)); with
        ``limits = (amax, jmax)`` the larger of |κ| and ``amax·(|dκ/ds|/jmax)^(2/3)`` — the
        curvature whose acceleration limit gives the same speed as the jerk of following the
        curvature change, ``v³·|dκ/ds| ≤ jmax``."""
        k = np.abs(ev["kappa"])
        if self.limits is None:
            return k
        amax, jmax = self.limits
        return np.maximum(k, amax * (np.abs(ev["dkappa"]) / jmax) ** (2.0 / 3.0))

    def _constraints(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(cost samples, g ≤ 0 rows) at ``x``: :meth:`objective_samples`; deviation − ε, R − clearance."""
        ev = self.evaluate(x)
        s = self.site
        # the end samples lie on the neighbours by construction (clearance exactly R). At an outside
        # corner the programmed vertex lies on the concave side and the clearance has its minimum
        # inside the transition: between two samples the curve can come closer by its sag,
        # |κ|·h²/8 at most (h: sample spacing). At an inside corner the transition turns away from
        # the contour and the clearance grows monotonically from the ends.
        kappa = np.abs(ev["kappa"])
        cost = self.objective_samples(ev)
        if s.inside:
            margin = 0.0
        else:
            h = np.hypot(*np.diff(ev["points"], axis=0).T)
            sag = np.maximum(kappa[1:], kappa[:-1]) * h * h / 8.0
            margin = np.maximum(sag[1:], sag[:-1])
        g = np.concatenate((ev["dev"] - (1.0 - 1e-3) * self.eps, s.radius + margin - ev["clear"][1:-1] - CLEAR_TOL_MM))
        return cost, g

    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        s = self.site
        cut = max(1e-6, s.min_cut * (1.0 + 1e-9))
        lo = np.array([cut, 1e-6, -np.inf, cut, 1e-6, -np.inf])
        hi = np.array([s.avail_a, np.inf, np.inf, s.avail_b, np.inf, np.inf])
        return lo, hi

    def _linearise(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        k0, g0 = self._constraints(x)
        scale = max(float(x[0] + x[3]), 1e-6)
        Jk = np.empty((k0.shape[0], self.N_VAR))
        Jg = np.empty((g0.shape[0], self.N_VAR))
        for i in range(self.N_VAR):
            h = 1e-6 * scale
            xp = x.copy()
            xp[i] += h
            kp, gp = self._constraints(xp)
            Jk[:, i] = (kp - k0) / h
            Jg[:, i] = (gp - g0) / h
        return k0, g0, Jk, Jg

    def qp_matrices(
        self, x: np.ndarray | None = None, trust: float | None = None
    ) -> tuple[Any, np.ndarray, Any, np.ndarray, np.ndarray]:
        """QP data (P, q, A, l, u) of the SQP step at ``x`` in the scaled variables (y, t),
        ``y = Δx/L`` with ``L = sa + sb`` (:meth:`step_scale`):

        min t + ½·ρ·|y|²  s.t.  (|κ_k| + ∇|κ_k|·L·y)/κ_ref ≤ t,  (g + ∇g·L·y)/ε ≤ 0,  bounds,
        |y| ≤ trust/L; at a transition-circle site (``min_cut > 0``) with an elastic slack σ ≥ 0 on
        the g rows priced W·σ (W = ``ELASTIC_WEIGHT``). Curvature rows are scaled by the current
        peak curvature and deviation/clearance rows by ε, so every row is of order one. Rows that
        cannot become active inside the trust box are left out (exactly the same QP solution; most
        probes are swept and have a zero gradient).
        """
        import scipy.sparse as sp

        x = self.x0 if x is None else x
        L = self.step_scale(x)
        trust = 0.5 * L if trust is None else trust
        k0, g0, Jk, Jg = self._linearise(x)
        n = self.N_VAR
        kref = max(float(k0.max()), 1e-9)
        lo_b, hi_b = self._bounds()
        reach = np.abs(Jg) @ np.minimum(trust, np.maximum(hi_b - x, x - lo_b))
        live = g0 + reach > 0.0
        Jg, g0 = Jg[live], g0[live]
        # columns: y (n), t and, for a transition-circle site, σ ≥ 0: an elastic slack on the
        # deviation/clearance rows priced at ELASTIC_WEIGHT, so that a step exists from its
        # (infeasible) start — a circle cannot be shrunk towards the joint to find a feasible one
        m = 1 if self.site.min_cut > 0.0 else 0
        rows_k = np.hstack((Jk * (L / kref), -np.ones((k0.shape[0], 1)), np.zeros((k0.shape[0], m))))
        rows_g = np.hstack((Jg * (L / self.eps), np.zeros((g0.shape[0], 1)), -np.ones((g0.shape[0], m))))
        rows_b = np.hstack((np.eye(n), np.zeros((n, 1 + m))))
        row_s = np.zeros((m, n + 1 + m))
        row_s[:, -1] = 1.0
        A = np.vstack((rows_k, rows_g, rows_b, row_s))
        lower = np.concatenate(
            (
                np.full(k0.shape[0], -np.inf),
                np.full(g0.shape[0], -np.inf),
                np.maximum(lo_b - x, -trust) / L,
                np.zeros(m),
            )
        )
        upper = np.concatenate((-k0 / kref, -g0 / self.eps, np.minimum(hi_b - x, trust) / L, np.full(m, np.inf)))
        lower = np.minimum(lower, upper)
        rho = 3e-2
        P = sp.diags(np.concatenate((np.full(n, rho), np.zeros(1 + m)))).tocsc()
        q = np.concatenate((np.zeros(n), [1.0], np.full(m, ELASTIC_WEIGHT)))
        return P, q, sp.csc_matrix(A), lower, upper

    @staticmethod
    def step_scale(x: np.ndarray) -> float:
        """Length scale L of the QP variables (``Δx = L·y``), mm."""
        return max(float(x[0] + x[3]), 1e-6)

    # ---------------------------------------------------------------- solve
    def _merit(self, x: np.ndarray) -> tuple[float, float]:
        k, g = self._constraints(x)
        return float(k.max()), float(max(0.0, g.max()))

    def solve(self, max_iter: int = 30) -> CornerSolution:
        """SQP iterations (an interior-point QP per step); returns the best iterate whose exact sampled constraints
        hold. Stops when the peak curvature improves by < 0.1 % over three accepted steps."""
        t0 = time.perf_counter()
        x = self.x0.copy()
        f, v = self._merit(x)
        if v > 0.0 and self.site.min_cut == 0.0:
            x = self._restore(x)
            f, v = self._merit(x)
        best = (f, x.copy()) if self._feasible(x, dense=True) else (math.inf, x.copy())
        L = max(float(x[0] + x[3]), 1e-6)
        trust = 0.25 * L
        status_msg = "max iterations"
        history: list[float] = []
        done = 0
        for it in range(1, max_iter + 1):
            done = it
            P, q, A, lo, hi = self.qp_matrices(x, trust)
            res = solve_qp(P, q, A, lo, hi)
            if res.x is None:
                trust *= 0.25
                if trust < 1e-7 * L:
                    status_msg = f"qp: {res.status}"
                    break
                continue
            dx = self.step_scale(x) * res.x[: self.N_VAR]
            xn = x + dx
            fn, vn = self._merit(xn)
            mu = 10.0 * max(f, 1e-6) / max(self.eps, 1e-9)
            if fn + mu * vn < f + mu * v - 1e-12 * max(f, 1.0):
                x, f, v = xn, fn, vn
                if f < best[0] and self._feasible(x) and self._feasible(x, dense=True):
                    best = (f, x.copy())
                trust = min(trust * 1.5, 0.5 * L)
                history.append(f)
                if vn <= 1e-6 * self.eps and len(history) > 5 and history[-6] - f < 1e-3 * f:
                    status_msg = "converged"
                    break
            else:
                trust *= 0.3
                if trust < 1e-6 * L:
                    status_msg = "converged (trust region)"
                    break
        x = best[1]
        self.iterations = done
        ev = self.evaluate(x, dense=True)
        ok = float(ev["dev"].max()) <= self.eps and float(ev["clear"].min()) >= self.site.radius - 2 * CLEAR_TOL_MM
        p0, d0, a0, a1, d1, p1 = ((float(row[0]), float(row[1])) for row in self.coefficients(x))
        geom = CornerGeometry(
            float(x[0]),
            float(x[3]),
            p0,
            d0,
            a0,
            a1,
            d1,
            p1,
            max_curvature=float(np.abs(ev["kappa"]).max()),
            max_deviation=float(ev["dev"].max()),
            min_clearance=float(ev["clear"].min()),
        )
        return Solution(
            SolveStatus.OPTIMAL if ok else SolveStatus.INFEASIBLE,
            float(self.objective_samples(ev).max()),
            done,
            time.perf_counter() - t0,
            geom,
            {
                "deviation": max(0.0, geom.max_deviation - self.eps),
                "clearance": max(0.0, self.site.radius - geom.min_clearance),
            },
            status_msg,
            "clarabel-sqp",
        )

    def _feasible(self, x: np.ndarray, dense: bool = False) -> bool:
        """Exact constraints with the true tolerance (the SQP aims 0.1 % inside it) on the SQP's
        samples, or on the dense samples of the final acceptance (``dense``), which also catch a
        transition dipping below the clearance between two SQP samples."""
        ev = self.evaluate(x, dense=dense)
        if dense:
            return float(ev["dev"].max()) <= self.eps and float(ev["clear"].min()) >= (
                self.site.radius - 2 * CLEAR_TOL_MM
            )
        return float(ev["dev"].max()) <= self.eps and float(ev["clear"][1:-1].min(initial=math.inf)) >= (
            self.site.radius - CLEAR_TOL_MM
        )

    def _restore(self, x: np.ndarray) -> np.ndarray:
        """Shrink the initial transition until the exact constraints hold (feasible start)."""
        for _ in range(60):
            _, v = self._merit(x)
            if v <= 0.0:
                return x
            cut = np.array([self.site.min_cut, 0.0, 0.0, self.site.min_cut, 0.0, 0.0])
            x = cut + (x - cut) * np.array([0.7, 0.7, 0.49, 0.7, 0.7, 0.49])
        return x
