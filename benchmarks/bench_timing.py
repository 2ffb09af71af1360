"""Timing benchmark, spec timing.md §6: B1–B9 × {isotropic, anisotropic} limits.

Run:  python benchmarks/bench_timing.py [--big] [--no-cache]

Planners (all measured in the same run): trcopt (own reachability solver + toppra for Poly),
naive exact stop per segment, grbl-style junction deviation (arcs cut in 2 µm chords; its
infeasibility is reported), toppra as a naive user calls it (default grid, spline output, no
split). References: closed forms §4.2–4.5 where they apply, else the discretised LP of §4.7
(HiGHS; lines as single intervals timed in closed form, arcs with DTHETA_LP grid), cached in
``benchmarks/data/lp_reference.json``.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from timing_cases import ANISO, ISO, families  # noqa: E402

from trcopt.timing import time_parameterize  # noqa: E402
from trcopt.timing.path import PathArrays  # noqa: E402
from trcopt.timing.sections import axis_limits, segment_feeds, split_sections  # noqa: E402

CACHE = Path(__file__).parent / "data" / "lp_reference.json"
DTHETA_LP = 0.002  # rad per LP interval on arcs (~3100 points per turn)


# -- reference LP (§4.7) ------------------------------------------------------------------------
def lp_reference(path, machine):
    from scipy.optimize import linprog
    from scipy.sparse import coo_matrix

    arrays = PathArrays(path)
    feeds = segment_feeds(path, machine)
    vmax, amax = axis_limits(machine)
    total = 0.0
    for sec in split_sections(path, arrays):
        lo, hi, segs = [], [], []
        for k in sec.segment_indices:
            L = arrays.length[k]
            n = 1 if arrays.kind[k] == 0 else max(8, math.ceil(abs(arrays.arc[k, 4]) * L / DTHETA_LP))
            g = np.linspace(0.0, L, n + 1)
            lo.append(g[:-1])
            hi.append(g[1:])
            segs.append(np.full(n, k))
        lo, hi, iseg = np.concatenate(lo), np.concatenate(hi), np.concatenate(segs)
        m = lo.shape[0]
        d1l, d2l = arrays.eval(iseg, lo + 1e-9 * (hi - lo), 1), arrays.eval(iseg, lo + 1e-9 * (hi - lo), 2)
        d1r, d2r = arrays.eval(iseg, hi - 1e-9 * (hi - lo), 1), arrays.eval(iseg, hi - 1e-9 * (hi - lo), 2)
        c = 0.5 / (hi - lo)
        rows, cols, vals, rhs = [], [], [], []
        r = 0
        for j in range(3):
            for (d1, d2, at_right) in ((d1l[:, j], d2l[:, j], False), (d1r[:, j], d2r[:, j], True)):
                ci = np.arange(m)
                ax = d1 * c
                coef_i = -ax + (0 if at_right else d2)
                coef_n = ax + (d2 if at_right else 0)
                for sign in (1.0, -1.0):
                    rr = r + np.arange(m)
                    rows += [rr, rr]
                    cols += [ci, ci + 1]
                    vals += [sign * coef_i, sign * coef_n]
                    rhs.append(np.full(m, amax[j]))
                    r += m
        A = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(r, m + 1)).tocsr()
        with np.errstate(divide="ignore"):
            capl = np.minimum(((vmax / np.abs(d1l)) ** 2).min(axis=1), feeds[iseg] ** 2)
            capr = np.minimum(((vmax / np.abs(d1r)) ** 2).min(axis=1), feeds[iseg] ** 2)
        ub = np.minimum(np.append(capl, np.inf), np.insert(capr, 0, np.inf))
        ub[0] = ub[-1] = 0.0
        res = linprog(
            -np.ones(m + 1), A_ub=A, b_ub=np.concatenate(rhs), bounds=np.c_[np.zeros(m + 1), ub], method="highs"
        )
        x = np.maximum(res.x, 0.0)
        sd = np.sqrt(x)
        for i in range(m):
            L = hi[i] - lo[i]
            if arrays.kind[iseg[i]] == 0:  # line: exact trapezoid with entry/exit speeds (§4.2)
                with np.errstate(divide="ignore"):
                    a = float((amax / np.abs(d1l[i])).min())
                    v = math.sqrt(min(capl[i], 1e300))
                v0, v1 = sd[i], sd[i + 1]
                vp = math.sqrt(min(v * v, (2 * a * L + v0 * v0 + v1 * v1) / 2))
                total += (vp - v0) / a + (vp - v1) / a + (L - (2 * vp * vp - v0 * v0 - v1 * v1) / (2 * a)) / vp
            else:
                total += 2 * L / (sd[i] + sd[i + 1])
    return total


# -- baselines (§6.3) ---------------------------------------------------------------------------
def naive_exact_stop(path, machine):
    vmax, amax = axis_limits(machine)
    feeds = segment_feeds(path, machine)
    arrays = PathArrays(path)
    T = 0.0
    for k, sg in enumerate(path):
        L = arrays.length[k]
        if arrays.kind[k] == 0:
            t = arrays.d[k]
            t = np.abs(np.array(sg.plane.to_xyz(tuple(t))))
            with np.errstate(divide="ignore"):
                v = min(feeds[k], float((vmax / t).min()))
                a = float((amax / t).min())
        else:
            R = 1.0 / (arrays.arc[k, 2] * arrays.arc[k, 4] ** 2)
            v = min(feeds[k], float(vmax.min()), math.sqrt(0.5 * amax.min() * R))
            a = amax.min() - v * v / R
        T += L / v + v / a if L >= v * v / a else 2 * math.sqrt(L / a)
    return T


def grbl_jd(path, machine, delta=0.01, eps=0.002):
    """Junction deviation on chords; returns (T, implied accel ratio at 1 ms servo period)."""
    vmax, amax = axis_limits(machine)
    feeds = segment_feeds(path, machine)
    pts, fs = [np.array(path[0].start_xyz)], []
    for k, sg in enumerate(path):
        g = sg.geometry
        if hasattr(g, "radius"):
            n = max(1, int(0.5 * abs(g.sweep) * g.radius / math.sqrt(eps * (2 * g.radius - eps))))
            for i in range(1, n + 1):
                pts.append(np.array(sg.plane.to_xyz(g.point(g.length * i / n))))
                fs.append(feeds[k])
        else:
            pts.append(np.array(sg.end_xyz))
            fs.append(feeds[k])
    P = np.array(pts)
    d = np.diff(P, axis=0)
    L = np.linalg.norm(d, axis=1)
    u = d / L[:, None]
    with np.errstate(divide="ignore"):
        acc = (amax / np.abs(u)).min(axis=1)
        vn = np.minimum(np.array(fs), (vmax / np.abs(u)).min(axis=1))
    n = L.shape[0]
    e = np.zeros(n + 1)
    for k in range(1, n):
        cos = -float(u[k - 1] @ u[k])
        if cos > 0.999999:
            v2 = 0.0
        elif cos < -0.999999:
            v2 = np.inf
        else:
            b = u[k] - u[k - 1]
            b /= np.linalg.norm(b)
            with np.errstate(divide="ignore"):
                aj = float((amax / np.abs(b)).min())
            s = math.sqrt((1 - cos) / 2)
            v2 = aj * delta * s / (1 - s)
        e[k] = min(v2, vn[k - 1] ** 2, vn[k] ** 2)
    for k in range(n - 1, -1, -1):
        e[k] = min(e[k], e[k + 1] + 2 * acc[k] * L[k])
    for k in range(n):
        e[k + 1] = min(e[k + 1], e[k] + 2 * acc[k] * L[k])
    T = 0.0
    for k in range(n):
        v0, v1, a, v = math.sqrt(e[k]), math.sqrt(e[k + 1]), acc[k], vn[k]
        vp = math.sqrt(min(v * v, (2 * a * L[k] + e[k] + e[k + 1]) / 2))
        T += (vp - v0) / a + (vp - v1) / a + (L[k] - (2 * vp * vp - e[k] - e[k + 1]) / (2 * a)) / vp
    jump = np.sqrt(e[1:-1]) * np.linalg.norm(u[1:] - u[:-1], axis=1)  # velocity jump per servo period
    if n > 1:
        du = u[1:] - u[:-1]
        axis_jump = np.abs(jump[:, None] * np.abs(du) / np.maximum(np.linalg.norm(du, axis=1)[:, None], 1e-300))
        ratio = float((axis_jump / 1e-3 / amax).max())
    else:
        ratio = 0.0
    return T, ratio


def toppra_naive(path, machine):
    """toppra as commonly used: spline through the waypoints, default grid, spline output."""
    import toppra as ta
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    vmax, amax = axis_limits(machine)
    arrays = PathArrays(path)
    pts = [np.array(path[0].start_xyz)]
    for k, _sg in enumerate(path):
        n = 1 if arrays.kind[k] == 0 else max(2, int(abs(arrays.arc[k, 4]) * arrays.length[k] / 0.2))
        for i in range(1, n + 1):
            pts.append(arrays.eval(np.array([k]), np.array([arrays.length[k] * i / n]), 0)[0])
    W = np.array(pts)
    ss = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(W, axis=0), axis=1))))
    spl = ta.SplineInterpolator(ss, W)
    inst = algo.TOPPRA([constraint.JointVelocityConstraint(np.c_[-vmax, vmax]),
                        constraint.JointAccelerationConstraint(np.c_[-amax, amax])], spl, solver_wrapper="seidel")
    traj = inst.compute_trajectory(0, 0)
    if traj is None:
        return float("nan"), False
    ts = np.arange(0.0, traj.duration, 1e-4)
    qd, qdd = traj(ts, 1), traj(ts, 2)
    ok = bool((np.abs(qd) / vmax).max() <= 1.001 and (np.abs(qdd) / amax).max() <= 1.001)
    return float(traj.duration), ok


def main(big: bool = False, use_cache: bool = True) -> None:
    cache = json.loads(CACHE.read_text()) if (use_cache and CACHE.exists()) else {}
    rows = []
    for fam, name, path, ref in families(big):
        for machine in (ISO, ANISO):
            key = f"{fam}|{name}|{machine.name}|{DTHETA_LP}"
            throughput = ref == "throughput"
            if callable(ref):
                t_ref, ref_kind = ref(machine), "closed"
            elif throughput:
                t_ref, ref_kind = float("nan"), "-"
            else:
                if key not in cache:
                    cache[key] = lp_reference(path, machine)
                t_ref, ref_kind = cache[key], "LP"
            walls = []
            for _ in range(5 if throughput else 3):
                t0 = time.perf_counter()
                traj = time_parameterize(path, machine)
                walls.append(time.perf_counter() - t0)
            wall = float(np.median(walls))
            rep = traj.check_limits(1e-4)
            from trcopt.timing.checks import max_jerk
            jerk = float(max_jerk(traj, 1e-3).max())
            limits = machine.name[:5]
            rows.append(
                (fam, name, limits, "trcopt", traj.duration, t_ref, ref_kind, rep.ok, jerk, wall, len(path) / wall)
            )
            if throughput:
                continue
            t0 = time.perf_counter()
            tn = naive_exact_stop(path, machine)
            w = time.perf_counter() - t0
            rows.append((fam, name, limits, "naive stop", tn, t_ref, ref_kind, True, float("nan"), w, len(path) / w))
            t0 = time.perf_counter()
            tg, ratio = grbl_jd(path, machine)
            w = time.perf_counter() - t0
            grbl = f"grbl JD (a x{ratio:.0f})"
            rows.append((fam, name, limits, grbl, tg, t_ref, ref_kind, False, float("nan"), w, len(path) / w))
            t0 = time.perf_counter()
            tt, ok = toppra_naive(path, machine)
            w = time.perf_counter() - t0
            rows.append((fam, name, limits, "toppra naive", tt, t_ref, ref_kind, ok, float("nan"), w, len(path) / w))
    CACHE.parent.mkdir(exist_ok=True)
    CACHE.write_text(json.dumps(cache, indent=1, sort_keys=True))
    print(
        "| family | case | limits | planner | T_plan s | T_ref s | ref | CTR | valid | max jerk mm/s³ (1 kHz) "
        "| wall s | seg/s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for fam, name, lim, planner, tp, tr, rk, ok, jerk, wall, sps in rows:
        ctr = tp / tr if tr == tr else float("nan")
        print(f"| {fam} | {name} | {lim} | {planner} | {tp:.6f} | {tr:.6f} | {rk} | {ctr:.5f} | "
              f"{'yes' if ok else 'NO'} | {jerk:.3g} | {wall:.4f} | {sps:.0f} |")
    tr_rows = [r for r in rows if r[3] == "trcopt" and r[5] == r[5]]
    worst = max(r[4] / r[5] for r in tr_rows)
    print(f"\ntrcopt: worst CTR {worst:.5f}; all valid: {all(r[7] for r in rows if r[3] == 'trcopt')}")


if __name__ == "__main__":
    main(big="--big" in sys.argv, use_cache="--no-cache" not in sys.argv)
