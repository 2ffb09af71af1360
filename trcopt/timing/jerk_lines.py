"""Closed-form jerk-limited profile of a section that is one straight line (spec timing.md §4.2).

A section made of collinear lines with one speed cap (one line, or lines in the same direction
with the same feed) has scalar limits along the line: ``v = min(F, min_k vmax_k/|t_k|)`` (F the
path-speed cap of :func:`trcopt.timing.sections.path_speed_caps`), ``a = min(min_k amax_k/|t_k|, A)``
and ``J = min(min_k jmax_k/|t_k|, J_path)`` for the unit direction ``t`` and the optional vector
limits A, J_path of ``machine.path``. On a line every axis moves as ``t_k·s(t)``, so these scalar
limits are exactly the per-axis and vector limits, and the rest-to-rest time-optimal motion is the
symmetric double-S (:func:`trcopt.timing.doubles.double_s_phases`): up to seven phases of constant
path jerk ``+J, 0, −J, 0, −J, 0, +J``. Each phase is one interval of the jerk-limited trajectory
model (``t0, s0, h, v0, a0, j``); a phase that crosses a joint between two of the lines is split
there, so that every interval lies on one segment.

The NLP of :class:`~trcopt.timing.jerk_problem.JerkProblem` solves the same problem on a grid with
a and J at 0.999 of the limit, so its profile is never faster than this one.
"""

from __future__ import annotations

import time

import numpy as np

from trcopt.solution import Solution, SolveStatus
from trcopt.timing.doubles import double_s_phases
from trcopt.timing.jerk_problem import SectionProfile
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import Section

__all__ = ["line_section_limits", "line_section_profile", "SOLVER"]

SOLVER = "double-s"  # Solution.solver and the plan JSON's section engine for closed-form sections
DIRECTION_TOL = 1e-9  # largest difference of unit directions (and relative caps) treated as one line


def line_section_limits(
    sec: Section,
    ar: PathArrays,
    feeds: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    jmax: np.ndarray,
    path_amax: float | None = None,
    path_jmax: float | None = None,
) -> tuple[float, float, float] | None:
    """Scalar limits (v mm/s, a mm/s², J mm/s³) of a section of collinear lines with one speed cap,
    or None when the section has another shape (an arc or Poly, a change of direction or of the
    feed)."""
    segs = np.arange(sec.first, sec.last + 1)
    if np.any(ar.kind[segs] != 0):
        return None
    dirs = ar.eval(segs, np.zeros(segs.shape[0]), 1)
    t = dirs[0] / np.linalg.norm(dirs[0])
    if np.abs(dirs / np.linalg.norm(dirs, axis=1)[:, None] - t[None, :]).max() > DIRECTION_TOL:
        return None
    f = feeds[segs]
    if np.abs(f - f[0]).max() > DIRECTION_TOL * f[0]:
        return None
    at = np.abs(t)
    with np.errstate(divide="ignore"):
        v = min(float(f.min()), float((vmax / at).min()))
        a = float((amax / at).min())
        j = float((jmax / at).min())
    if path_amax is not None:
        a = min(a, float(path_amax))
    if path_jmax is not None:
        j = min(j, float(path_jmax))
    return v, a, j


def _integrate(h: np.ndarray, jj: np.ndarray, s0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Node positions, speeds and accelerations of constant-jerk phases from rest at ``s0``."""
    n = h.shape[0]
    s, v, a = np.empty(n + 1), np.empty(n + 1), np.empty(n + 1)
    s[0], v[0], a[0] = s0, 0.0, 0.0
    for i in range(n):
        hi, ji = float(h[i]), float(jj[i])
        s[i + 1] = s[i] + v[i] * hi + a[i] * hi * hi / 2 + ji * hi**3 / 6
        v[i + 1] = v[i] + a[i] * hi + ji * hi * hi / 2
        a[i + 1] = a[i] + ji * hi
    return s, v, a


def _split_at(s0: float, v0: float, a0: float, j: float, h: float, target: float) -> float:
    """Time in ``(0, h)`` at which ``s0 + v0 τ + a0 τ²/2 + j τ³/6`` reaches ``target`` (bisection;
    ``s`` increases inside a phase of the profile)."""
    lo, hi = 0.0, h
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if s0 + v0 * mid + a0 * mid * mid / 2 + j * mid**3 / 6 < target:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * h:
            break
    return 0.5 * (lo + hi)


def line_section_profile(sec: Section, ar: PathArrays, limits: tuple[float, float, float]) -> Solution[SectionProfile]:
    """The double-S profile of section ``sec`` under the scalar ``limits`` (v, a, J) of
    :func:`line_section_limits`, split at the joints of its lines; a :class:`Solution` with
    ``solver = "double-s"``, zero iterations and the section time as cost."""
    t_start = time.perf_counter()
    h, jj = double_s_phases(sec.length, *limits)
    joints = ar.start[sec.first + 1 : sec.last + 1]
    if joints.shape[0]:
        s, v, a = _integrate(h, jj, sec.s_start)
        hs, js = [], []
        for i in range(h.shape[0]):
            inside = joints[(joints > s[i]) & (joints < s[i + 1])]
            tau_prev = 0.0
            for x in inside:
                tau = _split_at(float(s[i]), float(v[i]), float(a[i]), float(jj[i]), float(h[i]), float(x))
                if tau > tau_prev:
                    hs.append(tau - tau_prev)
                    js.append(jj[i])
                    tau_prev = tau
            hs.append(float(h[i]) - tau_prev)
            js.append(jj[i])
        h, jj = np.array(hs), np.array(js)
    s, v, a = _integrate(h, jj, sec.s_start)
    # the end is at rest at the section end (rounding of the integration is below 1e-12 relative)
    s[-1] = sec.s_start + sec.length
    v[0] = v[-1] = a[0] = a[-1] = 0.0
    s = np.minimum(np.maximum.accumulate(s), s[-1])
    v = np.maximum(v, 0.0)
    mid = 0.5 * (s[:-1] + s[1:])
    iseg = np.clip(np.searchsorted(ar.start, mid, side="right") - 1, sec.first, sec.last).astype(np.int64)
    prof = SectionProfile(s, v, a, h, jj, iseg)
    wall = time.perf_counter() - t_start
    return Solution(SolveStatus.OPTIMAL, prof.duration, 0, wall, prof, {}, "closed form", SOLVER)
