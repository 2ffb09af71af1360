"""``trcopt batch SWEEP``: plan many programs × option sets into one results table.

Exit codes: 0 every plan ok, 1 a plan raised an alarm or failed (its row says why), 2 usage or
I/O error (a bad sweep file, an unwritable table, an unreachable scheduler), 130 interrupted (the
finished rows are kept; run the same command again to resume).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from trcopt.cli.common import EXIT_ALARM, EXIT_OK, EXIT_USAGE, check_outputs, err

__all__ = ["add_arguments", "run_batch_command"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The arguments of ``trcopt batch``."""
    from trcopt.cli.plan import _workers

    p.description = "Plan every program × option set of a sweep file (TOML or CSV); see docs/batch.md."
    p.add_argument("sweep", help="sweep file: .toml (programs, [options], [axes]: cross product) or .csv (a set a row)")
    p.add_argument(
        "--results", "-o", metavar="F.csv",
        help="results table, appended as plans finish and resumed on a re-run (default: SWEEP-results.csv)",
    )
    p.add_argument("--json", metavar="F", help="the table as JSON as well (default: the results name with .json)")
    p.add_argument("--parquet", metavar="F", help="the table as Parquet as well (needs pyarrow)")
    p.add_argument("--out-dir", metavar="DIR", help="folder for each plan's outputs (the sweep's 'outputs')")
    p.add_argument(
        "--workers", type=_workers, default=0,
        help="local processes (default 0: one per CPU core; 1: in this process)",
    )
    p.add_argument("--scheduler", metavar="ADDR", help="run on the Dask cluster at ADDR (tcp://host:8786)")
    p.add_argument("--fresh", action="store_true", help="start the table anew instead of resuming it")
    p.add_argument("--retry-failed", action="store_true", help="plan again the rows that failed (exit status 2)")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress and no summary")
    p.set_defaults(handler=run_batch_command)


def run_batch_command(args: argparse.Namespace) -> int:
    from trcopt.batch import load_sweep, run_batch
    from trcopt.progress import reporting, terminal_reporter

    sweep_path = Path(args.sweep)
    results = Path(args.results) if args.results else sweep_path.with_name(f"{sweep_path.stem}-results.csv")
    json_path = Path(args.json) if args.json else results.with_suffix(".json")
    outputs = [results, json_path] + ([Path(args.parquet)] if args.parquet else [])
    problem = check_outputs(outputs, inputs=[sweep_path])
    if problem:
        err(problem, code="OUTPUT")
        return EXIT_USAGE
    if args.out_dir and Path(args.out_dir).exists() and not Path(args.out_dir).is_dir():
        err(f"--out-dir {args.out_dir} is not a folder", code="OUTPUT")
        return EXIT_USAGE
    sweep = load_sweep(sweep_path)
    with reporting(terminal_reporter(quiet=args.quiet)):
        report = run_batch(
            sweep,
            results,
            workers=args.workers,
            scheduler=args.scheduler,
            out_dir=args.out_dir,
            json_path=json_path,
            parquet_path=args.parquet,
            fresh=args.fresh,
            retry_failed=args.retry_failed,
        )
    if not args.quiet:
        print(report.summary())
        print(f"results: {results}, {json_path}" + (f", {args.parquet}" if args.parquet else ""))
    ran = set(report.ran)
    for row in report.rows:
        if row["exit_status"] == 2 and row["key"] in ran:
            print(f"{row['error']} [{row['options'] or 'defaults'}]", file=sys.stderr)
    return EXIT_OK if not (report.failed or report.alarmed) else EXIT_ALARM
