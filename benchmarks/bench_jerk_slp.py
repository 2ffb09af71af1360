"""A sequential-LP jerk-limited speed planner (research prototype) against trcopt's IPOPT engine.

Run:  python benchmarks/bench_jerk_slp.py [--families B1,B2,…]

Not used by trcopt: this script holds an alternative to :mod:`trcopt.timing.jerk` measured on the
benchmark paths B1–B9 (``timing_cases.py``, isotropic machine), with the IPOPT engine timed in the
same run as the baseline (cycle time and wall time). It prints the cycle time of the LP profile as
its own model computes it; the profile is not certified (no trajectory object, no ``check_limits``).

Method, per section, on the IPOPT engine's own node grid (``build_jerk_grid``): variables
``b_i = ṡ²`` and ``a_i = s̈`` at the nodes, ``a`` linear in arc length inside an interval (so
``b_{i+1} − b_i = (a_i + a_{i+1})·Δ_i``); the first and the last interval are exact pure-jerk
pieces from and to rest (``b_1 = 1.5·Δ_0·a_1``, ``a_1 ≤ J^{2/3}(6Δ_0)^{1/3}``); per-axis and vector
acceleration rows at both ends of every interval; per-axis jerk rows
``|q‴b + 3q″a + q′a′| ≤ J/ṡ̄`` and a 32-gon for the vector jerk, where ``ṡ̄`` is the speed of the
previous iterate (damped: it comes down at most by 0.6 per step, never below the iterate), with a
trust region ``b ≥ ½·b_prev``; objective: maximise Σ w_i·b_i with ``w_i = Δ_i / b_prev^{3/2}`` (the
linearised time); HiGHS (``scipy.optimize.linprog``). When the iterates settle, a last LP with
``ṡ̄² = (1.002)²·b`` as the bound on ``b`` as well is conservative in the model's own terms.

Measured 2026-11-25 (B1–B9, isotropic): 0.05–7 % slower than IPOPT (1.4 % on short lines, 3–7 %
where curvature jumps are passed) and no faster — not a replacement for the IPOPT engine.
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

MARGIN = 0.002
DAMP = 0.6
FLOOR = 0.05
TRUST = 0.5
SCHEDULE = [0.5, 0.3, 0.2, 0.1, 0.05, 0.03, 0.02, 0.01, 0.005, 0.002]
GL_X, GL_W = np.polynomial.legendre.leggauss(8)


def interval_times(b0, b1, a0, a1, delta):
    """∫ ds/ṡ over intervals where b = ṡ² is quadratic in s with b' = 2a, a linear."""
    k = (a1 - a0) / delta
    x = 0.5 * (GL_X[None, :] + 1.0) * delta[:, None]
    b = b0[:, None] + 2 * a0[:, None] * x + k[:, None] * x * x
    return 0.5 * delta * (GL_W[None, :] / np.sqrt(np.maximum(b, 1e-300))).sum(axis=1)


def profile_time(b, a, delta):
    n = b.shape[0] - 1
    t = np.empty(n)
    t[0] = 3.0 * delta[0] / math.sqrt(max(b[1], 1e-300))
    t[-1] = 3.0 * delta[-1] / math.sqrt(max(b[-2], 1e-300))
    if n > 2:
        t[1:-1] = interval_times(b[1:-2], b[2:-1], a[1:-2], a[2:-1], delta[1:-1])
    return t


def solve_section(grid, vmax, amax, jmax, b_upper, path_amax=None, path_jmax=None, iters=14, verbose=False):
    N = grid.intervals
    n = N + 1
    d = grid.delta
    q1l, q2l, q3l = grid.dl
    q1r, q2r, q3r = grid.dr
    tight = grid.tighten
    cap2 = np.where(np.isfinite(grid.vcap), grid.vcap, 1e9) ** 2
    bbar = np.minimum(np.maximum(b_upper, 0.0), cap2)
    bbar[0] = bbar[-1] = 0.0
    # -- equalities
    rows, cols, vals = [], [], []
    r = 0
    # start: b1 = 1.5 d0 a1
    rows += [r, r]
    cols += [1, n + 1]
    vals += [1.0, -1.5 * d[0]]
    r += 1
    for i in range(1, N - 1):
        rows += [r, r, r, r]
        cols += [i + 1, i, n + i, n + i + 1]
        vals += [1.0, -1.0, -d[i], -d[i]]
        r += 1
    rows += [r, r]
    cols += [N - 1, n + N - 1]
    vals += [1.0, 1.5 * d[N - 1]]
    r += 1
    A_eq = sp.csr_matrix((vals, (rows, cols)), shape=(r, 2 * n))
    b_eq = np.zeros(r)
    # -- acceleration rows (static): ±(q' a + q'' b) ≤ A·tight at both ends of every interval
    def acc_rows():
        R, C, V, rhs = [], [], [], []
        r = 0
        for side, (q1, q2) in (("l", (q1l, q2l)), ("r", (q1r, q2r))):
            node = np.arange(N) + (0 if side == "l" else 1)
            for k in range(3):
                lim = amax[k] * tight
                for sg in (1.0, -1.0):
                    idx = np.arange(N)
                    R += [r + idx, r + idx]
                    C += [n + node, node]
                    V += [sg * q1[:, k], sg * q2[:, k]]
                    rhs.append(lim)
                    r += N
        if path_amax is not None:
            M = 32
            psi = (np.arange(M) + 0.5) * np.pi / M
            g = path_amax * math.cos(0.5 * np.pi / M)
            for side, q2 in (("l", q2l), ("r", q2r)):
                node = np.arange(N) + (0 if side == "l" else 1)
                kap = np.linalg.norm(q2, axis=1)
                for p in psi:
                    idx = np.arange(N)
                    R += [r + idx, r + idx]
                    C += [n + node, node]
                    V += [np.full(N, math.cos(p)), math.sin(p) * kap]
                    rhs.append(np.full(N, g))
                    r += N
        return R, C, V, rhs, r

    aR, aC, aV, arhs, ar_n = acc_rows()
    # b at the middle of every inner interval, b_i + Δ(3a_i + a_{i+1})/4, between 0 and the cap
    inn = np.arange(1, N - 1)
    mm = inn.shape[0]
    icap2 = np.where(np.isfinite(grid.icap), grid.icap, 1e9)[inn] ** 2
    for sg, rhs in ((-1.0, np.zeros(mm)), (1.0, icap2)):
        idx = np.arange(mm)
        aR += [ar_n + idx] * 3
        aC += [inn, n + inn, n + inn + 1]
        aV += [np.full(mm, sg), sg * 0.75 * d[inn], sg * 0.25 * d[inn]]
        arhs.append(rhs)
        ar_n += mm
    A_acc = sp.csr_matrix((np.concatenate(aV), (np.concatenate(aR), np.concatenate(aC))), shape=(ar_n, 2 * n))
    b_acc = np.concatenate(arhs)
    # -- jerk rows: coefficients (static), right-hand sides depend on sdot_bar
    inner = np.arange(1, N - 1)
    m = inner.shape[0]
    jR, jC, jV, jscale = [], [], [], []  # jscale: row's J·tight (divided by sdot_bar per iteration)
    jint = []
    jnode = []
    r = 0
    for side, (q1, q2, q3) in (("l", (q1l, q2l, q3l)), ("r", (q1r, q2r, q3r))):
        node = inner + (0 if side == "l" else 1)
        for k in range(3):
            for sg in (1.0, -1.0):
                c1, c2, c3 = q1[inner, k], q2[inner, k], q3[inner, k]
                idx = np.arange(m)
                # X = q3 b + 3 q2 a + q1 (a_{i+1} - a_i)/d
                jR += [r + idx] * 4
                jC += [node, n + node, n + inner + 1, n + inner]
                jV += [sg * c3, sg * 3 * c2, sg * c1 / d[inner], -sg * c1 / d[inner]]
                jscale.append(jmax[k] * tight[inner])
                jint.append(inner)
                jnode.append(node)
                r += m
    if path_jmax is not None:
        M = 32
        for side, (q1, q2, q3) in (("l", (q1l, q2l, q3l)), ("r", (q1r, q2r, q3r))):
            node = inner + (0 if side == "l" else 1)
            t1, t2, t3 = q1[inner], q2[inner], q3[inner]
            kap = np.linalg.norm(t2, axis=1)
            nvec = np.where(kap[:, None] > 1e-12, t2 / np.maximum(kap, 1e-300)[:, None], 0.0)
            u_b = (t1 * t3).sum(axis=1)  # u = a' + (q'·q''') b
            w_b = (nvec * t3).sum(axis=1)  # w = (N·q''') b + 3 κ a
            straight = (kap < 1e-12) & (np.abs(u_b) < 1e-12) & (np.abs(w_b) < 1e-12)
            for p in (2 * np.pi * np.arange(M) / M):
                cp, sp_ = math.cos(p), math.sin(p)
                lim = np.where(straight, 1.0, math.cos(np.pi / M))
                idx = np.arange(m)
                jR += [r + idx] * 4
                jC += [node, n + node, n + inner + 1, n + inner]
                jV += [cp * u_b + sp_ * w_b, sp_ * 3 * kap, cp / d[inner], -cp / d[inner]]
                jscale.append(path_jmax * lim)
                jint.append(inner)
                jnode.append(node)
                r += m
    A_j = sp.csr_matrix((np.concatenate(jV), (np.concatenate(jR), np.concatenate(jC))), shape=(r, 2 * n))
    jscale = np.concatenate(jscale)
    jint = np.concatenate(jint)
    jnode = np.concatenate(jnode)
    # start/end pieces: a_1 ≤ Jeff^(2/3) (6 d0)^(1/3), −a_{N−1} ≤ Jeff^(2/3)(6 d_{N−1})^(1/3)
    def jeff(i, q1, q2, q3, vb):
        js = []
        for k in range(3):
            if abs(q1[i, k]) < 1e-12:
                continue
            rest = jmax[k] - 3 * abs(q2[i, k]) * vb * float(amax.max()) - abs(q3[i, k]) * vb**3
            js.append(max(rest, 1e-3 * jmax[k]) / abs(q1[i, k]))
        if path_jmax is not None:
            js.append(path_jmax)
        return min(js)

    best = None
    t0 = time.perf_counter()
    b_top = bbar.copy()
    ub, sbar2 = b_top.copy(), b_top.copy()
    prev, final, lb = None, False, None
    for it in range(iters):
        sbar_node = np.sqrt(np.maximum(sbar2, 1e-12))
        b_j = jscale / sbar_node[jnode]
        A_ub = sp.vstack([A_acc, A_j]).tocsr()
        b_ub = np.concatenate([b_acc, b_j])
        lo = np.zeros(n) if lb is None else np.minimum(lb, ub)
        bounds = [(float(low), float(x)) for low, x in zip(lo, ub, strict=True)] + [(None, None)] * n
        bounds[n] = (0.0, 0.0)
        bounds[2 * n - 1] = (0.0, 0.0)
        a1max = jeff(0, q1r, q2r, q3r, math.sqrt(sbar2[1])) ** (2 / 3) * (6 * d[0]) ** (1 / 3)
        aemax = jeff(N - 1, q1l, q2l, q3l, math.sqrt(sbar2[N - 1])) ** (2 / 3) * (6 * d[N - 1]) ** (1 / 3)
        bounds[n + 1] = (None, a1max)
        bounds[n + N - 1] = (-aemax, None)
        bhat = np.maximum(b_top if prev is None else prev, 1e-6 * cap2.max())
        w = np.zeros(n)
        w[:-1] += 0.5 * d
        w[1:] += 0.5 * d
        c = np.concatenate([-w / bhat**1.5, np.zeros(n)])
        c /= np.abs(c).max()
        res = linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds, method="highs")
        if res.status != 0 and lb is not None:
            for q in range(n):
                bounds[q] = (0.0, bounds[q][1])
            res = linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds, method="highs")
        if res.status != 0:
            if verbose:
                print("LP failed", res.message)
            return None
        b = res.x[:n].copy()
        a = res.x[n:].copy()
        T = profile_time(b, a, d).sum()
        if verbose:
            print(it, "final" if final else "free", T, time.perf_counter() - t0)
        if final:
            return T, b, a
        converged = prev is not None and np.abs(np.sqrt(b) - np.sqrt(prev)).max() < 1e-5 * math.sqrt(cap2.max())
        if converged or it >= iters - 2:
            ub = np.minimum(b_top, (1 + MARGIN) ** 2 * b)
            ub[0] = ub[-1] = 0.0
            sbar2 = ub.copy()
            lb = b / (1 + MARGIN) ** 2 * (1 - 1e-9)  # feasible (scaled iterate): no new dips
            final = True
        else:
            # the speeds of the jerk rows come down towards the iterate, never below it
            sbar2 = np.maximum(np.maximum(b, FLOOR * b_top), DAMP * sbar2)
            lb = TRUST * b
        prev = b
    return best


def main(argv: list[str]) -> int:
    import argparse
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from timing_cases import ISO, families

    from trcopt.timing import time_parameterize
    from trcopt.timing.jerk import jerk_limited
    from trcopt.timing.jerk_grid import build_jerk_grid
    from trcopt.timing.jerk_report import jerk_limits
    from trcopt.timing.path import PathArrays
    from trcopt.timing.sections import axis_limits, path_speed_caps, segment_feeds, split_sections

    parser = argparse.ArgumentParser(description="sequential-LP jerk-limited speed planning vs the IPOPT engine")
    parser.add_argument("--families", default="B1,B2,B3,B4,B5,B6,B7,B8,B9")
    args = parser.parse_args(argv)
    wanted = set(args.families.split(","))
    m = ISO
    print("| family | case | IPOPT cycle s (baseline) | IPOPT wall s | LP cycle s | LP wall s | LP / IPOPT |")
    print("|---|---|---|---|---|---|---|")
    for fam, case, path, _cf in families():
        if fam not in wanted or case.endswith("1000") or case.endswith("10000"):
            continue
        base = time_parameterize(path, m)
        t0 = time.perf_counter()
        ipopt = jerk_limited(path, m, base=base)
        t_ipopt = time.perf_counter() - t0
        arrays = PathArrays(path)
        feeds = path_speed_caps(segment_feeds(path, m), m)
        vmax, amax = axis_limits(m)
        jmax = jerk_limits(m)
        t0 = time.perf_counter()
        total = 0.0
        for sec in split_sections(path, arrays, 1e-6):
            nseg = sec.last - sec.first + 1
            grid = build_jerk_grid(sec, arrays, feeds, vmax, amax, jmax, base.s, base.sd, cycle_s=1e-3,
                                   points=min(60 + 30 * nseg, 600))
            res = solve_section(grid, vmax, amax, jmax, np.interp(grid.s, base.s, base.x))
            total += res[0] if res is not None else float("nan")
        t_lp = time.perf_counter() - t0
        print(f"| {fam} | {case} | {ipopt.duration:.6f} | {t_ipopt:.2f} | {total:.6f} | {t_lp:.2f} | "
              f"{total / ipopt.duration:.4f} |", flush=True)
    return 0


if __name__ == "__main__":
    import sys

    sys.exit(main(sys.argv[1:]))
