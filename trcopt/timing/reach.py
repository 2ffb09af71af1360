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

__all__ = ["interval_rows", "mvc_bound", "solve_lockstep"]


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


def solve_lockstep(
    alpha: np.ndarray, beta: np.ndarray, gamma: np.ndarray, xmax: np.ndarray, curved: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Backward and forward greedy passes for G sections padded to the same interval count.

    Parameters
    ----------
    alpha, beta, gamma:
        (G, N, 12) interval rows; padding intervals carry zero rows and γ > 0.
    xmax:
        (G, N+1) upper bounds on x (0 at section ends and on padding).
    curved:
        (G, N) True for intervals with curvature (the backward step is then an exact 2-D LP by
        Fourier–Motzkin elimination; on lines the rows are lattice rows and y = B_{i+1} is optimal).

    Returns
    -------
    x:
        (G, N+1) squared path speeds, mm²/s².
    bad:
        (G,) True where a forward step found no feasible value (the section needs toppra).
    """
    G, N, _ = alpha.shape
    if curved is None:
        curved = np.ones((G, N), dtype=bool)
    B = np.empty((G, N + 1))
    B[:, N] = xmax[:, N]
    tiny = 1e-12
    for i in range(N - 1, -1, -1):
        a = alpha[:, i]
        b = beta[:, i]
        K = B[:, i + 1]
        rhs = gamma[:, i] - b * K[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            ubk = np.where(a > tiny, rhs / a, np.inf)
        ub = ubk.min(axis=1)
        # curved intervals need not be lattice rows (a smaller y may allow a larger x, or an
        # upper bound on y may depend on x): solve the 2-variable LP exactly there
        cur = curved[:, i]
        if np.any(cur):
            ub[cur] = _max_x_over_y(a[cur], b[cur], gamma[cur, i], K[cur])
        B[:, i] = np.maximum(np.minimum(xmax[:, i], ub), 0.0)
    F = np.empty((G, N + 1))
    F[:, 0] = np.minimum(B[:, 0], xmax[:, 0])
    bad = np.zeros(G, dtype=bool)
    for i in range(N):
        b = beta[:, i]
        rhs = gamma[:, i] - alpha[:, i] * F[:, i, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            q = rhs / b
            ub = np.where(b > tiny, q, np.inf).min(axis=1)
            lb = np.where(b < -tiny, q, -np.inf).max(axis=1)
        zero_ok = np.where(np.abs(b) <= tiny, rhs >= -1e-9 * np.abs(gamma[:, i]), True).all(axis=1)
        y = np.maximum(np.minimum(B[:, i + 1], ub), 0.0)
        bad |= (lb > y + 1e-9 * (1.0 + np.abs(y))) | ~zero_ok
        F[:, i + 1] = y
    return F, bad


def _max_x_over_y(a: np.ndarray, b: np.ndarray, g: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Exact ``max x`` over ``{(x, y): a·x + b·y ≤ g (rows), 0 ≤ y ≤ K}`` (Fourier–Motzkin on y).

    Rows with b > 0 bound y from above by ``U(x)``, rows with b < 0 from below by ``L(x)``;
    ``x`` is feasible iff every ``L ≤ U``, each pair giving one linear bound on x.
    """
    tiny = 1e-12
    n = a.shape[0]
    up = b > tiny
    lo = b < -tiny
    with np.errstate(divide="ignore", invalid="ignore"):
        cu = np.where(up, g / b, np.inf)
        mu = np.where(up, -a / b, 0.0)
        cl = np.where(lo, g / b, -np.inf)
        ml = np.where(lo, -a / b, 0.0)
        cu = np.concatenate((cu, K[:, None]), axis=1)
        mu = np.concatenate((mu, np.zeros((n, 1))), axis=1)
        cl = np.concatenate((cl, np.zeros((n, 1))), axis=1)
        ml = np.concatenate((ml, np.zeros((n, 1))), axis=1)
        num = cu[:, None, :] - cl[:, :, None]
        den = ml[:, :, None] - mu[:, None, :]
        bound = np.where(den > tiny, num / np.where(den > tiny, den, 1.0), np.inf)
        flat = (~up) & (~lo) & (a > tiny)
        direct = np.where(flat, g / np.where(flat, a, 1.0), np.inf).min(axis=1)
    return np.minimum(direct, bound.reshape(n, -1).min(axis=1))
