"""Own TOPP-RA reachability solver for lines and arcs/helices, vectorised across sections.

The discrete problem is exactly the one toppra solves with its interpolation scheme (and the
reference LP of spec timing.md §4.7): on grid ``s_0..s_N`` with ``x_i = ṡ_i²`` and
``u_i = (x_{i+1} − x_i)/(2Δ_i)``, every interval must satisfy the per-axis acceleration rows

    −A_j ≤ p'_j(s_i⁺)·u_i + p''_j(s_i⁺)·x_i ≤ A_j   and   −A_j ≤ p'_j(s_{i+1}⁻)·u_i + p''_j(s_{i+1}⁻)·x_{i+1} ≤ A_j

with the derivatives taken one-sidedly inside the interval (so knots need no extra grid point),
and ``0 ≤ x_i ≤ x̄_i`` where ``x̄`` is the velocity box, the feed and the acceleration
maximum-velocity curve, with ``x_0 = x_N = 0``.

Each interval couples only ``(x_i, x_{i+1})``: its rows are written ``α·x_i + β·y ≤ γ``
(``y = x_{i+1}``). The backward pass computes the largest ``x_i`` compatible with some
``y ≤ B_{i+1}``, the forward pass the largest ``y ≤ B_{i+1}`` compatible with ``x_i = F_i``: the
same passes as TOPP-RA; on lines each step is a 1-D bound computation, on arcs an exact 2-D LP
by Fourier–Motzkin elimination of y,
done for all sections of similar length at once (lock-step numpy). The forward pass checks every
lower bound; a step that is infeasible is reported per section so the caller can hand the section
to toppra (that never happened in the benchmark suite).
"""

from __future__ import annotations

import numpy as np

__all__ = ["interval_rows", "mvc_bound", "pass_coefficients", "solve_lockstep"]


def interval_rows(
    d1l: np.ndarray, d2l: np.ndarray, d1r: np.ndarray, d2r: np.ndarray, delta: np.ndarray, amax: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows ``α x + β y ≤ γ`` of intervals (shape (n, 12)) from one-sided derivatives (n, 3).

    ``amax`` is (n, 3): the per-axis acceleration limit of each interval (already tightened).
    """
    c = (0.5 / delta)[:, None]
    al = d2l - d1l * c
    bl = d1l * c
    ar = -d1r * c
    br = d1r * c + d2r
    alpha = np.concatenate((al, -al, ar, -ar), axis=1)
    beta = np.concatenate((bl, -bl, br, -br), axis=1)
    gamma = np.concatenate((amax, amax, amax, amax), axis=1)
    return alpha, beta, gamma


def mvc_bound(d1: np.ndarray, d2: np.ndarray, amax: np.ndarray) -> np.ndarray:
    """Acceleration maximum-velocity curve: largest x with some u such that |d1 u + d2 x| ≤ A.

    Shapes: d1, d2, amax (n, 3). Returns (n,), ``inf`` where unbounded (straight line).
    """
    n = d1.shape[0]
    out = np.full(n, np.inf)
    ad1 = np.abs(d1)
    small = ad1 < 1e-9
    with np.errstate(divide="ignore", invalid="ignore"):
        direct = np.where(small & (np.abs(d2) > 0), amax / np.abs(d2), np.inf)
        out = np.minimum(out, direct.min(axis=1))
        rho = np.where(small, 0.0, d2 / np.where(small, 1.0, d1))
        w = np.where(small, 0.0, amax / np.where(small, 1.0, ad1))
        for j in range(3):
            for k in range(3):
                if j == k:
                    continue
                diff = rho[:, k] - rho[:, j]
                ok = (~small[:, j]) & (~small[:, k]) & (diff > 1e-15)
                bound = np.where(ok, (w[:, j] + w[:, k]) / np.where(ok, diff, 1.0), np.inf)
                out = np.minimum(out, bound)
    return out


def pass_coefficients(
    alpha: np.ndarray, beta: np.ndarray, gamma: np.ndarray, curved: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Precompute the two passes for intervals with rows ``α x + β y ≤ γ`` (shape (n, 12)).

    Fourier–Motzkin elimination of y: rows with β > 0 bound y above by ``U(x)``, rows with β < 0
    below by ``L(x)``, and ``0 ≤ y ≤ K``. ``max x`` is the min over pairs (L, U) of one linear
    bound; only the pairs with the row ``y ≤ K`` depend on K, so every other pair is evaluated
    here once (``q``), vectorised over all intervals, and the backward step reduces to
    ``B_i = min(q_i, min_l (K·wb_l + zb_l))``. The forward step is
    ``F_{i+1} = min(B_{i+1}, min_u (F_i·wf_u + zf_u))``. On lines (no curvature) the (L, U) pairs
    are parallel and ``q = ∞``.
    """
    tiny = 1e-12
    n = alpha.shape[0]
    up = beta > tiny
    lo = beta < -tiny
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # masked by np.where
        cu = np.where(up, gamma / beta, np.inf)
        mu = np.where(up, -alpha / beta, 0.0)
        cl = np.where(lo, gamma / beta, -np.inf)
        ml = np.where(lo, -alpha / beta, 0.0)
        # pair (L row, y ≤ K): cl + ml x ≤ K  →  x ≤ (K − cl)/ml  for ml > 0
        use = lo & (ml > tiny)
        wb = np.where(use, 1.0 / np.where(use, ml, 1.0), 0.0)
        zb = np.where(use, -cl * wb, np.inf)
        # pair (y ≥ 0, U row): 0 ≤ cu + mu x  →  x ≤ −cu/mu  for mu < 0
        use0 = up & (mu < -tiny)
        q = np.where(use0, -cu / np.where(use0, mu, 1.0), np.inf).min(axis=1)
        flat = (~up) & (~lo) & (alpha > tiny)
        q = np.minimum(q, np.where(flat, gamma / np.where(flat, alpha, 1.0), np.inf).min(axis=1))
        idx = np.nonzero(curved)[0]
        for chunk in np.array_split(idx, max(1, idx.shape[0] // 4096)):
            if chunk.shape[0] == 0:
                continue
            num = cu[chunk, None, :] - cl[chunk, :, None]
            den = ml[chunk, :, None] - mu[chunk, None, :]
            ok = den > tiny
            pair = np.where(ok, num / np.where(ok, den, 1.0), np.inf)
            q[chunk] = np.minimum(q[chunk], pair.reshape(chunk.shape[0], -1).min(axis=1))
        wf = np.where(up, mu, 0.0)
        zf = np.where(up, cu, np.inf)
        wl = np.where(lo, ml, 0.0)
        zl = np.where(lo, cl, -np.inf)
    del n
    return q, wb, zb, np.stack((wf, wl)), np.stack((zf, zl))


def solve_lockstep(
    q: np.ndarray, wb: np.ndarray, zb: np.ndarray, wf: np.ndarray, zf: np.ndarray, xmax: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Backward and forward passes for G sections padded to the same interval count N.

    Parameters
    ----------
    q, wb, zb:
        Backward data from :func:`pass_coefficients`, shapes (G, N), (G, N, 12), (G, N, 12);
        padding intervals carry ``q = ∞, wb = 0, zb = ∞``.
    wf, zf:
        Forward data (2, G, N, 12): upper rows ``y ≤ x·w + z`` and lower rows ``y ≥ x·w + z``.
    xmax:
        (G, N+1) upper bounds on x (0 at section ends and on padding).

    Returns
    -------
    x:
        (G, N+1) squared path speeds, mm²/s².
    bad:
        (G,) True where a forward step violates a lower row (the section then goes to toppra).
    """
    G, N = q.shape
    B = np.empty((G, N + 1))
    B[:, N] = xmax[:, N]
    cap = np.minimum(xmax[:, :N], q)
    for i in range(N - 1, -1, -1):
        K = B[:, i + 1]
        B[:, i] = np.minimum(cap[:, i], (K[:, None] * wb[:, i] + zb[:, i]).min(axis=1))
    np.maximum(B, 0.0, out=B)
    F = np.empty((G, N + 1))
    F[:, 0] = B[:, 0]
    wu, zu = wf[0], zf[0]
    for i in range(N):
        y = (F[:, i, None] * wu[:, i] + zu[:, i]).min(axis=1)
        F[:, i + 1] = np.maximum(np.minimum(B[:, i + 1], y), 0.0)
    # lower rows, checked for all intervals at once
    with np.errstate(invalid="ignore"):
        lb = (F[:, :-1, None] * wf[1] + zf[1]).max(axis=2)
    viol = lb - F[:, 1:] > 1e-9 * (1.0 + F[:, 1:])
    return F, viol.any(axis=1)
