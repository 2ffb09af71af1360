"""``JerkProblem``: the jerk-limited path-speed profile of one section as a CasADi/IPOPT NLP.

Model (one section = a tangent-continuous run of segments that starts and ends at rest), on the
nodes of a :class:`~trcopt.timing.jerk_grid.JerkGrid` (fixed in arc length, one segment per
interval, speed caps from the feed, the axis velocities and the curvature-jump knots):

* per node the path speed ``v_i = ṡ`` (mm/s) and path acceleration ``a_i = s̈`` (mm/s²); per
  interval its duration ``h_i`` (s) and a **constant path jerk** ``j_i = s⃛`` (mm/s³). The interval
  dynamics are integrated exactly (a triple integrator):
  ``s_{i+1} − s_i = v_i h + a_i h²/2 + j_i h³/6``, ``v_{i+1} = v_i + a_i h + j_i h²/2``,
  ``a_{i+1} = a_i + j_i h``. In the notation of TOPP (``x = ṡ²``, ``u = s̈``) the path jerk is
  ``du/dt = ṡ·du/ds``; integrating in time instead of in ``s`` keeps the start from rest exact
  (``s ∝ t³``, where any profile linear in ``s`` would never leave rest);
* per axis k, at both ends of every interval (derivatives taken *inside* the interval, so knots
  see the one-sided values): ``|q′_k v| ≤ vmax_k``, ``|q′_k a + q″_k v²| ≤ amax_k`` and
  ``|q‴_k v³ + 3 q″_k v a + q′_k j| ≤ jmax_k``; the programmed feed ``v ≤ F``; on arcs the limits
  are tightened by ``cos(Δθ/2)`` because the axis projections rotate inside an interval; extra rows
  inside arc and Poly intervals;
* with vector limits (``machine.path``): the path speed limit is part of the feed caps, and
  ``|q′a + q″v²|² ≤ A²`` and ``|q‴v³ + 3q″va + q′j|² ≤ J²`` (squared norms, smooth) at the same
  places as the per-axis rows (no ``cos(Δθ/2)`` tightening: the norms do not depend on the
  direction);
* ``v = a = 0`` at both section ends (tangent discontinuities are passed at rest with zero
  acceleration, as in the acceleration-limited stage);
* **curvature jumps** are passed at the knot speed cap of the grid,
  ``|Δq″_k|·v² ≤ jmax_k·T_c`` for every axis and ``|Δq″|·v² ≤ J·T_c`` with a vector jerk limit
  (see :mod:`trcopt.timing.jerk` for the jerk measure);
* objective: minimise the section time ``Σ h_i``.

The grid's speed estimate, scaled by ``init_scale``, warm-starts IPOPT. casadi is imported inside
:meth:`JerkProblem.build`.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from trcopt.solution import Solution, SolveStatus
from trcopt.timing.jerk_grid import JerkGrid, build_jerk_grid
from trcopt.timing.jerk_rows import RowBatch
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import Section

__all__ = ["JerkProblem", "SectionProfile", "section_label", "FAST_IPOPT"]

ACC_MARGIN = 0.999  # node constraints on a and j, leaving room for the variation inside an interval
POLY_ROW_FRACTIONS = (0.25, 0.5, 0.75)  # interior rows of a Poly interval, fractions of its duration
#: IPOPT options of a first attempt (``JerkProblem(..., fast=True)``) on top of ``ipopt_options``: a
#: monotone barrier from a small start, the warm start taken as given — on B9 random 50 a quarter fewer
#: iterations and about half the time of the adaptive barrier (benchmarks/JERK.md)
FAST_IPOPT: dict[str, Any] = {
    "mu_strategy": "monotone",
    "mu_init": 1e-3,
    "warm_start_init_point": "yes",
    "warm_start_bound_push": 1e-6,
    "warm_start_mult_bound_push": 1e-6,
}


@dataclass(frozen=True)
class SectionProfile:
    """Solved (or last-iterate) profile of one section; arc lengths are global (mm)."""

    s: np.ndarray  # nodes, mm
    v: np.ndarray  # path speed at nodes, mm/s
    a: np.ndarray  # path acceleration at nodes, mm/s²
    h: np.ndarray  # interval durations, s
    j: np.ndarray  # constant path jerk per interval, mm/s³
    iseg: np.ndarray  # segment of every interval

    @property
    def duration(self) -> float:
        return float(self.h.sum())


class JerkProblem:
    """Jerk-limited time-optimal profile of one section (inspect ``grid``/``opti`` before ``solve``).

    Parameters
    ----------
    section:
        The section (from :func:`trcopt.timing.sections.split_sections`).
    arrays:
        Closed-form evaluator of the whole tool path.
    feeds:
        Path-speed limit per segment of the whole path, mm/s (the feed, capped by the vector
        speed limit).
    vmax, amax, jmax:
        Per-axis limits X, Y, Z (mm/s, mm/s², mm/s³).
    base_s, base_v:
        The acceleration-limited profile (global arc length mm, path speed mm/s) used to place the
        nodes and to warm-start IPOPT.
    cycle_s:
        Interpolation cycle T_c (s) in which a curvature-jump acceleration step must be absorbed.
    points:
        Target number of intervals (before the per-arc minimum of ``|sweep|/DTHETA_JERK``, see
        :mod:`trcopt.timing.jerk_grid`).
    init_scale:
        The warm start is this fraction of the estimated speed.
    path_amax, path_jmax:
        Vector limits on |a| (mm/s²) and |j| (mm/s³), or None.
    fast:
        Solve with ``FAST_IPOPT`` on top of ``ipopt_options`` (``False``: ``ipopt_options`` alone,
        the adaptive barrier, slower but the more robust from a poor start).

    Attributes
    ----------
    grid:
        The :class:`~trcopt.timing.jerk_grid.JerkGrid` of the section: nodes, path derivatives,
        speed caps and curvature-jump knots.
    """

    #: IPOPT options (silent); override per instance or class to experiment
    ipopt_options: dict[str, Any] = {
        "print_level": 0,
        "sb": "yes",
        "tol": 1e-9,
        "acceptable_tol": 1e-6,
        "max_iter": 400,  # converged solves take 20–150; a stuck start is retried instead
        "mu_strategy": "adaptive",
    }

    def __init__(
        self,
        section: Section,
        arrays: PathArrays,
        feeds: np.ndarray,
        vmax: np.ndarray,
        amax: np.ndarray,
        jmax: np.ndarray,
        base_s: np.ndarray,
        base_v: np.ndarray,
        *,
        cycle_s: float = 1e-3,
        points: int | None = None,
        label: str = "",
        init_scale: float = 0.95,
        path_amax: float | None = None,
        path_jmax: float | None = None,
        fast: bool = False,
    ) -> None:
        self.section = section
        self.fast = fast
        self.arrays = arrays
        self.feeds = feeds
        self.vmax, self.amax, self.jmax = vmax, amax, jmax
        self.path_amax, self.path_jmax = path_amax, path_jmax
        self.cycle_s = cycle_s
        self.label = label
        self.init_scale = init_scale
        nseg = section.last - section.first + 1
        self.points = points if points is not None else min(60 + 30 * nseg, 600)
        self._opti: Any = None
        self._vars: dict[str, Any] = {}
        self.grid: JerkGrid = build_jerk_grid(
            section, arrays, feeds, vmax, amax, jmax, base_s, base_v, cycle_s=cycle_s, points=self.points, label=label,
            path_amax=path_amax, path_jmax=path_jmax,
        )
        self.v_init = init_scale * self.grid.v_estimate

    @property
    def intervals(self) -> int:
        return self.grid.intervals

    # -- NLP ------------------------------------------------------------------------------------------
    def _initial_guess(self) -> dict[str, np.ndarray]:
        v = self.v_init
        d = self.grid.delta
        h = 2.0 * d / np.maximum(v[:-1] + v[1:], 1e-9)
        t = np.concatenate(([0.0], np.cumsum(h)))
        a = np.gradient(v, t) if v.shape[0] > 2 else np.zeros_like(v)
        a[0] = a[-1] = 0.0
        j = np.diff(a) / h
        return {"v": v, "a": a, "h": h, "j": j}

    def build(self) -> Any:
        """Build (once) and return the ``casadi.Opti`` instance."""
        if self._opti is not None:
            return self._opti
        import casadi as ca

        n = self.intervals
        opti = ca.Opti()
        guess = self._initial_guess()
        self.vref = max(float(np.max(self.grid.vcap[np.isfinite(self.grid.vcap)])), 1.0)
        self.aref = float(self.amax.min())
        self.jref = float(self.jmax.min())
        if self.path_amax is not None:
            self.aref = min(self.aref, self.path_amax)
        if self.path_jmax is not None:
            self.jref = min(self.jref, self.path_jmax)
        self.href = max(float(guess["h"].sum()) / n, 1e-6)
        # A holds the interior accelerations a_1..a_{N-1}; a_0 = a_N = 0 (rest at both ends)
        # and V the interior speeds v_1..v_{N-1}; v_0 = v_N = 0
        Vi, A, H, Jp = opti.variable(n - 1), opti.variable(n - 1), opti.variable(n), opti.variable(n)
        V = ca.vertcat(0, Vi, 0)
        v = self.vref * V
        a_all = ca.vertcat(0, self.aref * A, 0)
        h = self.href * H
        jj = self.jref * Jp
        v0, v1 = v[:-1], v[1:]
        a0, a1 = a_all[:-1], a_all[1:]
        dm = ca.DM(self.grid.delta)
        opti.subject_to((v0 * h + a0 * h**2 / 2 + jj * h**3 / 6) / dm == 1)
        opti.subject_to((v0 + a0 * h + jj * h**2 / 2 - v1) / self.vref == 0)
        opti.subject_to((a0 + jj * h - a1) / self.aref == 0)
        cap = np.where(np.isfinite(self.grid.vcap), self.grid.vcap, 1e6) / self.vref
        opti.subject_to(opti.bounded(0, Vi, ca.DM(cap[1:-1])))
        # ṡ is quadratic in t on an interval; its middle Bernstein coefficient v_i + a_i h/2 bounds it
        # from above (convex hull), so the speed caps hold inside the interval as well
        rows = RowBatch()
        rows.subject_to((-np.inf, (v0 + a0 * h / 2) / self.vref, self.grid.icap / self.vref))
        rows.subject_to((1e-9, H, np.inf))
        tight = float(self.grid.tighten.min()) if self.intervals else 1.0
        # acceleration rows: the right-end row of an interval is the left-end row of the next one
        # where both lie on one line or arc (same v, a and q′, q″ at the shared node), so it is kept
        # once, with the tighter of the two arc factors; at the section end v = a = 0 (no row)
        shared = self.shared_nodes()
        right = [int(i) for i in np.nonzero(~shared[:-1])[0]]
        lim_left = self.grid.tighten.copy()
        lim_left[1:] = np.where(shared[:-1], np.minimum(self.grid.tighten[1:], self.grid.tighten[:-1]), lim_left[1:])
        ends = [(self.grid.dl, v0, a0, lim_left)]
        if right:
            ends.append((tuple(d[right] for d in self.grid.dr), v1[right], a1[right], self.grid.tighten[right]))
        for k in self.grid.axes_used:
            for (d1, d2, _), vv, aa, lim in ends:
                if not self._axis_row_implied("a", k, tight):
                    acc = (ca.DM(d1[:, k]) * aa + ca.DM(d2[:, k]) * vv**2) / self.amax[k]
                    rows.subject_to((-lim * ACC_MARGIN, acc, lim * ACC_MARGIN))
            lim_j = self.grid.tighten * ACC_MARGIN
            for (d1, d2, d3), vv, aa in ((self.grid.dl, v0, a0), (self.grid.dr, v1, a1)):
                if not self._axis_row_implied("j", k, tight):
                    jerk = ca.DM(d3[:, k]) * vv**3 + 3 * ca.DM(d2[:, k]) * vv * aa + ca.DM(d1[:, k]) * jj
                    rows.subject_to((-lim_j, jerk / self.jmax[k], lim_j))
        if self.path_amax is not None:
            for (d1, d2, _), vv, aa, _ in ends:
                acc_v = [ca.DM(d1[:, k]) * aa + ca.DM(d2[:, k]) * vv**2 for k in self.grid.axes_used]
                self._vector_rows(rows, acc_v, [])
        if self.path_jmax is not None:
            for (d1, d2, d3), vv, aa in ((self.grid.dl, v0, a0), (self.grid.dr, v1, a1)):
                jerk_v = [
                    ca.DM(d3[:, k]) * vv**3 + 3 * ca.DM(d2[:, k]) * vv * aa + ca.DM(d1[:, k]) * jj
                    for k in self.grid.axes_used
                ]
                self._vector_rows(rows, [], jerk_v)
        self._arc_midpoint_rows(rows, ca, v0, a0, h, jj)
        self._poly_midpoint_rows(rows, ca, v0, a0, h, jj)
        rows.flush(opti, ca)
        opti.minimize(ca.sum1(H) / n)
        opti.set_initial(Vi, guess["v"][1:-1] / self.vref)
        opti.set_initial(A, guess["a"][1:-1] / self.aref)
        opti.set_initial(H, guess["h"] / self.href)
        opti.set_initial(Jp, guess["j"] / self.jref)
        opti.solver(
            "ipopt",
            {"expand": False, "print_time": False, "error_on_fail": False},
            {**self.ipopt_options, **(FAST_IPOPT if self.fast else {})},
        )
        self._opti = opti
        self._vars = {"V": Vi, "A": A, "H": H, "J": Jp}
        return opti

    def shared_nodes(self) -> np.ndarray:
        """Per interval i: whether node i+1 joins it to interval i+1 on one line or arc, with the same
        q′ and q″ on both sides (then the acceleration row at that node is one row, not two)."""
        g = self.grid
        n = g.intervals
        out = np.zeros(n, dtype=bool)
        if n > 1:
            same = (g.iseg[1:] == g.iseg[:-1]) & (self.arrays.kind[g.iseg[1:]] != 2)
            for d_left, d_right in ((g.dl[0], g.dr[0]), (g.dl[1], g.dr[1])):
                diff = np.abs(d_left[1:] - d_right[:-1]).max(axis=1)
                same &= diff <= 1e-12 * (1.0 + np.abs(d_left[1:]).max(axis=1))
            out[:-1] = same
        return out

    def _axis_row_implied(self, kind: str, k: int, tighten: float = 1.0) -> bool:
        """Whether the per-axis acceleration (``kind`` "a") or jerk ("j") row of axis ``k`` follows
        from the vector row (|x_k| ≤ |x| ≤ m·limit ≤ m·tighten·axis limit), so it is left out of
        the NLP (the solution is checked against every row afterwards all the same)."""
        path, axis = (self.path_amax, self.amax[k]) if kind == "a" else (self.path_jmax, self.jmax[k])
        return path is not None and path <= axis * tighten

    def _vector_rows(self, opti: Any, acc: list[Any], jerk: list[Any]) -> None:
        """``|a|² ≤ (m·A)²`` and ``|j|² ≤ (m·J)²`` (m = ``ACC_MARGIN``) from the components of a and j.

        Only the vector limits that are given; the squared norms keep the rows smooth.
        """
        if self.path_amax is not None and acc:
            opti.subject_to(opti.bounded(-np.inf, sum(c**2 for c in acc) / self.path_amax**2, ACC_MARGIN**2))
        if self.path_jmax is not None and jerk:
            opti.subject_to(opti.bounded(-np.inf, sum(c**2 for c in jerk) / self.path_jmax**2, ACC_MARGIN**2))

    def _arc_midpoint_rows(self, opti: Any, ca: Any, v0: Any, a0: Any, h: Any, jj: Any) -> None:
        """Acceleration and jerk rows at the time midpoint of every arc interval.

        On an arc the axis projections rotate and ``ṡ²`` bulges inside an interval, so the end
        rows alone can be exceeded in between; the midpoint position ``s_i + v h/2 + a h²/8 + j h³/48``
        enters the closed-form q′, q″, q‴ symbolically.
        """
        ar = self.arrays
        idx = np.nonzero(ar.kind[self.grid.iseg] == 1)[0]
        if idx.shape[0] == 0:
            return
        seg = self.grid.iseg[idx]
        r, a0c, da, dw = ar.arc[seg, 2], ar.arc[seg, 3], ar.arc[seg, 4], ar.arc[seg, 6]
        lo = self.grid.s[idx] - ar.start[seg]
        rows = [int(i) for i in idx]
        v, a, hh, j = v0[rows], a0[rows], h[rows], jj[rows]
        sdd = a + j * hh / 2
        sd = v + a * hh / 2 + j * hh**2 / 8
        sig = v * hh / 2 + a * hh**2 / 8 + j * hh**3 / 48
        th = ca.DM(a0c + da * lo) + ca.DM(da) * sig
        c, sn = ca.cos(th), ca.sin(th)
        R, D = ca.DM(r), ca.DM(da)
        uvw1 = (-R * D * sn, R * D * c, ca.DM(dw))
        uvw2 = (-R * D**2 * c, -R * D**2 * sn, ca.DM.zeros(idx.shape[0]))
        uvw3 = (R * D**3 * sn, -R * D**3 * c, ca.DM.zeros(idx.shape[0]))
        perm = ar.perm[seg]
        if self.path_amax is not None or self.path_jmax is not None:
            # norms do not depend on the axis order: the plane components (u, v, w) serve
            self._vector_rows(
                opti,
                [uvw1[c] * sdd + uvw2[c] * sd**2 for c in range(3)],
                [uvw3[c] * sd**3 + 3 * uvw2[c] * sd * sdd + uvw1[c] * j for c in range(3)],
            )
        for k in self.grid.axes_used:
            for comp in range(3):
                sel = [int(x) for x in np.nonzero(perm[:, comp] == k)[0]]
                if not sel:
                    continue
                if not self._axis_row_implied("a", k):
                    acc = (uvw1[comp] * sdd + uvw2[comp] * sd**2) / self.amax[k]
                    opti.subject_to(opti.bounded(-ACC_MARGIN, acc[sel], ACC_MARGIN))
                if not self._axis_row_implied("j", k):
                    jerk = (uvw3[comp] * sd**3 + 3 * uvw2[comp] * sd * sdd + uvw1[comp] * j) / self.jmax[k]
                    opti.subject_to(opti.bounded(-ACC_MARGIN, jerk[sel], ACC_MARGIN))

    def _poly_midpoint_rows(self, opti: Any, ca: Any, v0: Any, a0: Any, h: Any, jj: Any) -> None:
        """Rows at a quarter, half and three quarters of the time of every Poly interval.

        Every interval lies on one Hermite piece (the sample joints are nodes), a polynomial of
        degree ≤ 5 in arc length, so q′, q″, q‴ at the symbolic position ``s_i + σ(τ)`` are its
        exact Taylor expansion from the interval start (q⁽⁴⁾ there, q⁽⁵⁾ constant). On quintic
        pieces q‴ is quadratic in s: a row that took it linear between the end values
        underestimated it by up to 10 % where it peaks inside an interval (jerk measure 1.05 on
        a run spline). Poly transitions are sharp (curvature up to 1/ε), so the direction turns
        noticeably within one interval and the bilinear term 3q″·ṡ·s̈ can peak between the nodes."""
        ar = self.arrays
        idx = np.nonzero(ar.kind[self.grid.iseg] == 2)[0]
        if idx.shape[0] == 0:
            return
        rows = [int(i) for i in idx]
        v, a, hh, j = v0[rows], a0[rows], h[rows], jj[rows]
        d1, d2, d3 = (x[idx] for x in self.grid.dl)
        d4, d5 = np.zeros((idx.shape[0], 3)), np.zeros((idx.shape[0], 3))
        lo = self.grid.s[idx] - ar.start[self.grid.iseg[idx]] + 1e-6 * self.grid.delta[idx]
        for r, (i, x) in enumerate(zip(idx, lo, strict=True)):
            seg = ar.evals[int(self.grid.iseg[i])].segment
            q4, q5 = seg.geometry.higher(float(x))  # type: ignore[union-attr]
            d4[r], d5[r] = seg.plane.to_xyz(q4), seg.plane.to_xyz(q5)
        for frac in POLY_ROW_FRACTIONS:
            tau = frac * hh
            sdd = a + j * tau
            sd = v + a * tau + j * tau**2 / 2
            sig = v * tau + a * tau**2 / 2 + j * tau**3 / 6
            acc_v, jerk_v = [], []
            for k in self.grid.axes_used:
                q4, q5 = ca.DM(d4[:, k]), ca.DM(d5[:, k])
                q3 = ca.DM(d3[:, k]) + q4 * sig + q5 * sig**2 / 2
                q2 = ca.DM(d2[:, k]) + ca.DM(d3[:, k]) * sig + q4 * sig**2 / 2 + q5 * sig**3 / 6
                q1 = (
                    ca.DM(d1[:, k])
                    + ca.DM(d2[:, k]) * sig
                    + ca.DM(d3[:, k]) * sig**2 / 2
                    + q4 * sig**3 / 6
                    + q5 * sig**4 / 24
                )
                acc = (q1 * sdd + q2 * sd**2) / self.amax[k]
                jerk = (q3 * sd**3 + 3 * q2 * sd * sdd + q1 * j) / self.jmax[k]
                if not self._axis_row_implied("a", k):
                    opti.subject_to(opti.bounded(-ACC_MARGIN, acc, ACC_MARGIN))
                if not self._axis_row_implied("j", k):
                    opti.subject_to(opti.bounded(-ACC_MARGIN, jerk, ACC_MARGIN))
                if self.path_amax is not None or self.path_jmax is not None:
                    acc_v.append(q1 * sdd + q2 * sd**2)
                    jerk_v.append(q3 * sd**3 + 3 * q2 * sd * sdd + q1 * j)
            self._vector_rows(opti, acc_v, jerk_v)

    @property
    def opti(self) -> Any:
        return self.build()

    @property
    def variables(self) -> dict[str, Any]:
        """Scaled decision variables: V = v/vref and A = a/aref at interior nodes, H = h/href, J = j/jref."""
        self.build()
        return dict(self._vars)

    def solve(self) -> Solution[SectionProfile]:
        """Solve with IPOPT (silent). Returns a :class:`~trcopt.solution.Solution`."""
        opti = self.build()
        t0 = time.perf_counter()
        try:
            sol = opti.solve()
            val = sol.value
            stats = sol.stats()
        except RuntimeError as exc:  # Opti raises on a failed solve; keep the last iterate
            val = opti.debug.value
            try:
                stats = opti.stats()
            except RuntimeError:
                stats = {"return_status": str(exc).strip().splitlines()[-1], "iter_count": -1}
        wall = time.perf_counter() - t0
        V, A, H, Jp = (np.atleast_1d(np.asarray(val(self._vars[k]), dtype=float)).ravel() for k in ("V", "A", "H", "J"))
        prof = SectionProfile(
            self.grid.s.copy(),
            np.concatenate(([0.0], np.maximum(V * self.vref, 0.0), [0.0])),
            np.concatenate(([0.0], A * self.aref, [0.0])),
            H * self.href,
            Jp * self.jref,
            self.grid.iseg.copy(),
        )
        viol = self.violations(prof)
        status_text = str(stats.get("return_status", ""))
        converged = status_text in ("Solve_Succeeded", "Solved_To_Acceptable_Level")
        ok = (
            converged
            and viol["dynamics_mm"] < 1e-6
            and max(viol["velocity"], viol["acceleration"], viol["jerk"]) < 1e-4
        )
        status = (
            SolveStatus.OPTIMAL
            if ok
            else (SolveStatus.INFEASIBLE if "Infeasible" in status_text else SolveStatus.FAILED)
        )
        return Solution(status, prof.duration, int(stats.get("iter_count", -1)), wall, prof, viol, status_text)

    def violations(self, p: SectionProfile) -> dict[str, float]:
        """Largest violation per constraint group (relative to the limit; dynamics in mm)."""
        v0, v1, a0, a1, h, j = p.v[:-1], p.v[1:], p.a[:-1], p.a[1:], p.h, p.j
        ds = v0 * h + a0 * h**2 / 2 + j * h**3 / 6 - self.grid.delta
        dv = v0 + a0 * h + j * h**2 / 2 - v1
        dyn = max(float(np.abs(ds).max()), float(np.abs(dv).max()) * float(h.max()))
        cap = np.where(np.isfinite(self.grid.vcap), self.grid.vcap, np.inf)
        vel = float(np.max(np.maximum(p.v - cap, 0.0) / np.maximum(cap, 1.0)))
        acc = jer = 0.0
        for (d1, d2, d3), vv, aa in ((self.grid.dl, v0, a0), (self.grid.dr, v1, a1)):
            avec = d1 * aa[:, None] + d2 * (vv * vv)[:, None]
            jvec = d3 * (vv**3)[:, None] + 3 * d2 * (vv * aa)[:, None] + d1 * j[:, None]
            A = np.abs(avec) / (self.amax[None, :] * self.grid.tighten[:, None] * ACC_MARGIN)
            Jx = np.abs(jvec) / (self.jmax[None, :] * self.grid.tighten[:, None] * ACC_MARGIN)
            acc = max(acc, float(A.max()) - 1.0)
            jer = max(jer, float(Jx.max()) - 1.0)
            if self.path_amax is not None:
                acc = max(acc, float(np.linalg.norm(avec, axis=1).max()) / (self.path_amax * ACC_MARGIN) - 1.0)
            if self.path_jmax is not None:
                jer = max(jer, float(np.linalg.norm(jvec, axis=1).max()) / (self.path_jmax * ACC_MARGIN) - 1.0)
        return {
            "dynamics_mm": dyn,
            "velocity": vel,
            "acceleration": max(acc, 0.0),
            "jerk": max(jer, 0.0),
            "negative_time": float(max(-h.min(), 0.0)),
        }


def section_label(segments: Sequence[Any], section: Section) -> str:
    """``blocks N10–N40`` for messages."""
    a = segments[section.first].span.block_label()
    b = segments[section.last].span.block_label()
    return f"block {a}" if a == b else f"blocks {a}–{b}"
