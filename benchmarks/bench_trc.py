"""TRC stage throughput and memory on a generated program of compensated blocks.

Run: ``python benchmarks/bench_trc.py [--blocks 100000]``. Prints a table; not a test.
Times are the process's CPU time (one core), so a busy machine disturbs them less than wall time.

The throughput runs over moves built before the clock starts (as from a read program); the
memory runs generate the moves lazily. The program is a long wavy contour compensated with G41
R=2: per 50 mm period one straight line, a 45° inside corner, a convex half circle (G2, offset
radius 7), two more inside corners, a concave half circle (G3, offset radius 3) with outside
corners and transition circles. The moves are generated lazily and the tool-centre segments are
counted, not stored, so the peak memory measures the engine's own working set (bounded look-ahead
window).

Baseline in the same run: the offset-only pass (each programmed element built and offset by R in
closed form, no junction logic, no output segments) over the same moves — the floor of any exact TRC implementation in
this code base.
"""

from __future__ import annotations

import argparse
import gc
import platform
import time
import tracemalloc
from collections.abc import Iterator

from trcopt.compensation import compensate
from trcopt.compensation.elements import make_programmed_geometry
from trcopt.config import TrcSettings
from trcopt.errors import SourceSpan
from trcopt.geometry import Plane
from trcopt.modes import Side
from trcopt.nc.model import CompState, Move, MoveKind

RADIUS = 2.0
PERIOD = [  # (kind, dx, dy, centre offset from start or None)
    ("G1", 10.0, 0.0, None),
    ("G1", 5.0, 5.0, None),
    ("G2", 10.0, 0.0, (5.0, 0.0)),
    ("G1", 5.0, -5.0, None),
    ("G1", 5.0, 0.0, None),
    ("G3", 10.0, 0.0, (5.0, 0.0)),
    ("G1", 5.0, 0.0, None),
]


def program(blocks: int) -> Iterator[Move]:
    """Selection block, ``blocks`` compensated contour blocks, deselection block."""
    on = CompState(side=Side.LEFT, radius=RADIUS, tool_active=True)
    off = CompState(side=Side.OFF, radius=RADIUS, tool_active=True)
    span = SourceSpan("bench.mpf", 1, 1, "N10")
    pos = (-10.0, 10.0, 0.0)
    yield Move(MoveKind.LINE, pos, (0.0, 0.0, 0.0), Plane.G17, span, on, 10.0)
    pos = (0.0, 0.0, 0.0)
    for k in range(blocks):
        kind, dx, dy, c = PERIOD[k % len(PERIOD)]
        end = (pos[0] + dx, pos[1] + dy, 0.0)
        sp = SourceSpan("bench.mpf", k + 2, 1, f"N{(k + 2) * 10}")
        if c is None:
            yield Move(MoveKind.LINE, pos, end, Plane.G17, sp, on, 10.0)
        else:
            centre = (pos[0] + c[0], pos[1] + c[1], 0.0)
            yield Move(MoveKind.ARC, pos, end, Plane.G17, sp, on, 10.0, centre, kind == "G3")
        pos = end
    yield Move(MoveKind.LINE, pos, (pos[0] + 10, pos[1] + 10, 0.0), Plane.G17, span, off, 10.0)


def run_trc(blocks: int) -> tuple[float, int, int]:
    """Throughput over the moves of a read program (built before the clock starts)."""
    moves = list(program(blocks))
    diags: list = []
    t0 = time.process_time()
    n = sum(1 for _ in compensate(moves, TrcSettings(), diags))
    dt = time.process_time() - t0
    errors = [d for d in diags if d.severity.value == "error"]
    if errors:
        raise SystemExit(f"benchmark program raised {errors[0].format()}")
    return dt, n, len(diags)


def run_offset_only(blocks: int) -> float:
    moves = list(program(blocks))
    t0 = time.process_time()
    for m in moves:
        make_programmed_geometry(m).offset(RADIUS)
    return time.process_time() - t0


def peak_memory(blocks: int) -> float:
    gc.collect()
    tracemalloc.start()
    sum(1 for _ in compensate(program(blocks), TrcSettings(), []))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=100_000)
    args = ap.parse_args()
    n = args.blocks
    dt, segs, ndiag = run_trc(n)
    dt_base = run_offset_only(n)
    mem_small = peak_memory(n // 10)
    mem_full = peak_memory(n)
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, one core")
    print()
    print(f"| measurement | {n // 10:,} blocks | {n:,} blocks |")
    print("|---|---|---|")
    print(f"| TRC engine peak memory (tracemalloc, output not stored) | {mem_small:,.0f} KiB | {mem_full:,.0f} KiB |")
    print()
    print("| stage | blocks | segments | CPU time (s) | blocks/s | ratio to baseline |")
    print("|---|---|---|---|---|---|")
    print(f"| baseline: offset only, no junctions | {n:,} | {n:,} | {dt_base:.3f} | {n / dt_base:,.0f} | 1.00 |")
    print(
        f"| TRC engine (corners, look-ahead, CDOF) | {n:,} | {segs:,} | {dt:.3f} | {n / dt:,.0f} "
        f"| {dt / dt_base:.2f} |"
    )
    print()
    print(f"diagnostics: {ndiag}; target: >= 30,000 blocks/s, memory independent of program length")


if __name__ == "__main__":
    main()
