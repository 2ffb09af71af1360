"""Corner transitions at CAM scale: corners per second and peak memory of ``--corners arc`` (the
closed-form circular blends, as the program's blending modes) and ``--corners optimal`` on CAM
polylines of 200 to 100 000 chords.

Run:  python benchmarks/bench_cam_scale.py [--sizes 200,1000,10000,100000] [--timing-up-to 10000]
      [--optimal-up-to 10000] [--optimal-compensated-up-to 100000]

Each row plans one generated closed freeform contour (r(t) = c·(30 + 5·sin 5t + 2·cos 11t) mm, N
chords, c = max(1, N·0.25 mm / (2π·30 mm)) so that chords stay about 0.25 mm or longer, F6000)
written as LinuxCNC G-code, without compensation (G40 CAM output) and with ``G41.1 D2``:
the exact plan (read, compensate, verify) is the baseline measured in the same run; the corner
stage alone (:func:`trcopt.optimize.corners.blend.blend_corners`, modes ``arc`` and ``optimal``,
ε = 0.01 mm; the solvers and the strategy's modules imported before) gives the corners per
second (of wall time; the stage's CPU time beside it, which other jobs on the machine do not
stretch); every row runs in a fresh process whose peak resident memory (plan and corner stage) is
reported; up to ``--timing-up-to`` chords the acceleration-limited cycle times of both paths are added. The tool
enters and leaves from outside the contour (X = 50·c).
"""

from __future__ import annotations

import argparse
import importlib
import math
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from trcopt.optimize.corners.blend import blend_corners  # noqa: E402
from trcopt.pipeline import PlanOptions, plan  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402


def contour(chords: int, compensated: bool) -> str:
    """The closed freeform contour as ``chords`` G1 moves (LinuxCNC)."""
    scale = max(1.0, chords * 0.25 / (2 * math.pi * 30))  # chords of about 0.25 mm and more
    out = ["G21 G17 G90 G40 F6000", f"G0 X{50 * scale:.3f} Y0 Z1", "G1 Z0"]  # outside the contour
    pts = []
    for i in range(chords + 1):
        t = 2 * math.pi * i / chords
        r = scale * (30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t))
        pts.append((r * math.cos(t), r * math.sin(t)))
    if compensated:
        out.append(f"G41.1 D2 G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}")
    else:
        out.append(f"G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}")
    out += [f"G1 X{x:.5f} Y{y:.5f}" for x, y in pts[1:]]
    if compensated:
        out.append(f"G40 G1 X{50 * scale:.3f} Y0")
    return "\n".join([*out, "G0 Z5", "M2"]) + "\n"


def row(chords: int, compensated: bool, with_timing: bool, mode: str = "arc") -> str:
    """One table row, measured in this process (which should be fresh: its peak RSS is reported)."""
    import resource

    text = contour(chords, compensated)
    t0 = time.perf_counter()
    exact = plan(text, file="cam.ngc", options=PlanOptions(corners="exact", timing=False, verify=True))
    t_exact = time.perf_counter() - t0
    import clarabel  # noqa: F401  (imports outside the measurement)
    import scipy.interpolate  # noqa: F401
    import toppra  # noqa: F401

    from trcopt.optimize.corners import strategies

    importlib.import_module(strategies.get(mode).module)  # the strategy's modules (imported at first use)

    t0, c0 = time.perf_counter(), time.process_time()
    blended = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=0.01, mode=mode)
    t_corners, c_corners = time.perf_counter() - t0, time.process_time() - c0
    n = blended.blended
    cycle = ""
    if with_timing:
        t_ex = time_parameterize(exact.toolpath).duration
        t_bl = time_parameterize(blended.segments).duration
        cycle = f"{t_ex:.3f} | {t_bl:.3f} | {t_ex / t_bl:.2f}"
    else:
        cycle = "– | – | –"
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    kind = "G41.1 D2" if compensated else "G40"
    return (
        f"| {chords:,} | {kind} | {mode} | {t_exact:.2f} | {n:,} | {t_corners:.3f} | {c_corners:.3f} | "
        f"{n / max(t_corners, 1e-9):,.0f} | {peak:.0f} | {blended.max_deviation_mm:.4g} | {cycle} |"
    )


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--sizes", default="200,1000,10000,100000", help="chord counts (comma separated)")
    parser.add_argument("--timing-up-to", type=int, default=10000, help="time the paths up to this many chords")
    parser.add_argument("--optimal-up-to", type=int, default=10000, help="run optimal up to this many chords")
    parser.add_argument("--optimal-compensated-up-to", type=int, default=100000,
                        help="run optimal on the compensated contour up to this many chords")
    parser.add_argument("--row", help=argparse.SUPPRESS)  # chords,compensated,timing,mode: one row (a child)
    args = parser.parse_args(argv)
    if args.row:
        c, comp, timing, mode = args.row.split(",")
        print(row(int(c), comp == "1", timing == "1", mode), flush=True)
        return
    print("| chords | path | mode | exact plan s (baseline, no timing) | corners blended | corner stage s "
          "| its CPU s | corners/s | process peak RSS MiB | max deviation mm | exact cycle s | blended cycle s "
          "| speed-up |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for chords in (int(x) for x in args.sizes.split(",")):
        for compensated in (False, True):
            for mode in ("arc", "optimal"):
                cap = args.optimal_compensated_up_to if compensated else args.optimal_up_to
                if mode == "optimal" and chords > cap:
                    continue
                # every row in a fresh process: its peak resident memory is that row's alone
                spec = f"{chords},{int(compensated)},{int(chords <= args.timing_up_to)},{mode}"
                out = subprocess.run([sys.executable, __file__, "--row", spec], capture_output=True, text=True)
                failed = f"| {chords:,} | {mode} | failed: {out.stderr.strip()[-200:]} |"
                print(out.stdout.strip() or failed, flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
