"""Plan verification throughput: the indexed (linear-time) verification against the TRC stage.

Run: ``python benchmarks/bench_verify.py [--blocks 10000 100000] [--no-baseline] [--cam 10000 100000]``.
Prints tables; not a test. Times are the process's CPU time (one core).

The program is the one of ``bench_trc.py`` (a long wavy contour of lines, inside corners and half
circles, compensated with G41 R=2). For each size the moves are compensated (the TRC time is the
baseline: verification should cost about as much as compensation, not grow faster) and the
tool-centre path is verified with :func:`trcopt.verify.verify_plan`, which reads the path into
arrays once and evaluates the residuals as whole arrays, and filters the clearance candidates
through a uniform grid (:class:`trcopt.verify.index.BoxGrid`).

For comparison, at the smallest size the same verification runs

* with the quadratic candidate filter the grid replaced (every programmed box tested for every
  tool-centre segment, and every programmed vertex for every transition circle), copied here as
  ``QuadraticFilter``;
* one segment at a time, as it was before the whole-array evaluation
  (``tests/verify/reference_verify.py``);

all three reports are checked to be identical.

``--cam`` adds the closed CAM contour of ``bench_cam_scale.py`` (N chords, LinuxCNC ``G41.1 D2``:
near-tangent joints left as they are, the closing joint) at the given sizes: the plan without
verification (read, compensate) is the baseline there, and the per-segment reference is timed at
every size.
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path
from unittest import mock

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests" / "verify"))

from bench_cam_scale import contour  # noqa: E402
from bench_trc import program  # noqa: E402
from reference_verify import reference_verify_plan  # noqa: E402

from trcopt.compensation import compensate, programmed_segment  # noqa: E402
from trcopt.config import TrcSettings  # noqa: E402
from trcopt.pipeline import PlanOptions, plan  # noqa: E402
from trcopt.verify import plan as verify_module  # noqa: E402
from trcopt.verify import verify_plan  # noqa: E402


class QuadraticFilter:
    """The candidate filter before the index: every box (vertex) tested for every query."""

    def __init__(self, boxes: np.ndarray) -> None:
        self.boxes = np.asarray(boxes, float).reshape(-1, 4)

    def near(self, box: tuple[float, float, float, float], margin: float) -> np.ndarray:
        b = self.boxes
        return np.nonzero(
            (b[:, 0] <= box[2] + margin)
            & (b[:, 2] >= box[0] - margin)
            & (b[:, 1] <= box[3] + margin)
            & (b[:, 3] >= box[1] - margin)
        )[0]

    def nearest_distance(self, p: tuple[float, float]) -> float:
        if len(self.boxes) == 0:
            return math.inf
        return float(np.min(np.hypot(self.boxes[:, 0] - p[0], self.boxes[:, 1] - p[1])))


def run(blocks: int, baselines: bool) -> dict[str, float]:
    moves = list(program(blocks))
    settings = TrcSettings()
    tol = settings.tolerances.coincidence_mm
    programmed = [s for s in (programmed_segment(m, tol) for m in moves) if s is not None]
    t0 = time.process_time()
    toolpath = list(compensate(moves, settings, []))
    t_trc = time.process_time() - t0
    t0 = time.process_time()
    rep = verify_plan(programmed, toolpath, moves, settings)
    t_verify = time.process_time() - t0
    out = {"segments": len(toolpath), "trc": t_trc, "verify": t_verify, "ok": rep.ok}
    if baselines:
        with mock.patch.object(verify_module, "BoxGrid", QuadraticFilter):
            t0 = time.process_time()
            old = verify_plan(programmed, toolpath, moves, settings)
            out["quadratic"] = time.process_time() - t0
        if old.to_json() != rep.to_json():
            raise SystemExit("the indexed and the quadratic verification differ")
        t0 = time.process_time()
        ref = reference_verify_plan(programmed, toolpath, moves, settings)
        out["reference"] = time.process_time() - t0
        if ref.to_json() != rep.to_json():
            raise SystemExit("the whole-array and the per-segment verification differ")
    return out


def run_cam(chords: int) -> dict[str, float]:
    """The CAM contour planned without verification (the baseline), then verified both ways."""
    text = contour(chords, True)
    t0 = time.process_time()
    r = plan(text, file="cam.ngc", options=PlanOptions(timing=False, verify=False, corners="exact"))
    t_plan = time.process_time() - t0
    near = 0.05  # LinuxCNC's near-tangent limit (the rs274 profile)
    t0 = time.process_time()
    rep = verify_plan(r.programmed, r.toolpath, r.nc.moves, near_tangent_rad=near)
    t_verify = time.process_time() - t0
    t0 = time.process_time()
    ref = reference_verify_plan(r.programmed, r.toolpath, r.nc.moves, near_tangent_rad=near)
    t_ref = time.process_time() - t0
    if ref.to_json() != rep.to_json():
        raise SystemExit("the whole-array and the per-segment verification differ")
    return {"segments": len(r.toolpath), "plan": t_plan, "verify": t_verify, "reference": t_ref, "ok": rep.ok}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="+", default=[10_000, 100_000])
    ap.add_argument("--no-baseline", action="store_true", help="skip the quadratic filter and per-segment reference")
    ap.add_argument("--cam", type=int, nargs="*", default=[], help="chords of the CAM contour rows")
    args = ap.parse_args()
    sizes = sorted(args.blocks)
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, one core")
    print()
    print("| blocks | segments | TRC (s) | verification (s) | verification blocks/s | verification / TRC "
          "| quadratic filter (s) | per-segment (s) | speed-up |")
    print("|---|---|---|---|---|---|---|---|---|")
    for k, n in enumerate(sizes):
        r = run(n, baselines=k == 0 and not args.no_baseline)
        q, ref = r.get("quadratic"), r.get("reference")
        qcol = "—" if q is None else f"{q:.3f}"
        rcol = "—" if ref is None else f"{ref:.3f}"
        speed = "—" if ref is None else f"{ref / r['verify']:.1f}×"
        print(
            f"| {n:,} | {r['segments']:,} | {r['trc']:.3f} | {r['verify']:.3f} | {n / r['verify']:,.0f} "
            f"| {r['verify'] / r['trc']:.2f} | {qcol} | {rcol} | {speed} |"
        )
        if not r["ok"]:
            raise SystemExit(f"the benchmark path failed its verification at {n} blocks")
    if args.cam:
        print()
        print("| CAM chords | segments | plan without verification (s) | verification (s) | verification blocks/s "
              "| per-segment (s) | speed-up |")
        print("|---|---|---|---|---|---|---|")
        for n in sorted(args.cam):
            r = run_cam(n)
            print(
                f"| {n:,} | {r['segments']:,} | {r['plan']:.3f} | {r['verify']:.3f} | {n / r['verify']:,.0f} "
                f"| {r['reference']:.3f} | {r['reference'] / r['verify']:.1f}× |"
            )
            if not r["ok"]:
                raise SystemExit(f"the CAM contour failed its verification at {n} chords")


if __name__ == "__main__":
    main()
