"""Plan verification throughput: the indexed (linear-time) verification against the TRC stage.

Run: ``python benchmarks/bench_verify.py [--blocks 10000 100000] [--no-baseline]``. Prints a table;
not a test. Times are the process's CPU time (one core).

The program is the one of ``bench_trc.py`` (a long wavy contour of lines, inside corners and half
circles, compensated with G41 R=2). For each size the moves are compensated (the TRC time is the
baseline: verification should cost about as much as compensation, not grow faster) and the
tool-centre path is verified with :func:`trcopt.verify.verify_plan`, which filters the clearance
candidates through a uniform grid (:class:`trcopt.verify.index.BoxGrid`).

For comparison, at the smallest size the same verification runs with the quadratic candidate
filter it replaced (every programmed box tested for every tool-centre segment, and every
programmed vertex for every transition circle), copied here as ``QuadraticFilter``; both give
identical residuals (checked).
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

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_trc import program  # noqa: E402

from trcopt.compensation import compensate, programmed_segment  # noqa: E402
from trcopt.config import TrcSettings  # noqa: E402
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


def run(blocks: int, quadratic: bool) -> dict[str, float]:
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
    if quadratic:
        with mock.patch.object(verify_module, "BoxGrid", QuadraticFilter):
            t0 = time.process_time()
            old = verify_plan(programmed, toolpath, moves, settings)
            out["quadratic"] = time.process_time() - t0
        if old.to_json() != rep.to_json():
            raise SystemExit("the indexed and the quadratic verification differ")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="+", default=[10_000, 100_000])
    ap.add_argument("--no-baseline", action="store_true", help="skip the quadratic filter")
    args = ap.parse_args()
    sizes = sorted(args.blocks)
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, one core")
    print()
    print("| blocks | segments | TRC (s) | verification (s) | verification blocks/s | verification / TRC "
          "| quadratic filter (s) | speed-up |")
    print("|---|---|---|---|---|---|---|---|")
    for k, n in enumerate(sizes):
        r = run(n, quadratic=k == 0 and not args.no_baseline)
        q = r.get("quadratic")
        qcol = "—" if q is None else f"{q:.3f}"
        speed = "—" if q is None else f"{q / r['verify']:.1f}×"
        print(
            f"| {n:,} | {r['segments']:,} | {r['trc']:.3f} | {r['verify']:.3f} | {n / r['verify']:,.0f} "
            f"| {r['verify'] / r['trc']:.2f} | {qcol} | {speed} |"
        )
        if not r["ok"]:
            raise SystemExit(f"the benchmark path failed its verification at {n} blocks")


if __name__ == "__main__":
    main()
