"""One corner transition as an SQP of OSQP quadratic programs (issue 6, part 1).

A tangent discontinuity J of the tool-centre path between element ``a`` (incoming) and ``b``
(outgoing) is replaced by a quintic Hermite curve from a point A on ``a`` (arc length ``sa``
before J) to a point B on ``b`` (``sb`` after J). End conditions give G2 continuity by
construction: ``P'(0) = α·t_A``, ``P''(0) = α²·κ_A·n_A + β·t_A`` (same at B with γ, δ), so the
decision vector is ``x = (sa, α, β, sb, γ, δ)`` (mm, mm, mm, mm, mm, mm).

Constraints (all evaluated exactly on samples, linearised by finite differences):

* **no gouge** — distance of every blend sample to every nearby programmed element ≥ R;
* **cut deviation ≤ ε** — the material left beyond the exact cut boundary, measured along the
  boundary normals (:func:`material_left`); the sampled value is an upper bound of the true one
  because the swept region of the sampled centres is a subset of the true swept region;
* positive end speeds, available lengths on both neighbours.

Objective: the largest |curvature| (epigraph variable), the time surrogate of a corner (speed
through it ≈ sqrt(a/κ)); under jerk limits (``limits=(amax, jmax)``) the larger of |κ| and the
curvature equivalent of the curvature rate, ``amax·(|dκ/ds|/jmax)^(2/3)`` (following a curvature
change at speed v takes jerk v³·|dκ/ds|). Each SQP step solves an OSQP QP in scaled variables with
a proximal term and a trust region; steps are accepted on an exact merit function.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.geometry.poly import quintic_hermite_basis, quintic_hermite_third
from trcopt.solution import Solution, SolveStatus
from trcopt.verify.model import points_distance

__all__ = [
    "CornerSite",
    "CornerBlendProblem",
    "CornerSolution",
    "CornerGeometry",
    "material_left",
    "quintic_basis",
    "signed_curvature",
]

Element = Line | Arc
CLEAR_TOL_MM = 1e-9
ELASTIC_WEIGHT = 100.0  # price of the elastic slack (in units of the scaled objective)


def quintic_basis(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic Hermite basis and its first two derivatives at ``u`` (K×6 each), coefficient order
    (P0, D0, A0, A1, D1, P1) as in :func:`trcopt.geometry.hermite_curve`."""
    u = np.asarray(u, float)
    h0, h1, h2 = quintic_hermite_basis(u)
    return tuple(np.stack(np.broadcast_arrays(*h), axis=1) for h in (h0, h1, h2))  # type: ignore[return-value]


def _third_basis(u: np.ndarray) -> np.ndarray:
    """Third derivatives of the quintic Hermite basis at ``u`` (K×6)."""
    u = np.asarray(u, float)
    return np.stack(np.broadcast_arrays(*quintic_hermite_third(u)), axis=1)


def _frame_back(el: Element, s_back: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Point, unit tangent and signed curvature of ``el`` at plane arc length ``s_back`` before its end."""
    lam = 1.0 - s_back / el.plane_length
    return _frame(el, lam)


def _frame_fwd(el: Element, s_fwd: float) -> tuple[np.ndarray, np.ndarray, float]:
    return _frame(el, s_fwd / el.plane_length)


def _frame(el: Element, lam: float) -> tuple[np.ndarray, np.ndarray, float]:
    p = np.array(el.point2(lam), float)
    if isinstance(el, Line):
        return p, np.array(el.direction2(), float), 0.0
    return p, np.array(el.tangent2(lam), float), signed_curvature(el)


def signed_curvature(el: Element) -> float:
    """Signed plane curvature of a line (0) or arc (positive = turning left), 1/mm."""
    return 0.0 if isinstance(el, Line) else el.sense / el.radius


def joint_turn(a: Element, b: Element) -> float:
    """Signed turning angle from the end of ``a`` to the start of ``b``, rad (positive = left)."""
    ta, tb = a.end_tangent(), b.start_tangent()
    return math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])


def _rot90(v: np.ndarray) -> np.ndarray:
    return np.stack((-v[..., 1], v[..., 0]), axis=-1)


@dataclass(frozen=True)
class CornerSite:
    """A tangent discontinuity of the tool-centre path and what constrains its transition.

    Attributes
    ----------
    a, b:
        Incoming and outgoing tool-centre elements (plane coordinates, mm).
    radius:
        Tool radius in force, mm.
    material_sign:
        +1 when the material (programmed contour) lies left of the tool's travel (G42), −1 when
        right (G41).
    avail_a, avail_b:
        Longest plane arc length the transition may take from ``a`` (before J) and ``b`` (after J), mm.
    programmed:
        Programmed contour elements near the corner (no-gouge and deviation reference).
    probes:
        Points of the exact cut boundary near the corner (n×2, mm) and unit directions away from
        the material (n×2): the deviation is the material left along these rays.
    context:
        Exact tool-centre elements around the corner that stay in the new path (n_c×… samples
        used to cover the probes), as sample points (m×2, mm).
    min_cut:
        Smallest ``sa`` and ``sb`` (mm). Non-zero when the corner is a transition circle (G450)
        between two lines: ``a`` and ``b`` are then the lines extended to their intersection, the
        circle is replaced as a whole, and the transition must start and end on the real lines,
        at least ``min_cut`` (the circle's tangent length) from the intersection.
    """

    a: Element
    b: Element
    radius: float
    material_sign: float
    avail_a: float
    avail_b: float
    programmed: tuple[Element, ...]
    probes: np.ndarray
    probe_dirs: np.ndarray
    w: float = 0.0
    context: tuple[Element, ...] = ()
    min_cut: float = 0.0

    def material_left(self, curve: np.ndarray, sa: float, sb: float, eps: float) -> np.ndarray:
        """Material left (mm) at every probe for a transition sampled by ``curve`` (k×2) that
        replaces ``sa`` mm of ``a`` and ``sb`` mm of ``b``.

        Probes within R of the remaining exact elements are swept (exact distances); the rest
        are measured against discs around the transition samples and fine samples of the legs
        near the cut points (spacing ``sqrt(0.08·R·ε)``: the sampled swept region lags the true
        one by ≤ 1 % of ε).
        """
        if not len(self.probes):
            return np.zeros(1)
        R = self.radius
        la, lb = self.a.plane_length, self.b.plane_length
        rest = [self.a.sub(0.0, 1.0 - sa / la), self.b.sub(sb / lb, 1.0), *self.context]
        d = np.min([points_distance(e, self.probes) for e in rest], axis=0)
        out = np.zeros(len(self.probes))
        open_ = d > R * (1.0 + 1e-12) + 1e-12
        if not np.any(open_):
            return out
        fine = max(math.sqrt(0.08 * R * eps), 1e-5)
        legs = []
        for d0, el, back in ((sa, self.a, True), (sb, self.b, False)):
            stop = min(d0 + 2.0 * R, el.plane_length)
            for dd in np.append(np.arange(d0, stop, fine), stop):
                legs.append((_frame_back if back else _frame_fwd)(el, dd)[0])
        centres = np.vstack((curve, np.array(legs)))
        out[open_] = material_left(self.probes[open_], self.probe_dirs[open_], centres, R)
        return out

    @property
    def joint(self) -> np.ndarray:
        return np.array(self.a.point2(1.0), float)

    @property
    def turn(self) -> float:
        """Signed turning angle at J, rad (positive = left)."""
        return joint_turn(self.a, self.b)

    @property
    def inside(self) -> bool:
        """True when the material lies on the outer side of the turn (pocket-like corner)."""
        return self.turn * self.material_sign < 0


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


def material_left(probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, radius: float) -> np.ndarray:
    """Thickness of material left along each probe ray (mm, ≥ 0).

    A probe is a point of the exact cut boundary with the unit direction pointing away from the
    material; the new tool sweeps discs of ``radius`` around ``centres``. The result is the
    distance along the ray to the first disc (0 when the probe itself is swept). Sampled centres
    sweep a subset of the true region, so the value is an upper bound. ``centres`` is m×2 (the
    same for every probe) or n×m×2 (its own centres per probe).
    """
    rel = (centres if centres.ndim == 3 else centres[None, :, :]) - probes[:, None, :]  # n×m×2
    along = np.einsum("nmk,nk->nm", rel, dirs)
    perp2 = np.einsum("nmk,nmk->nm", rel, rel) - along * along
    inside = perp2 <= radius * radius
    root = np.sqrt(np.maximum(radius * radius - perp2, 0.0))
    entry = np.where(inside, along - root, np.inf)
    exit_ = np.where(inside, along + root, -np.inf)
    # a disc that contains the probe (entry ≤ 0 ≤ exit) sweeps it: thickness 0
    covered = np.any((entry <= 0.0) & (exit_ >= 0.0), axis=1)
    ahead = np.where(entry > 0.0, entry, np.inf).min(axis=1)
    out = np.where(covered, 0.0, ahead)
    return np.minimum(out, 10.0 * radius + 1.0)


class CornerBlendProblem:
    """The transition at one corner as an inspectable SQP; each step is an OSQP QP.

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
        self.H3 = _third_basis(self.u)
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
        pa, ta, ka = _frame_back(s.a, sa)
        pb, tb, kb = _frame_fwd(s.b, sb)
        na, nb = _rot90(ta), _rot90(tb)
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
        if s.programmed:
            clear = np.min([points_distance(e, p) for e in s.programmed], axis=0)
        else:
            clear = np.full(len(p), np.inf)
        out = {"kappa": kappa, "speed": sp, "dev": dev, "clear": clear, "points": p}
        if self.limits is not None:
            d3 = (_third_basis(np.linspace(0.0, 1.0, 400)) if dense else self.H3) @ C
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
        """OSQP data (P, q, A, l, u) of the SQP step at ``x`` in the scaled variables (y, t),
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
        """SQP iterations (OSQP per step); returns the best iterate whose exact sampled constraints
        hold. Stops when the peak curvature improves by < 0.1 % over three accepted steps."""
        import osqp

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
            solver = osqp.OSQP()
            solver.setup(
                P, q, A, lo, hi, verbose=False, eps_abs=1e-7, eps_rel=1e-7, max_iter=20000, polishing=True,
                adaptive_rho_interval=25,
            )
            res = solver.solve(raise_error=False)
            if res.x is None or not np.all(np.isfinite(res.x)) or res.info.status_val not in (1, 2):
                trust *= 0.25
                if trust < 1e-7 * L:
                    status_msg = f"osqp: {res.info.status}"
                    break
                continue
            dx = self.step_scale(x) * np.asarray(res.x[: self.N_VAR])
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
        C = self.coefficients(x)
        geom = CornerGeometry(
            float(x[0]),
            float(x[3]),
            *(tuple(float(c) for c in row) for row in C),  # type: ignore[arg-type]
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
            "osqp-sqp",
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
