"""Corner-transition benchmark: exact stop vs same-ε circular blends vs
optimal G2 transitions (SQP of interior-point QPs), with grbl junction deviation as the infeasible reference.

Run:  python benchmarks/bench_corners.py [problem.mpf ...] [--eps 0.01,0.1]

Every plan is timed by trcopt's timing stage on the default machine. For each blended plan the
independent no-gouge check (tests/gouge.py) and the sampled cut-part deviation
(:func:`trcopt.optimize.corners.deviation.cut_deviation`) are reported.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).parent))

from bench_timing import grbl_jd  # noqa: E402

from tests.gouge import gouges  # noqa: E402
from trcopt.config import DEFAULT_MACHINE  # noqa: E402
from trcopt.modes import TransitionKind  # noqa: E402
from trcopt.optimize.corners import blend_corners  # noqa: E402
from trcopt.pipeline import PlanOptions, plan_file  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402

WORKERS = os.cpu_count() or 1
DEFAULT = ["corner_30deg", "pocket_square", "star_g451", "cam_quarter_circle"]


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("programs", nargs="*", type=Path, help=f"part programs (default: {', '.join(DEFAULT)})")
    parser.add_argument(
        "--eps", type=lambda text: [float(e) for e in text.split(",")], default=[0.01, 0.1],
        help="contour tolerances, mm, comma-separated (default 0.01,0.1)",
    )
    args = parser.parse_args(argv)
    eps_list = args.eps
    files = args.programs or [ROOT / "problems" / "corners" / f"{n}.mpf" for n in DEFAULT]
    m = DEFAULT_MACHINE
    hdr = (
        f"{'contour':20s} {'eps':>6s} {'T_exact':>8s} {'T_arc':>8s} {'T_opt':>8s} {'exact/opt':>9s} "
        f"{'arc/opt':>8s} {'T_jd':>7s} {'jd_acc':>7s} {'dev_arc':>8s} {'dev_opt':>8s} {'goug':>4s} "
        f"{'corners':>8s} {'q/spl/arc':>10s} {'wall_s':>7s}"
    )
    print(hdr)
    for f in files:
        r = plan_file(f, PlanOptions(timing=False))
        t_exact = time_parameterize(r.toolpath, m).duration
        for eps in eps_list:
            res_arc = blend_corners(r.toolpath, r.programmed, tolerance_mm=eps, mode="arc")
            t_arc = time_parameterize(res_arc.segments, m).duration
            w0 = time.perf_counter()
            res = blend_corners(r.toolpath, r.programmed, tolerance_mm=eps, mode="optimal", workers=WORKERS)
            wall = time.perf_counter() - w0
            t_opt = time_parameterize(res.segments, m).duration
            t_jd, jd_ratio = grbl_jd([s for s in r.toolpath if not s.is_rapid], m, delta=eps)
            g = len(gouges(r.programmed, res.segments)) + len(gouges(r.programmed, res_arc.segments))
            print(
                f"{f.stem:20s} {eps:6.3f} {t_exact:8.4f} {t_arc:8.4f} {t_opt:8.4f} {t_exact / t_opt:9.3f} "
                f"{t_arc / t_opt:8.4f} {t_jd:7.4f} {jd_ratio:7.1f} {res_arc.max_deviation_mm:8.5f} "
                f"{res.max_deviation_mm:8.5f} {g:4d} {res.blended:3d}/{len(res.corners):<4d} "
                f"{res.count(TransitionKind.QUINTIC):3d}/{res.count(TransitionKind.SPLINE):3d}/"
                f"{res.count(TransitionKind.ARC):<3d} {wall:7.2f}",
                flush=True,
            )


if __name__ == "__main__":
    main(sys.argv[1:])
