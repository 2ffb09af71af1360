"""The feed profile of a :class:`~trcopt.trajectory.Trajectory` as CSV (``trcopt plan --csv``).

One row per sample every ``dt`` seconds: time, arc length, position, path speed, per-axis velocity
and acceleration, per-axis jerk when the profile bounds it (jerk-limited feed), the segment index
into the tool path and its source block. Rendered to text first and written atomically.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Iterator
from io import StringIO
from pathlib import Path

from trcopt.io.atomic import write_chunks_atomic
from trcopt.trajectory import Trajectory

__all__ = [
    "render_feed_csv", "feed_csv_chunks", "write_feed_csv", "csv_step", "FEED_CSV_COLUMNS", "JERK_CSV_COLUMNS",
    "CSV_MAX_ROWS", "CSV_FINEST_STEP_S", "CSV_CHUNK_ROWS",
]

CSV_MAX_ROWS = 200_000  # the default step keeps a feed-profile CSV within this many rows (~40 MB)
CSV_FINEST_STEP_S = 1e-3  # ... and is never finer than this

FEED_CSV_COLUMNS = (
    "t_s", "s_mm", "x_mm", "y_mm", "z_mm", "path_speed_mm_s",
    "vx_mm_s", "vy_mm_s", "vz_mm_s", "ax_mm_s2", "ay_mm_s2", "az_mm_s2", "segment", "block",
)
JERK_CSV_COLUMNS = ("jx_mm_s3", "jy_mm_s3", "jz_mm_s3")  # before "segment", for a jerk-limited profile


def csv_step(duration_s: float, max_rows: int = CSV_MAX_ROWS) -> float:
    """The default sampling step of a feed-profile CSV: the finest of 1, 2, 5 × 10ⁿ s, not below
    :data:`CSV_FINEST_STEP_S`, that keeps a cycle of ``duration_s`` within ``max_rows`` rows."""
    import math

    need = max(CSV_FINEST_STEP_S, duration_s / max(1, max_rows - 1)) if math.isfinite(duration_s) else 1.0
    exponent = math.floor(math.log10(need))
    for mantissa in (1, 2, 5, 10):
        step = round(mantissa * 10.0**exponent, 12)
        if step >= need * (1 - 1e-12):
            return step
    return 10.0 ** (exponent + 1)  # pragma: no cover (10 × 10ⁿ always qualifies)


def render_feed_csv(trajectory: Trajectory, dt: float = 1e-3) -> str:
    """The feed profile sampled every ``dt`` seconds as CSV text (``\\r\\n`` line ends).

    Positions, speeds and velocities in mm and mm/s with 6 decimals, accelerations in mm/s² with
    3, jerks in mm/s³ with 1 (columns ``FEED_CSV_COLUMNS``, with ``JERK_CSV_COLUMNS`` inserted
    before ``segment`` when the samples carry the jerk).
    """
    return "".join(feed_csv_chunks(trajectory, dt))


CSV_CHUNK_ROWS = 8192  # rows per piece of :func:`feed_csv_chunks`


def feed_csv_chunks(trajectory: Trajectory, dt: float = 1e-3) -> Iterator[str]:
    """:func:`render_feed_csv` in pieces of text (for a streamed, atomic write,
    :func:`trcopt.io.atomic.write_chunks_atomic`); the pieces joined are its text."""
    smp = trajectory.sample(dt)
    jerk = smp.j
    head = FEED_CSV_COLUMNS[:-2]
    columns = (*head, *JERK_CSV_COLUMNS, *FEED_CSV_COLUMNS[-2:]) if jerk is not None else FEED_CSV_COLUMNS
    out = StringIO()
    w = csv.writer(out)
    w.writerow(columns)
    t, s, xyz, speed, v, a = (x.tolist() for x in (smp.t, smp.s, smp.xyz, smp.speed, smp.v, smp.a))
    jj = None if jerk is None else jerk.tolist()
    segment = smp.segment.tolist()
    for i in range(smp.t.shape[0]):
        x, vi, ai = xyz[i], v[i], a[i]
        w.writerow([
            f"{t[i]:.6f}", f"{s[i]:.6f}", f"{x[0]:.6f}", f"{x[1]:.6f}", f"{x[2]:.6f}", f"{speed[i]:.6f}",
            f"{vi[0]:.6f}", f"{vi[1]:.6f}", f"{vi[2]:.6f}", f"{ai[0]:.3f}", f"{ai[1]:.3f}", f"{ai[2]:.3f}",
            *(() if jj is None else (f"{c:.1f}" for c in jj[i])),
            int(segment[i]), smp.block[i],
        ])
        if i % CSV_CHUNK_ROWS == CSV_CHUNK_ROWS - 1:
            yield out.getvalue()
            out.seek(0)
            out.truncate()
    yield out.getvalue()


def write_feed_csv(trajectory: Trajectory, path: str | os.PathLike[str], dt: float = 1e-3) -> Path:
    """Write :func:`render_feed_csv` of ``trajectory`` (sampled every ``dt`` seconds) to ``path``.

    Raises
    ------
    OutputError
        The file cannot be written; an existing file at ``path`` is left untouched.
    """
    return write_chunks_atomic(path, feed_csv_chunks(trajectory, dt))
