"""Run a sweep: the jobs not in the table yet, on a local process pool or a Dask cluster.

Rows are appended to the table as the plans finish (in completion order), outputs written into
the output folder atomically; a plan that fails is a row with its error. An interruption (Ctrl-C,
a lost cluster) leaves the finished rows on disk; the next run does only the others.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from trcopt.batch.job import OUTPUT_SUFFIX, Work, error_row, run_job
from trcopt.batch.sweep import Job, Sweep
from trcopt.batch.table import ResultsTable, parquet_available, write_json, write_parquet
from trcopt.codes import Code
from trcopt.errors import TrcoptError
from trcopt.io.atomic import write_text_atomic
from trcopt.progress import stage

__all__ = ["BatchReport", "run_batch", "output_paths"]

Result = tuple[dict[str, Any], dict[str, str]]


@dataclass(slots=True)
class BatchReport:
    """What a run did: the keys it planned, the keys it skipped (already in the table), and the
    table in sweep order."""

    ran: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    rows: list[dict[str, Any]] = field(default_factory=list)

    @property
    def failed(self) -> int:
        return sum(1 for r in self.rows if r["exit_status"] == 2)

    @property
    def alarmed(self) -> int:
        return sum(1 for r in self.rows if r["exit_status"] == 1)

    def summary(self) -> str:
        n = len(self.rows)
        return (
            f"{n} plan(s): {n - self.failed - self.alarmed} ok, {self.alarmed} with an alarm, {self.failed} failed; "
            f"{len(self.ran)} planned now, {len(self.skipped)} already in the table"
        )


def output_paths(job: Job, out_dir: str | os.PathLike[str], kinds: tuple[str, ...]) -> dict[str, Path]:
    """Where a job's outputs go: ``<out_dir>/<program stem>.<key>.plan.json`` / ``.nc`` (the
    first 10 digits of the row's key tell the option sets of a program apart)."""
    stem = Path(job.program).stem
    return {k: Path(out_dir) / f"{stem}.{job.key[:10]}{OUTPUT_SUFFIX[k]}" for k in kinds}


def _work(job: Job, outputs: tuple[str, ...]) -> Work:
    try:
        data = Path(job.path).read_bytes()
    except OSError as exc:
        return Work(job, None, TrcoptError(f"cannot read {job.path}: {exc.strerror}", code=Code.IO).format(job.path))
    from trcopt.nc.text import decode_program

    try:
        return Work(job, decode_program(data, job.path), "", outputs)
    except TrcoptError as exc:  # not a text file
        return Work(job, None, exc.format(job.path))


def _local(works: list[Work], workers: int) -> Iterator[tuple[Work, Callable[[], Result]]]:
    """(work, result getter) in completion order on a process pool (in this process for 1)."""
    if workers <= 1:
        for w in works:
            yield w, (lambda w=w: run_job(w))  # type: ignore[misc]
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # forkserver: no fork of a process that runs threads (the progress display, Dask's)
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("forkserver"))
    try:
        futures: dict[Future[Result], Work] = {pool.submit(run_job, w): w for w in works}
        for fut in as_completed(futures):
            yield futures[fut], fut.result
    except BaseException:  # Ctrl-C, or the caller stopped: end the running plans now, not after them
        processes = list((getattr(pool, "_processes", None) or {}).values())  # (shutdown forgets them)
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()
        raise
    pool.shutdown()


def _connect(scheduler: Any) -> Any:
    """A ``distributed.Client`` of the cluster at ``scheduler`` (an address; a client as it is)."""
    try:
        from distributed import Client
    except ImportError:
        raise TrcoptError(
            "--scheduler needs dask.distributed: pip install 'trcopt[dask]'", code=Code.USAGE
        ) from None
    if isinstance(scheduler, Client):
        return scheduler
    try:
        return Client(scheduler, timeout=30)
    except (OSError, TimeoutError) as exc:
        raise TrcoptError(f"cannot reach the Dask scheduler at {scheduler}: {exc}", code=Code.IO) from None


def _dask(works: list[Work], client: Any) -> Iterator[tuple[Work, Callable[[], Result]]]:
    """(work, result getter) in completion order on the Dask cluster of ``client``."""
    from distributed import as_completed

    futures = client.map(run_job, works, pure=False, key=[f"trcopt-{w.job.key}" for w in works])
    by_key = {f.key: w for f, w in zip(futures, works, strict=True)}
    try:
        for fut in as_completed(futures):
            yield by_key[fut.key], fut.result
    finally:
        client.cancel(futures)


def run_batch(
    sweep: Sweep,
    table: str | os.PathLike[str],
    *,
    workers: int = 1,
    scheduler: Any = None,
    out_dir: str | os.PathLike[str] | None = None,
    json_path: str | os.PathLike[str] | None = None,
    parquet_path: str | os.PathLike[str] | None = None,
    fresh: bool = False,
    retry_failed: bool = False,
    on_row: Callable[[dict[str, Any]], None] | None = None,
) -> BatchReport:
    """Plan every job of ``sweep`` whose key is not in the CSV ``table`` yet.

    Parameters
    ----------
    workers:
        Local processes (1: in this process); ignored with ``scheduler``.
    scheduler:
        A Dask scheduler address (``tcp://host:8786``) or a ``distributed.Client``.
    out_dir:
        Folder for each plan's outputs (the sweep's ``outputs``); written as plans finish.
    json_path, parquet_path:
        The whole table as JSON / Parquet, written when the batch ends.
    fresh:
        Start the table anew instead of resuming it.
    retry_failed:
        Plan again the rows that failed (exit status 2) instead of keeping them.
    on_row:
        Called with each new row as it is appended.
    """
    if parquet_path is not None and not parquet_available():
        raise TrcoptError("--parquet needs pyarrow (pip install pyarrow)", code=Code.USAGE)
    if sweep.outputs and out_dir is None:
        raise TrcoptError("the sweep asks for outputs: give an output folder (--out-dir)", code=Code.USAGE)
    # the cluster is reached before the table is touched: a --fresh run that cannot reach it
    # leaves the table as it was
    client = _connect(scheduler) if scheduler is not None else None
    try:
        return _run(sweep, table, workers, client, out_dir, json_path, parquet_path, fresh, retry_failed, on_row)
    finally:
        if client is not None and client is not scheduler:
            client.close()


def _run(
    sweep: Sweep, table: str | os.PathLike[str], workers: int, client: Any, out_dir: str | os.PathLike[str] | None,
    json_path: str | os.PathLike[str] | None, parquet_path: str | os.PathLike[str] | None, fresh: bool,
    retry_failed: bool, on_row: Callable[[dict[str, Any]], None] | None,
) -> BatchReport:
    """:func:`run_batch` with the cluster's client (None: local processes) and its checks done."""
    results = ResultsTable(table, fresh=fresh)
    if retry_failed:
        results.rows = [r for r in results.rows if r["exit_status"] != 2]
    done = results.keys
    report = BatchReport()
    todo = [j for j in sweep.jobs if j.key not in done]
    report.skipped = [j.key for j in sweep.jobs if j.key in done]
    with results, stage("plans", len(todo)) as advance:
        works = [_work(j, sweep.outputs) for j in todo]
        stream = _dask(works, client) if client is not None else _local(works, workers)
        for work, get in stream:
            try:
                row, outputs = get()
            except Exception as exc:  # the worker died, the task was lost: the row says so
                lost = TrcoptError(f"the plan was lost: {type(exc).__name__}: {exc}").format(work.job.path)
                row, outputs = error_row(work.job, lost), {}
            if outputs and out_dir is not None:
                for kind, path in output_paths(work.job, out_dir, tuple(outputs)).items():
                    path.parent.mkdir(parents=True, exist_ok=True)
                    write_text_atomic(path, outputs[kind])
            results.append(row)
            report.ran.append(work.job.key)
            advance(1)
            if on_row is not None:
                on_row(row)
    report.rows = results.ordered([j.key for j in sweep.jobs])
    if json_path is not None:
        write_json(json_path, report.rows)
    if parquet_path is not None:
        write_parquet(parquet_path, report.rows)
    return report
