"""trcopt against the literature's corner-smoothing baselines, on the same paths, limits and ε.

Run:  python benchmarks/bench_literature.py [--jerk-up-to 10] [--points 100]

Paths (``baselines.py``): the rotated square of the published reproduction (3 × 90°, ε = 0.2 mm),
a butterfly outline and a random zig-zag with turns up to 170° (ε = 0.05 mm), vertex tolerance,
vector limits V = 100 mm/s, A = 3 000 mm/s², J = 60 000 mm/s³ (per-axis limits far above them).

Rows per path, all computed in this run:

* the literature's baselines from ``baselines.py``: the G01 junction-speed planner and Zhao, Zhu &
  Ding 2013 (speed cap at each transition's middle, and held over the whole transition);
* trcopt, the path written as G40 lines and planned through the API: exact stop; ``arc`` (circular
  blends within ε at the vertex); ``optimal`` (under jerk limits the symmetric cubic B-spline
  transitions within ε). Each trcopt plan is timed acceleration-limited (``time_parameterize``)
  and, up to ``--jerk-up-to`` segments, jerk-limited (``jerk_limited``; IPOPT per section) — the
  baselines are jerk-limited, so only the jerk-limited rows compare on their terms. Every trcopt
  profile is re-checked against every limit (``check_limits``: per-axis and vector |v|, |a|, and
  with jerk |j| including the curvature-jump steps), the measured vertex deviation is reported.
  The Zhao plans are re-checked on their transitions with every term of |a| and |j|
  (``baselines.vector_load``); their own model bounds only κv² and κ²v³ at the transition middle.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent))
sys.path.insert(0, str(ROOT))

import baselines as bl  # noqa: E402

from trcopt import AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan  # noqa: E402
from trcopt.config import PathLimits  # noqa: E402
from trcopt.optimize.corners.blend import blend_corners  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402
from trcopt.timing.jerk import jerk_limited  # noqa: E402


def machine(lim: bl.Limits) -> Machine:
    generous = tuple((k, AxisLimits(1e4, 1e6, 1e8)) for k in "XYZ")
    return Machine(name="vector", rapid_mm_min=60000.0, axes=generous, path=PathLimits(lim.V, lim.A, lim.J))


def g40_path(points: np.ndarray, feed: float) -> list[Segment]:
    return [
        Segment(Line((a[0], a[1], 0.0), (b[0], b[1], 0.0)), Plane.G17, Role.CONTOUR, SourceSpan("lit", i + 1, 1), feed)
        for i, (a, b) in enumerate(zip(points[:-1], points[1:], strict=True))
    ]


def vertex_deviation(exact: list[Segment], path: list[Segment], step: float = 1e-3) -> float:
    """The largest distance (mm) from an inner vertex of the exact polyline to the new path,
    sampled every ``step`` mm (a k-d tree of the samples): the vertex tolerance as the baselines
    measure it, whatever the transitions (per-corner curves or one spline across many corners)."""
    from scipy.spatial import cKDTree

    from trcopt.timing.path import PathArrays

    arrays = PathArrays(path)
    counts = np.maximum(2, np.ceil(arrays.length / step).astype(int) + 1)
    iseg = np.repeat(np.arange(len(path)), counts)
    local = np.concatenate([np.linspace(0.0, L, n) for L, n in zip(arrays.length, counts, strict=True)])
    samples = arrays.eval(iseg, local, 0)[:, :2]
    vertices = np.array([s.geometry.end[:2] for s in exact[:-1]])
    return float(cKDTree(samples).query(vertices)[0].max())


def trcopt_rows(name: str, pts: np.ndarray, eps: float, lim: bl.Limits, jerk_up_to: int) -> list[str]:
    m = machine(lim)
    exact = g40_path(pts, lim.V)
    rows = []
    for mode in ("exact", "arc", "optimal"):
        t0 = time.perf_counter()
        if mode == "exact":
            path, dev = exact, 0.0
        else:
            objective = "jerk" if mode == "optimal" else "curvature"
            res = blend_corners(exact, exact, tolerance_mm=eps, machine=m, mode=mode, kind="vertex",
                                objective=objective)
            path = res.segments
            dev = vertex_deviation(exact, path)
        t_corner = time.perf_counter() - t0
        acc = time_parameterize(path, m)
        rep = acc.check_limits(dt=1e-4)
        note = f"corners {t_corner:.2f} s; vertex deviation {dev:.4f} mm"
        rows.append(f"| {name} | {len(exact)} | {eps:g} | trcopt {mode}, acceleration-limited | {acc.duration:.5f} | "
                    f"{'yes' if rep.ok else 'NO'} | {note} |")
        if len(path) <= jerk_up_to:
            t0 = time.perf_counter()
            jt = jerk_limited(path, m, base=acc)
            wall = time.perf_counter() - t0
            jr = jt.check_limits(dt=1e-4)
            rows.append(f"| {name} | {len(exact)} | {eps:g} | trcopt {mode}, jerk-limited | {jt.duration:.5f} | "
                        f"{'yes' if jr.ok else 'NO'} | {note}; jerk stage {wall:.1f} s |")
        else:
            rows.append(f"| {name} | {len(exact)} | {eps:g} | trcopt {mode}, jerk-limited | – | – | "
                        f"{len(path)} segments > --jerk-up-to {jerk_up_to} |")
    return rows


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--jerk-up-to", type=int, default=10, help="jerk-limited timing up to this many segments")
    parser.add_argument("--points", type=int, default=100, help="points of the butterfly and the zig-zag")
    args = parser.parse_args(argv)
    lim = bl.Limits()
    cases = [
        ("rotated square (3 x 90 deg)", bl.rotated_square(), 0.2),
        (f"butterfly, {args.points} pts", bl.butterfly(args.points), 0.05),
        (f"zig-zag, {args.points} pts, turns <= 170 deg", bl.zigzag(args.points), 0.05),
    ]
    print(f"limits: V={lim.V:g} mm/s, A={lim.A:g} mm/s^2, J={lim.J:g} mm/s^3 (vector), Ts={lim.Ts:g} s\n")
    print("| path | segments | eps mm | method | cycle s | limits ok | notes |")
    print("|---|---|---|---|---|---|---|")
    for name, pts, eps in cases:
        pts = bl._clean(pts)
        g = bl.g01_baseline(pts, lim)
        print(f"| {name} | {len(pts) - 1} | {eps:g} | G01 junction speed (baseline) | {g.total_time:.5f} | – | |")
        for mode, label in (("midpoint", "Zhao 2013, cap at the transition middle (baseline)"),
                            ("constant", "Zhao 2013, cap over the whole transition (baseline)"),
                            ("every-term", "Zhao 2013, cap over the transition bounding κ′v³ too (baseline)")):
            z = bl.zhao2013(pts, eps, lim, transition_speed=mode)
            acc, jerk = bl.vector_load(z, lim)
            ok = "yes" if acc <= 1.001 and jerk <= 1.01 else "NO"
            print(f"| {name} | {len(pts) - 1} | {eps:g} | {label} | {z.total_time:.5f} | {ok} | "
                  f"on the transitions: max \\|a\\|/A {acc:.3f}, \\|j\\|/J {jerk:.3f} (every term, sampled) |")
        for row in trcopt_rows(name, pts, eps, lim, args.jerk_up_to):
            print(row, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
