"""One plan of a batch, run where the executor puts it (this process, a pool process, a Dask worker).

:func:`run_job` never raises: a program that cannot be read or planned, an output that cannot be
rendered, even a bug, is a row with ``exit_status`` 2 and the error text. The program text travels
with the job (a Dask worker needs no access to the sweep's files); the outputs come back as text
and are written by the process that keeps the table.
"""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from trcopt.batch.sweep import Job
from trcopt.errors import TrcoptError

__all__ = ["Work", "run_job", "error_row", "OUTPUT_SUFFIX"]

# each plan's outputs, as ``trcopt plan`` writes them (csv: the feed profile, when it was timed)
OUTPUT_SUFFIX = {"json": ".plan.json", "gcode": ".nc", "svg": ".svg", "html": ".html", "csv": ".feed.csv"}


@dataclass(frozen=True, slots=True)
class Work:
    """A job with its program text (None and ``read_error`` set when it could not be read)."""

    job: Job
    source: str | None
    read_error: str = ""
    outputs: tuple[str, ...] = ()


def base_row(job: Job) -> dict[str, Any]:
    return {"key": job.key, "program": job.program, "options": job.options_text}


def error_row(job: Job, message: str, wall_time_s: float = 0.0) -> dict[str, Any]:
    """The row of a job that produced no plan; ``message`` is an error line (``file: error CODE: …``)."""
    return {
        **base_row(job), "ok": False, "exit_status": 2, "alarms": None, "first_alarm": None, "warnings": None,
        "cycle_time_s": None, "path_length_mm": None, "max_deviation_mm": None,
        "wall_time_s": round(wall_time_s, 4), "error": message,
    }


def run_job(work: Work) -> tuple[dict[str, Any], dict[str, str]]:
    """Plan ``work`` and return its table row and its rendered outputs (kind → text)."""
    job = work.job
    if work.source is None:
        return error_row(job, work.read_error), {}
    start = time.perf_counter()
    try:
        from trcopt.pipeline import plan

        result = plan(work.source, file=job.path, options=job.plan_options)
        outputs = {kind: text for kind in work.outputs if (text := _render(kind, result, job)) is not None}
    except TrcoptError as exc:
        return error_row(job, exc.format(job.path), time.perf_counter() - start), {}
    except Exception as exc:  # a bug: the batch goes on, the row says what happened
        last = traceback.extract_tb(exc.__traceback__)[-1:]
        where = f" at {Path(last[0].filename).name}:{last[0].lineno}" if last else ""
        text = TrcoptError(f"internal error {type(exc).__name__}{where}: {exc}").format(job.path)
        return error_row(job, text, time.perf_counter() - start), {}
    wall = time.perf_counter() - start
    errors = result.errors
    corners = result.extra.get("corners") or {}
    deviation = corners.get("max_deviation_mm")
    row = {
        **base_row(job),
        "ok": result.ok,
        "exit_status": 0 if result.ok else 1,
        "alarms": len(errors),
        "first_alarm": str(errors[0].alarm if errors[0].alarm is not None else errors[0].code) if errors else None,
        "warnings": len(result.warnings),
        "cycle_time_s": None if result.duration is None else round(result.duration, 6),
        "path_length_mm": round(result.path_length, 6),
        "max_deviation_mm": None if deviation is None else round(float(deviation), 6),
        "wall_time_s": round(wall, 4),
        "error": errors[0].format() if errors else "",
    }
    return row, outputs


def _render(kind: str, result: Any, job: Job) -> str | None:
    """The text of one output of a plan (None: a feed profile for a plan that was not timed)."""
    from trcopt import controllers

    if kind == "json":
        from trcopt.io import dumps_plan

        return dumps_plan(result.to_json())
    if kind == "svg":
        from trcopt.io.svg import render_svg

        return render_svg(result.programmed, result.toolpath, result.diagnostics, title=job.program)
    if kind == "html":
        from trcopt.io.html_preview import render_html

        return render_html(
            result.programmed, result.toolpath, result.diagnostics, result.timing,
            title=job.program, source=result.source, summary=result.summary(),
        )
    if kind == "csv":
        if result.timing is None:
            return None
        from trcopt.io.feed_csv import csv_step, feed_csv_chunks

        return "".join(feed_csv_chunks(result.timing, csv_step(result.timing.duration)))
    from trcopt.io.gcode_program import plan_to_gcode

    controller = controllers.get(result.dialect)
    return plan_to_gcode(
        result, flavor=controller.gcode, dialect=controller.dialect, program_name=Path(job.program).name
    )
