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

A vector limit on |a| (``machine.path.amax_mm_s2``) adds two convex, non-linear rows per interval;
:func:`solve_lockstep_vector` runs the same two passes with them (see the comment above
:func:`ellipse_terms`).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "interval_rows",
    "mvc_bound",
    "pass_coefficients",
    "solve_lockstep",
    "ellipse_terms",
    "x_bounds",
    "best_x",
    "peak_y",
    "forward_rows",
    "solve_lockstep_vector",
]


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
        # rows in pairs of opposite sign (the ± rows of interval_rows): of each pair at most one row
        # bounds y above and one below, so only those rows are paired (the pairs left out are ∞)
        bc = beta[idx]
        paired = bc.shape[1] == 12 and bool(
            np.array_equal(bc[:, 3:6], -bc[:, 0:3]) and np.array_equal(bc[:, 9:12], -bc[:, 6:9])
        )
        for chunk in np.array_split(idx, max(1, idx.shape[0] // 4096)):
            if chunk.shape[0] == 0:
                continue
            if paired:
                b = beta[chunk][:, _PAIRS]
                rows = chunk[:, None]
                u_col = np.where(b > tiny, _PAIRS, _PAIRS + 3)
                l_col = np.where(b < -tiny, _PAIRS, _PAIRS + 3)
                num = cu[rows, u_col][:, None, :] - cl[rows, l_col][:, :, None]
                den = ml[rows, l_col][:, :, None] - mu[rows, u_col][:, None, :]
            else:
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


_PAIRS = np.array([0, 1, 2, 6, 7, 8])  # the first row of every ± pair of interval_rows (the other: +3)


def solve_lockstep(
    q: np.ndarray, wb: np.ndarray, zb: np.ndarray, wf: np.ndarray, zf: np.ndarray, xmax: np.ndarray,
    *, backward: bool = False, start: np.ndarray | None = None,
) -> tuple[np.ndarray, ...]:
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
        With ``backward`` the (G, N) flags per interval instead, and the backward pass (G, N+1)
        as a third result. ``start`` (G,) replaces the forward pass's first value (a window
        continuing a solved profile).
    """
    G, N = q.shape
    # the passes step along the intervals (the interval first: copies for a few long pieces, views
    # for many short ones; the ufuncs writing into buffers) — the operations of
    #   B_i = min(cap_i, min_l(B_{i+1}·wb_l + zb_l)),  F_{i+1} = max(min(B_{i+1}, min_u(F_i·wu + zu)), 0)
    def steps(a: np.ndarray) -> np.ndarray:
        view = a.transpose(1, 0, 2)
        return np.ascontiguousarray(view) if G <= 8 else view

    mul, add, least, lower = np.multiply, np.add, np.minimum.reduce, np.minimum
    tmp = np.empty((G, wb.shape[2]))
    cap = np.minimum(xmax[:, :N], q).T
    wbt, zbt = steps(wb), steps(zb)
    Bt = np.empty((N + 1, G))
    Bt[N] = xmax[:, N]
    for i in range(N - 1, -1, -1):
        mul(Bt[i + 1, :, None], wbt[i], out=tmp)
        add(tmp, zbt[i], out=tmp)
        lower(cap[i], least(tmp, axis=1), out=Bt[i])
    np.maximum(Bt, 0.0, out=Bt)
    B = np.ascontiguousarray(Bt.T)
    Ft = np.empty((N + 1, G))
    Ft[0] = B[:, 0] if start is None else start  # a given start: known to be reachable
    wut, zut = steps(wf[0]), steps(zf[0])
    y = np.empty(G)
    for i in range(N):
        mul(Ft[i, :, None], wut[i], out=tmp)
        add(tmp, zut[i], out=tmp)
        lower(Bt[i + 1], least(tmp, axis=1), out=y)
        np.maximum(y, 0.0, out=Ft[i + 1])
    F = np.ascontiguousarray(Ft.T)
    # lower rows, checked for all intervals at once
    with np.errstate(invalid="ignore"):
        lb = (F[:, :-1, None] * wf[1] + zf[1]).max(axis=2)
    viol = lb - F[:, 1:] > 1e-9 * (1.0 + F[:, 1:])
    return (F, viol, B) if backward else (F, viol.any(axis=1))


# -- vector (path) acceleration limit ----------------------------------------------------------------
#
# With a limit A on the norm of the acceleration vector, every interval adds two convex rows that are
# not linear in (x, y): with u = (y − x)/(2Δ) and the curvature κ = |p''| at the interval's ends
# (p' ⟂ p'', |p'| = 1 on lines and arcs/helices, so |a|² = u² + κ²ṡ⁴),
#
#     left:  (y − x)² + c_l·x² ≤ D      and      right:  (y − x)² + c_r·y² ≤ D,
#
# with c = 4Δ²κ² and D = 4Δ²A². On a line or an arc κ is constant inside the interval and x is
# linear in s, so |a|² is convex in s and the two end rows bound it everywhere in between. For a
# fixed y both rows and the per-axis rows give an interval of x (closed form), so the largest
# feasible x, ``g(y)``, is concave in y; the backward step is ``B_i = g(min(K, y*))`` with ``y*``
# the argmax of g (golden-section search, once per interval), the forward step intersects the
# y-intervals for x = F_i in closed form.

GOLDEN_STEPS = 72  # golden-section steps: the bracket shrinks to 0.618^72 ≈ 1e-15 of the speed cap
_GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)
_TINY = 1e-12


def ellipse_terms(
    kappa_l: np.ndarray, kappa_r: np.ndarray, delta: np.ndarray, amax: float | np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(c_l, c_r, D)`` of the vector-acceleration rows of intervals of length ``delta`` (mm).

    ``kappa_l``, ``kappa_r`` are the curvatures |p''| (1/mm) inside the interval at its ends and
    ``amax`` the limit on |a| (mm/s²).
    """
    d2 = 4.0 * delta * delta
    return d2 * kappa_l * kappa_l, d2 * kappa_r * kappa_r, d2 * amax * amax


def x_bounds(alpha: np.ndarray, beta: np.ndarray, gamma: np.ndarray) -> tuple[np.ndarray, ...]:
    """Rows ``α x + β y ≤ γ`` (shape (..., 12)) as bounds on x for a given y.

    Returns ``(cu, mu, cl, ml, ylo, yhi)``: ``x ≤ cu + mu·y`` and ``x ≥ cl + ml·y`` per row
    (``±inf``/0 where a row gives no such bound; columns that bound no interval are dropped), and
    the bounds ``ylo ≤ y ≤ yhi`` of the rows without x.
    """
    pos = alpha > _TINY
    neg = alpha < -_TINY
    flat = ~(pos | neg)
    with np.errstate(divide="ignore", invalid="ignore"):
        a_safe = np.where(pos | neg, alpha, 1.0)
        b_safe = np.where(np.abs(beta) > _TINY, beta, 1.0)
        cu = np.where(pos, gamma / a_safe, np.inf)
        mu = np.where(pos, -beta / a_safe, 0.0)
        cl = np.where(neg, gamma / a_safe, -np.inf)
        ml = np.where(neg, -beta / a_safe, 0.0)
        yhi = np.where(flat & (beta > _TINY), gamma / b_safe, np.inf).min(axis=-1)
        ylo = np.where(flat & (beta < -_TINY), gamma / b_safe, -np.inf).max(axis=-1)
    rows = tuple(range(alpha.ndim - 1))
    up = pos.any(axis=rows) if rows else pos
    lo = neg.any(axis=rows) if rows else neg
    return cu[..., up], mu[..., up], cl[..., lo], ml[..., lo], ylo, yhi


def best_x(
    bounds: tuple[np.ndarray, ...], cl: np.ndarray, cr: np.ndarray, D: np.ndarray, cap: np.ndarray, y: np.ndarray
) -> np.ndarray:
    """``g(y)``: the largest x with ``(x, y)`` feasible in an interval, ``-inf`` where there is none.

    ``bounds`` are the per-axis rows from :func:`x_bounds`; the vector-acceleration rows
    ``cl``, ``cr``, ``D`` (shape (...)) and ``0 ≤ x ≤ cap`` complete the interval.
    """
    cu, mu, cxl, mxl, ylo, yhi = bounds
    yy = y[..., None]
    ub = np.min(cu + mu * yy, axis=-1, initial=np.inf)
    lb = np.max(cxl + mxl * yy, axis=-1, initial=0.0)
    q = 1.0 + cl
    disc_l = D * q - cl * y * y
    rl = np.sqrt(np.maximum(disc_l, 0.0))
    disc_r = D - cr * y * y
    rr = np.sqrt(np.maximum(disc_r, 0.0))
    ub = np.minimum(np.minimum(ub, (y + rl) / q), np.minimum(y + rr, cap))
    lb = np.maximum(np.maximum(lb, (y - rl) / q), y - rr)
    scale = 1.0 + np.abs(y)
    ok = (
        (y >= ylo - _TINY * scale)
        & (y <= yhi + _TINY * scale)
        & (disc_l >= -_TINY * D * q)
        & (disc_r >= -_TINY * D)
        & (ub >= lb - _TINY * (1.0 + np.abs(ub)))
    )
    return np.where(ok, ub, -np.inf)


def peak_y(
    bounds: tuple[np.ndarray, ...], cl: np.ndarray, cr: np.ndarray, D: np.ndarray, cap: np.ndarray, ymax: np.ndarray
) -> np.ndarray:
    """Smallest ``y ∈ [0, ymax]`` where :func:`best_x` is largest (golden-section search).

    ``g`` is concave where finite and finite at ``y = 0``, so the search brackets its maximum;
    the ends ``0`` and ``ymax`` are candidates as well (``g`` monotone).
    """

    def g(y: np.ndarray) -> np.ndarray:
        return best_x(bounds, cl, cr, D, cap, y)

    a = np.zeros_like(ymax)
    b = ymax.copy()
    c = b - _GOLDEN * (b - a)
    d = a + _GOLDEN * (b - a)
    fc, fd = g(c), g(d)
    for _ in range(GOLDEN_STEPS):
        left = fc >= fd  # the maximum lies in [a, d]
        a = np.where(left, a, c)
        b = np.where(left, d, b)
        keep_y = np.where(left, c, d)
        keep_f = np.where(left, fc, fd)
        new = np.where(left, b - _GOLDEN * (b - a), a + _GOLDEN * (b - a))
        fn = g(new)
        c, fc = np.where(left, new, keep_y), np.where(left, fn, keep_f)
        d, fd = np.where(left, keep_y, new), np.where(left, keep_f, fn)
    cand = np.stack((np.zeros_like(ymax), np.minimum(c, d), np.maximum(c, d), ymax), axis=-1)
    vals = np.stack((g(cand[..., 0]), np.where(c <= d, fc, fd), np.where(c <= d, fd, fc), g(ymax)), axis=-1)
    pick = vals.argmax(axis=-1)  # first maximum: the smallest y among equal values
    return np.take_along_axis(cand, pick[..., None], axis=-1)[..., 0]


def forward_rows(
    alpha: np.ndarray, beta: np.ndarray, gamma: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Rows ``α x + β y ≤ γ`` as bounds on y for a given x: ``y ≤ x·wu + zu`` and ``y ≥ x·wl + zl``."""
    up = beta > _TINY
    lo = beta < -_TINY
    with np.errstate(divide="ignore", invalid="ignore"):
        wu = np.where(up, -alpha / np.where(up, beta, 1.0), 0.0)
        zu = np.where(up, gamma / np.where(up, beta, 1.0), np.inf)
        wl = np.where(lo, -alpha / np.where(lo, beta, 1.0), 0.0)
        zl = np.where(lo, gamma / np.where(lo, beta, 1.0), -np.inf)
    return wu, zu, wl, zl


def solve_lockstep_vector(
    alpha: np.ndarray, beta: np.ndarray, gamma: np.ndarray, cl: np.ndarray, cr: np.ndarray, D: np.ndarray,
    curved: np.ndarray, xmax: np.ndarray, *, backward: bool = False, start: np.ndarray | None = None,
) -> tuple[np.ndarray, ...]:
    """Backward and forward passes with the vector-acceleration rows, G sections in lock-step.

    Parameters
    ----------
    alpha, beta, gamma:
        Per-axis rows (G, N, 12); padding intervals carry ``α = β = 0, γ = 1``.
    cl, cr, D:
        Vector-acceleration rows (G, N) from :func:`ellipse_terms`; padding ``0, 0, 1``.
    curved:
        (G, N) True on arc intervals; there the argmax ``y*`` of :func:`best_x` is searched
        (:func:`peak_y`), on lines ``g`` is non-decreasing and ``y*`` is the next node's cap.
    xmax:
        (G, N+1) upper bounds on x (0 at section ends and on padding).

    Returns
    -------
    x:
        (G, N+1) squared path speeds, mm²/s².
    bad:
        (G,) True where a forward step violates a lower bound (the section then goes to toppra).
        With ``backward`` the (G, N) flags per interval instead, and the backward pass (G, N+1)
        as a third result. ``start`` (G,) replaces the forward pass's first value (a window
        continuing a solved profile).
    """
    G, N = cl.shape
    bounds = x_bounds(alpha, beta, gamma)
    ystar = xmax[:, 1:].copy()
    if np.any(curved):
        sub = tuple(b[curved] for b in bounds)
        ystar[curved] = peak_y(sub, cl[curved], cr[curved], D[curved], xmax[:, :-1][curved], xmax[:, 1:][curved])
    # backward: between 0 and y* every y is feasible (convex set), so only the upper bounds of x count
    cu, mu = bounds[0], bounds[1]
    q = 1.0 + cl
    Dq = D * q
    B = np.empty((G, N + 1))
    B[:, N] = xmax[:, N]
    for i in range(N - 1, -1, -1):
        y = np.minimum(B[:, i + 1], ystar[:, i])
        yy = y * y
        x = np.minimum(
            np.minimum((y + np.sqrt(np.maximum(Dq[:, i] - cl[:, i] * yy, 0.0))) / q[:, i], xmax[:, i]),
            y + np.sqrt(np.maximum(D[:, i] - cr[:, i] * yy, 0.0)),
        )
        if cu.shape[-1]:
            x = np.minimum(x, (cu[:, i] + mu[:, i] * y[:, None]).min(axis=1))
        B[:, i] = np.maximum(x, 0.0)
    wu, zu, wl, zl = forward_rows(alpha, beta, gamma)
    qr = 1.0 + cr
    Dqr = D * qr
    F = np.empty((G, N + 1))
    F[:, 0] = B[:, 0] if start is None else start  # a given start: known to be reachable
    for i in range(N):
        x = F[:, i]
        xx = x * x
        y = np.minimum(
            np.minimum(B[:, i + 1], (x[:, None] * wu[:, i] + zu[:, i]).min(axis=1)),
            np.minimum(
                x + np.sqrt(np.maximum(D[:, i] - cl[:, i] * xx, 0.0)),
                (x + np.sqrt(np.maximum(Dqr[:, i] - cr[:, i] * xx, 0.0))) / qr[:, i],
            ),
        )
        F[:, i + 1] = np.maximum(y, 0.0)
    x, y = F[:, :-1], F[:, 1:]
    with np.errstate(invalid="ignore"):
        lb = (x[:, :, None] * wl + zl).max(axis=2)
        disc_l = D - cl * x * x
        disc_r = Dqr - cr * x * x
        lb = np.maximum(lb, x - np.sqrt(np.maximum(disc_l, 0.0)))
        lb = np.maximum(lb, (x - np.sqrt(np.maximum(disc_r, 0.0))) / qr)
    viol = (lb - y > 1e-9 * (1.0 + y)) | (disc_l < -1e-9 * D) | (disc_r < -1e-9 * Dqr)
    return (F, viol, B) if backward else (F, viol.any(axis=1))
