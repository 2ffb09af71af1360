"""Acceleration-limited timing at program scale: wall time and peak memory of ``time_parameterize``.

Run:  python benchmarks/bench_timing_scale.py [--sizes 1000,10000,100000]

Two tool paths per size, built by planning generated LinuxCNC programs with trcopt (read,
compensate, no timing):

* ``one section``: the closed freeform contour of ``bench_cam_scale.py`` with ``G41.1 D2`` and
  ``--corners arc`` — every joint tangent, so the whole path is one section of N segments;
* ``N sections``: the same contour as exact G1 chords (G40): a stop at every vertex.

Each path is timed twice in the same run: the **baseline** solves every section whole and all
short sections of similar length in one lock-step group (the own solver's passes over the whole
program's row data at once, as before the windows), **trcopt** with the default windows and group
budget (:mod:`trcopt.timing.own`). Peak memory is Python's (tracemalloc) over
``time_parameterize``; wall time is a separate run without tracing. The two cycle times must be
identical. The last column is the wall time of the plan's limit check of the profile
(``check_limits`` at the 1 ms step of ``trcopt plan``).
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
import tracemalloc
from pathlib import Path

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent))
sys.path.insert(0, str(ROOT))

from bench_cam_scale import contour  # noqa: E402

import trcopt.timing.solve as solve_module  # noqa: E402
from trcopt.pipeline import ACCELERATION_CHECK_DT_S, PlanOptions, check_step, plan  # noqa: E402
from trcopt.timing.own import WINDOW_INTERVALS, solve_own  # noqa: E402


def tool_path(chords: int, one_section: bool) -> list:
    text = contour(chords, compensated=one_section)
    corners = "arc" if one_section else "exact"
    return plan(text, file="scale.ngc", options=PlanOptions(corners=corners, tolerance_mm=0.01, timing=False,
                                                             verify=False)).toolpath


def measure(path: list, window: int | None) -> tuple[float, float, float, float]:
    """(cycle time s, wall s, peak MiB, limit check s) of time_parameterize with the given window;
    ``None``: the baseline, every section whole and every group of short sections at once. The
    limit check is the plan's (``check_limits`` at 1 ms)."""
    budget = {} if window is not None else {"group_budget": 2**62}
    solve_module.solve_own = functools.partial(solve_own, window=window, **budget)
    try:
        t0 = time.perf_counter()
        traj = solve_module.time_parameterize(path)
        wall = time.perf_counter() - t0
        duration = traj.duration
        t0 = time.perf_counter()
        traj.check_limits(check_step(duration, ACCELERATION_CHECK_DT_S))
        check = time.perf_counter() - t0
        tracemalloc.start()
        solve_module.time_parameterize(path)
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
    finally:
        solve_module.solve_own = solve_own
    return duration, wall, peak, check


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--sizes", default="1000,10000,100000", help="segments (about; comma separated)")
    args = parser.parse_args(argv)
    print(f"window: {WINDOW_INTERVALS} intervals\n")
    print("| path | segments | planner | cycle s | wall s | segments/s | peak MiB | same cycle time | limit check s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for size in (int(x) for x in args.sizes.split(",")):
        for one in (True, False):
            path = tool_path(size // 2 if one else size, one)
            kind = "one section (G41.1, arc corners)" if one else "N sections (G40 chords, exact)"
            base = measure(path, None)
            ours = measure(path, WINDOW_INTERVALS)
            n = len(path)
            for name, (dur, wall, peak, check) in (("baseline: whole sections", base), ("trcopt: windows", ours)):
                same = "yes" if dur == base[0] else f"NO ({dur - base[0]:+.3g} s)"
                print(f"| {kind} | {n:,} | {name} | {dur:.3f} | {wall:.2f} | {n / wall:,.0f} | {peak:.0f} | {same} "
                      f"| {check:.2f} |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
