"""Acceleration bounds of the FIR jerk-limited feed: the machine limits it uses and the ``U``/``L`` tables.

See :mod:`trcopt.timing.jerk_fir_bounds` for where the tables go (per interval end, on speed levels)
and :mod:`trcopt.timing.jerk_fir` for the method.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FirLimits", "rates", "tables", "bound_tables", "steady_caps", "window_min"]


@dataclass(frozen=True)
class FirLimits:
    """Machine limits as the FIR engine uses them (per axis X, Y, Z; vector limits or None)."""

    feeds: np.ndarray  # path-speed cap per segment of the whole path, mm/s
    vmax: np.ndarray
    amax: np.ndarray
    jmax: np.ndarray
    path_amax: float | None
    path_jmax: float | None
    cycle_s: float


def rates(c: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Largest ``u ≥ 0`` with ``c·u ≤ r`` on every row (last axis); ``-1`` where ``u = 0`` already fails."""
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(c > 1e-12, r / np.where(c > 1e-12, c, 1.0), np.where(r >= 0, np.inf, -1.0))
    out = q.min(axis=-1)
    return np.where(out < 0, -1.0, out)


def tables(
    d: tuple[np.ndarray, np.ndarray, np.ndarray],
    tight: np.ndarray,
    lim: FirLimits,
    levels: np.ndarray,
    T: np.ndarray,
    margin: float,
) -> tuple[np.ndarray, np.ndarray]:
    """``U`` and ``L`` (rows × levels) at one end of every interval.

    While a ramp of constant unfiltered acceleration ``u`` enters or leaves the filter window, the
    filtered path acceleration moves between 0 and ``u`` and the path jerk is ``±u/T``. Rows, per axis,
    for ``s̈`` at both ends of its range and both signs of ``s⃛``: ``|q′_k s̈ + q″_k ṡ²| ≤ amax_k`` and
    ``|q‴_k ṡ³ + 3q″_k ṡ s̈| + |q′_k| u/T ≤ jmax_k``; the vector limits by ``|a|`` exactly and ``|j|`` by the
    triangle inequality.
    """
    d1, d2, d3 = (x[:, None, :] for x in d)  # (n, 1, 3)
    v = levels[None, :, None]  # (1, K, 1)
    x = v * v
    am = (lim.amax[None, :] * tight[:, None] * margin)[:, None, :]
    jm = (lim.jmax[None, :] * tight[:, None] * margin)[:, None, :]
    f1 = d1 / T[:, None, None]
    e3 = d3 * v**3
    e2 = 3.0 * d2 * v
    shape = np.broadcast_shapes(d1.shape, v.shape)
    ones = np.ones(shape)

    # rows c·u ≤ r per axis: acceleration ±(q′u + q″x) ≤ am; jerk with both signs of the path jerk
    # (|e3 + e2 s̈| + |q′| u/T ≤ jm for s̈ = 0 and s̈ = ±u): the signed rows of one end of a ramp
    # alone let its middle, where the acceleration changes with the speed, exceed the jerk
    af = np.abs(f1)
    rows_c = [d1 * ones, -d1 * ones, af * ones, e2 + af, -e2 + af]
    rows_r = [am - d2 * x, am + d2 * x, jm - np.abs(e3), jm - e3, jm + e3]
    u_in = rates(np.concatenate(rows_c, axis=-1), np.concatenate(rows_r, axis=-1))
    rows_c = [-d1 * ones, d1 * ones, af * ones, -e2 + af, e2 + af]
    l_in = rates(np.concatenate(rows_c, axis=-1), np.concatenate(rows_r, axis=-1))
    out = [u_in, l_in]
    n1 = np.linalg.norm(d[0], axis=1)[:, None]
    n2 = np.linalg.norm(d[1], axis=1)[:, None]
    n3 = np.linalg.norm(d[2], axis=1)[:, None]
    xx = levels[None, :] ** 2
    if lim.path_amax is not None:
        A = lim.path_amax * margin
        p = np.maximum(n1 * n1, 1e-300)
        q = (d[0] * d[1]).sum(axis=1)[:, None] * xx
        r = (n2 * xx) ** 2 - A * A
        disc = q * q - p * r
        ok = (disc >= 0) & (r <= 0)
        root = np.sqrt(np.maximum(disc, 0.0))
        out = [
            np.where(ok, np.minimum(out[0], (-q + root) / p), -1.0),
            np.where(ok, np.minimum(out[1], (q + root) / p), -1.0),
        ]
    if lim.path_jmax is not None:
        J = lim.path_jmax * margin
        vv = levels[None, :]
        c = 3.0 * n2 * vv + n1 / T[:, None]
        r = J - n3 * vv**3
        with np.errstate(divide="ignore", invalid="ignore"):
            b = np.where(r >= 0, np.where(c > 1e-12, r / np.where(c > 1e-12, c, 1.0), np.inf), -1.0)
        out = [np.minimum(t, b) for t in out]
    return out[0], out[1]


def bound_tables(
    d: tuple[np.ndarray, np.ndarray, np.ndarray],
    tight: np.ndarray,
    lim: FirLimits,
    levels: np.ndarray,
    T: np.ndarray,
    margin: float,
    line: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`tables`, with the rows of lines (no curvature: one value for every speed) in closed
    form: ``min_k (amax_k, jmax_k T)/|q′_k|`` and the vector limits."""
    k = levels.shape[0]
    out = [np.empty((line.shape[0], k)) for _ in range(2)]
    curved = ~line
    if np.any(curved):
        sub = tuple(x[curved] for x in d)
        for o, t in zip(out, tables(sub, tight[curved], lim, levels, T[curved], margin), strict=True):
            o[curved] = t
    if np.any(line):
        a1 = np.abs(d[0][line])
        with np.errstate(divide="ignore"):
            am = (lim.amax[None, :] * margin / a1).min(axis=1)
            jm = (lim.jmax[None, :] * margin * T[line][:, None] / a1).min(axis=1)
        c = np.minimum(am, jm)
        if lim.path_amax is not None:
            c = np.minimum(c, lim.path_amax * margin)
        if lim.path_jmax is not None:
            c = np.minimum(c, lim.path_jmax * margin * T[line])
        for o in out:
            o[line] = c[:, None]
    return out[0], out[1]


def steady_caps(d: tuple, tight: np.ndarray, lim: FirLimits, margin: float) -> np.ndarray:
    """Steady-state speed cap (s̈ = s⃛ = 0) at one end of every interval."""
    with np.errstate(divide="ignore"):
        va = np.sqrt((lim.amax[None, :] * tight[:, None] * margin / np.abs(d[1])).min(axis=1))
        vj = np.cbrt((lim.jmax[None, :] * tight[:, None] * margin / np.abs(d[2])).min(axis=1))
        vcap = np.minimum(va, vj)
        if lim.path_amax is not None:
            vcap = np.minimum(vcap, np.sqrt(lim.path_amax * margin / np.linalg.norm(d[1], axis=1)))
        if lim.path_jmax is not None:
            vcap = np.minimum(vcap, np.cbrt(lim.path_jmax * margin / np.linalg.norm(d[2], axis=1)))
    return vcap


def window_min(table: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Row ``i`` of the result: the minimum of rows ``lo[i]..hi[i] - 1`` of ``table`` (sparse table of
    minima over 2^p consecutive rows)."""
    n = table.shape[0]
    sparse = [table]
    p = 1
    while (1 << p) <= n:
        prev = sparse[-1]
        w = 1 << (p - 1)
        sparse.append(np.minimum(prev[:-w], prev[w:]))
        p += 1
    width = np.maximum(hi - lo, 1)
    pw = np.floor(np.log2(width)).astype(np.int64)
    out = np.empty_like(table)
    for q in np.unique(pw):
        m = pw == q
        tab = sparse[int(q)]
        out[m] = np.minimum(tab[lo[m]], tab[hi[m] - (1 << int(q))])
    return out
