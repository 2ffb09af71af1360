"""Batch planning: many programs × option sets, one results table (``trcopt batch``).

A sweep file (:mod:`trcopt.batch.sweep`, TOML cross product or CSV rows) names the programs and
the option axes; :func:`run_batch` plans every combination on a local process pool or a Dask
cluster and appends one row per plan to a CSV (:mod:`trcopt.batch.table`) as it finishes. A re-run
skips the rows already there (the key of a row hashes the program and the option set), so an
interrupted batch resumes where it stopped. See docs/batch.md.

>>> from trcopt.batch import load_sweep, run_batch           # doctest: +SKIP
>>> report = run_batch(load_sweep("sweep.toml"), "results.csv", workers=2)
>>> report.rows[0]["cycle_time_s"]
"""

from __future__ import annotations

from trcopt.batch.job import Work, run_job
from trcopt.batch.run import BatchReport, output_paths, run_batch
from trcopt.batch.sweep import OPTION_NAMES, OUTPUT_KINDS, Job, Sweep, job_key, load_sweep, plan_options
from trcopt.batch.table import COLUMNS, ResultsTable, read_rows

__all__ = [
    "BatchReport",
    "COLUMNS",
    "Job",
    "OPTION_NAMES",
    "OUTPUT_KINDS",
    "ResultsTable",
    "Sweep",
    "Work",
    "job_key",
    "load_sweep",
    "output_paths",
    "plan_options",
    "read_rows",
    "run_batch",
    "run_job",
]
