"""Limit check of one FIR section profile, with the positions of the violations.

Evaluates the per-axis velocity, acceleration and jerk (``v = q′ṡ``, ``a = q′s̈ + q″ṡ²``,
``j = q‴ṡ³ + 3q″ṡs̈ + q′s⃛``) of a profile of constant-path-jerk intervals in closed form at both
ends of every interval, where ``ṡ`` peaks inside it, and on curves at least every ``CHECK_DT``
inside it; the feed, the vector limits and the knot speed rule at curvature jumps. The ratios are
the ones :meth:`trcopt.timing.jerk.JerkTrajectory.check_limits` reports; a section profile is
accepted when every ratio is at most ``1 + FIR_TOL``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from trcopt.timing.jerk_fir_bounds import FirLimits
from trcopt.timing.path import PathArrays, path_derivatives

__all__ = ["FirCheck", "check_profile", "CHECK_DT", "FIR_TOL"]

CHECK_DT = 2.5e-4  # s, largest time step between check points inside an interval on a curve
FIR_TOL = 1e-6  # ratios accepted up to 1 + FIR_TOL


@dataclass(frozen=True)
class FirCheck:
    """Worst ratio per limit group and where the limits are exceeded."""

    ratios: dict[str, float]
    bad_s: np.ndarray  # positions (global mm) of the violating check points
    bad_ratio: np.ndarray  # their worst ratio
    bad_kind: np.ndarray  # 0 speed, 1 acceleration, 2 jerk (smooth), 3 knot
    bad_tangential: np.ndarray  # the path acceleration/jerk term is the larger part of the excess

    @property
    def ok(self) -> bool:
        return self.bad_s.shape[0] == 0

    @property
    def worst(self) -> float:
        return max(self.ratios.values()) if self.ratios else 0.0


def check_profile(
    s0: np.ndarray,
    v0: np.ndarray,
    a0: np.ndarray,
    j: np.ndarray,
    h: np.ndarray,
    iseg: np.ndarray,
    ar: PathArrays,
    lim: FirLimits,
    knot_s: np.ndarray,
    knot_dq2: np.ndarray,
) -> FirCheck:
    """Check the intervals ``(s0, v0, a0, j, h)`` on segments ``iseg`` (see the module docstring)."""
    n = h.shape[0]
    curved = ar.kind[iseg] != 0
    sub = np.where(curved, np.clip(np.ceil(h / CHECK_DT), 2, 64), 1).astype(np.int64)
    # τ = 0, h (and interior points on curves), and the peak of ṡ inside
    reps = sub + 1
    idx = np.repeat(np.arange(n), reps)
    start = np.repeat(np.cumsum(reps) - reps, reps)
    frac = (np.arange(idx.shape[0]) - start) / np.repeat(sub, reps)
    tau = frac * h[idx]
    with np.errstate(divide="ignore", invalid="ignore"):
        tp = np.where(j != 0, -a0 / j, -1.0)
    peak = np.nonzero((tp > 0) & (tp < h))[0]
    idx = np.concatenate((idx, peak))
    tau = np.concatenate((tau, tp[peak]))
    i = idx
    s = s0[i] + v0[i] * tau + a0[i] * tau**2 / 2 + j[i] * tau**3 / 6
    sd = np.maximum(v0[i] + a0[i] * tau + j[i] * tau**2 / 2, 0.0)
    sdd = a0[i] + j[i] * tau
    sddd = j[i]
    seg = iseg[i]
    pad = 1e-9
    local = np.clip(s - ar.start[seg], 0.0, ar.length[seg])
    local = np.clip(local, pad * ar.length[seg], (1 - pad) * ar.length[seg])
    d1, d2, d3 = path_derivatives(ar, seg, local)
    vel = d1 * sd[:, None]
    acc = d1 * sdd[:, None] + d2 * (sd * sd)[:, None]
    jer = d3 * (sd**3)[:, None] + 3 * d2 * (sd * sdd)[:, None] + d1 * sddd[:, None]
    rv = np.maximum((np.abs(vel) / lim.vmax).max(axis=1), sd / lim.feeds[seg])
    ra = (np.abs(acc) / lim.amax).max(axis=1)
    rj = (np.abs(jer) / lim.jmax).max(axis=1)
    if lim.path_amax is not None:
        ra = np.maximum(ra, np.linalg.norm(acc, axis=1) / lim.path_amax)
    if lim.path_jmax is not None:
        rj = np.maximum(rj, np.linalg.norm(jer, axis=1) / lim.path_jmax)
    ratios = {"v": float(rv.max()), "a": float(ra.max()), "j": float(rj.max())}
    # share of the path acceleration / path jerk term on the worst axis
    ka = np.argmax(np.abs(acc) / lim.amax, axis=1)
    kj = np.argmax(np.abs(jer) / lim.jmax, axis=1)
    rows = np.arange(s.shape[0])
    tan_a = np.abs(d1[rows, ka] * sdd) >= 0.5 * np.abs(acc[rows, ka])
    tan_j = np.abs(d1[rows, kj] * sddd) >= 0.5 * np.abs(jer[rows, kj])
    lim1 = 1.0 + FIR_TOL
    parts_s, parts_r, parts_k, parts_t = [], [], [], []
    for k, (r, tan) in enumerate(((rv, np.zeros_like(tan_a)), (ra, tan_a), (rj, tan_j))):
        m = r > lim1
        parts_s.append(s[m])
        parts_r.append(r[m])
        parts_k.append(np.full(int(m.sum()), k))
        parts_t.append(tan[m])
    if knot_s.shape[0]:
        s_end = s0 + v0 * h + a0 * h**2 / 2 + j * h**3 / 6
        kv = np.interp(knot_s, np.append(s0, s_end[-1]), np.append(v0, 0.0))
        rk = (np.abs(knot_dq2) * (kv**2)[:, None] / (lim.cycle_s * lim.jmax)).max(axis=1)
        if lim.path_jmax is not None:
            rk = np.maximum(rk, np.linalg.norm(knot_dq2, axis=1) * kv**2 / (lim.cycle_s * lim.path_jmax))
        ratios["knot"] = float(rk.max())
        m = rk > lim1
        parts_s.append(knot_s[m])
        parts_r.append(rk[m])
        parts_k.append(np.full(int(m.sum()), 3))
        parts_t.append(np.zeros(int(m.sum()), dtype=bool))
    return FirCheck(
        ratios, np.concatenate(parts_s), np.concatenate(parts_r), np.concatenate(parts_k), np.concatenate(parts_t)
    )
