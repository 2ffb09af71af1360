"""``trcopt plan PROGRAM`` and ``trcopt check PROGRAM``: the main job and its diagnostics-only form.

Exit codes: 0 ok, 1 the program raised an alarm (outputs are still written, with the path up to
the alarm), 2 usage or I/O error.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from trcopt import controllers
from trcopt.cli.common import EXIT_ALARM, EXIT_OK, EXIT_USAGE, check_outputs, err, err_exc
from trcopt.errors import Severity, TrcoptError
from trcopt.io.atomic import OutputError, StagedFile
from trcopt.io.flavors import OUTPUT_FLAVORS
from trcopt.modes import ApprRadius, ToolUnit, parse_enum
from trcopt.optimize.corners import strategies as corner_strategies

if TYPE_CHECKING:
    from trcopt.pipeline import PlanOptions, PlanResult

__all__ = ["add_arguments", "add_check_arguments", "run_plan", "run_check"]


def _add_reading_arguments(p: argparse.ArgumentParser) -> None:
    """What selects how a program is read and compensated (``plan`` and ``check`` alike)."""
    p.add_argument("program", help="part program (.mpf/.spf Siemens, .h Heidenhain, .ngc RS274NGC)")
    p.add_argument("--dialect", default="auto", choices=["auto", *controllers.dialects()])
    p.add_argument(
        "--profile", default="auto", choices=["auto", *controllers.names()],
        help="compensation semantics of a controller (default: the reading controller's)",
    )
    p.add_argument("--machine", metavar="FILE.toml", help="machine limits (default: embedded machine)")
    p.add_argument(
        "--tool-table", metavar="F",
        help="tool table: LinuxCNC .tbl (rs274) or TOML (heidenhain, siemens); default: beside the program",
    )
    p.add_argument(
        "--zero-offsets", metavar="F",
        help="SINUMERIK settable zero offsets G54… (TOML); default: <program>.offsets.toml beside the program",
    )
    p.add_argument(
        "--tool-unit", default=ToolUnit.PROGRAM.value, choices=[u.value for u in ToolUnit],
        help="length unit of a LinuxCNC tool table and offset parameters (default: the program's G20/G21 unit)",
    )
    p.add_argument(
        "--appr-radius", default=ApprRadius.CENTRE.value, choices=[a.value for a in ApprRadius],
        help="Heidenhain APPR/DEP CT/LCT radius: of the tool-centre arc (default) or of the contour arc",
    )
    p.add_argument(
        "--strict", action="store_true",
        help="possible contour violations become alarm 10751, a failed verification (VERIFY-…) an error",
    )


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The arguments of ``trcopt plan``."""
    _add_reading_arguments(p)
    p.add_argument("--json", metavar="F", help="write the plan JSON (schema trcopt.plan/1)")
    p.add_argument("--gcode", metavar="F", help="write plain tool-centre G-code (G40 only)")
    p.add_argument(
        "--gcode-flavor", default=None,
        choices=sorted({*controllers.names(), *controllers.dialects(), *OUTPUT_FLAVORS, "klartext"}),
        help="G-code flavour of a controller, grbl (plain ISO) or klartext (Heidenhain conversational, for "
        "Heidenhain programs); default: the reading controller's, klartext for a Heidenhain program written to .h",
    )
    p.add_argument("--decimals", type=int, default=4, help="decimals in the written G-code (default 4)")
    p.add_argument("--svg", metavar="F", help="write an SVG picture of both paths")
    p.add_argument(
        "--html", metavar="F",
        help="write an interactive preview: one self-contained HTML page (views, pan/zoom, speed, alarms)",
    )
    p.add_argument("--csv", metavar="F", help="write the feed profile as CSV (needs timing)")
    p.add_argument(
        "--csv-step", metavar="S", type=_positive_seconds, default=None,
        help="sampling step of --csv, s (default: 1 ms, coarser for long cycles: at most 200 000 rows)",
    )
    p.add_argument("--png", metavar="F", help="write a speed-profile picture (PNG or SVG by suffix)")
    p.add_argument("--no-timing", action="store_true", help="skip the time parameterisation")
    p.add_argument(
        "--corners", default=corner_strategies.PROGRAM, choices=corner_strategies.names(),
        help="corners: what the program's path-control mode does (default: program), exact stop at every "
        "corner (exact), or circular (arc) or optimised (optimal) transitions within the program's tolerance, "
        "else --tolerance",
    )
    p.add_argument(
        "--tolerance", type=_positive_mm, default=0.01,
        help="corner tolerance of --corners arc|optimal where the program sets none, mm (default 0.01)",
    )
    p.add_argument(
        "--tolerance-kind", choices=("contour", "vertex"), default=None,
        help="how a corner tolerance of a path without compensation is measured: from the programmed path "
        "(contour) or from the corner point (vertex); default: the program's mode's, else contour",
    )
    p.add_argument(
        "--jerk", action="store_true",
        help="jerk-limited feed (needs jmax_mm_s3 on every machine axis; IPOPT per section, slower)",
    )
    p.add_argument(
        "--jerk-engine", choices=("nlp", "fir"), default="nlp",
        help="--jerk: nlp (the time optimum per section) or fir (about 4x faster, cycle times 1-7%% longer; "
        "every profile checked) — benchmarks/JERK.md",
    )
    p.add_argument(
        "--workers", type=_workers, default=0,
        help="processes for --corners optimal and --jerk (default 0: one per CPU core)",
    )
    p.add_argument(
        "--stream", choices=("auto", "on", "off"), default="auto",
        help="plan window by window in bounded memory: auto (programs over 4 MiB whose outputs are --json/--gcode "
        "only), on (whenever the program and options allow), off (always the whole program)",
    )
    p.add_argument("--quiet", "-q", action="store_true", help="print diagnostics only")
    p.set_defaults(handler=run_plan)


def add_check_arguments(p: argparse.ArgumentParser) -> None:
    """The arguments of ``trcopt check``: those of ``plan`` that read and compensate."""
    _add_reading_arguments(p)
    p.add_argument("--quiet", "-q", action="store_true", help="no progress display")
    p.set_defaults(handler=run_check)


def _options(args: argparse.Namespace) -> PlanOptions:
    from trcopt.config import DEFAULT_MACHINE, load_machine
    from trcopt.pipeline import PlanOptions

    machine = DEFAULT_MACHINE if not getattr(args, "machine", None) else load_machine(args.machine)
    return PlanOptions(
        dialect=args.dialect,
        profile=getattr(args, "profile", "auto"),
        machine=machine,
        timing=not getattr(args, "no_timing", True),
        strict=args.strict,
        tool_table=getattr(args, "tool_table", None),
        zero_offsets=getattr(args, "zero_offsets", None),
        tool_unit=parse_enum(ToolUnit, getattr(args, "tool_unit", ToolUnit.PROGRAM), "tool unit"),
        appr_radius=parse_enum(ApprRadius, getattr(args, "appr_radius", ApprRadius.CENTRE), "APPR/DEP radius"),
        corners=getattr(args, "corners", corner_strategies.EXACT),
        tolerance_mm=getattr(args, "tolerance", 0.01),
        tolerance_kind=getattr(args, "tolerance_kind", None),
        jerk=getattr(args, "jerk", False),
        jerk_engine=getattr(args, "jerk_engine", "nlp"),
        workers=getattr(args, "workers", 1),
    )


def _positive(what: str) -> Callable[[str], float]:
    """An argparse type for a positive finite ``what`` (``"length in mm"``, ``"time in s"``)."""

    def parse(text: str) -> float:
        import math

        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        if not (math.isfinite(value) and value > 0.0):
            raise argparse.ArgumentTypeError(f"must be a positive finite {what}, got {text!r}")
        return value

    return parse


_positive_mm = _positive("length in mm")  # --tolerance
_positive_seconds = _positive("time in s")  # --csv-step


def _workers(text: str) -> int:
    """``--workers`` value: a non-negative integer; 0 means one process per CPU core."""
    import os

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 (one per CPU core) or positive, got {value}")
    return value or os.cpu_count() or 1


def _suffix(path: str) -> str:
    return Path(path).suffix.lower()


def _importable(module: str) -> bool:
    """Whether the optional ``module`` can be imported (checked before the work starts)."""
    import importlib.util

    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def _print_diagnostics(result: PlanResult) -> None:
    for d in result.diagnostics:
        stream = sys.stderr if d.severity is Severity.ERROR else sys.stdout
        print(d.format(), file=stream)


def _plan_with_progress(args: argparse.Namespace, opts: PlanOptions) -> PlanResult:
    """Plan ``args.program``, with progress on a terminal's standard error unless ``--quiet``."""
    from trcopt.pipeline import plan_file
    from trcopt.progress import reporting, stage, terminal_reporter

    reporter = terminal_reporter(quiet=getattr(args, "quiet", False))
    with reporting(reporter), stage(f"planning {Path(args.program).name}"):
        return plan_file(args.program, opts)


def run_check(args: argparse.Namespace) -> int:
    opts = _options(args)
    result = _streamed(args, opts) or _plan_with_progress(args, opts)
    _print_diagnostics(result)
    return EXIT_OK if result.ok else EXIT_ALARM


def run_plan(args: argparse.Namespace) -> int:
    from trcopt.io.atomic import stage_chunks
    from trcopt.progress import reporting, stage, terminal_reporter

    if (args.csv or args.png) and args.no_timing:
        err("--csv/--png need the timing stage (drop --no-timing)")
        return EXIT_USAGE
    if args.png and not _importable("matplotlib"):
        err("--png needs matplotlib: pip install 'trcopt[plot]'")
        return EXIT_USAGE
    # every output path is checked before the work starts
    problem = check_outputs([args.json, args.gcode, args.svg, args.html, args.csv, args.png], inputs=[args.program])
    if problem:
        err(problem, code="OUTPUT")
        return EXIT_USAGE
    opts = _options(args)
    # a Heidenhain program written to a .h file: the conversational program a TNC runs (a .h file
    # is Klartext there; the ISO flavour's I/J would be read as absolute centres by a TNC's DIN/ISO)
    auto_klartext = args.gcode_flavor is None and bool(args.gcode) and _suffix(args.gcode) == ".h"
    if auto_klartext and _suffix(args.program) == ".h":
        args.gcode_flavor = "klartext"
    result = _streamed(args, opts) or _plan_with_progress(args, opts)
    _print_diagnostics(result)
    if not args.quiet:
        print(result.summary())
    if auto_klartext:
        args.gcode_flavor = "klartext" if result.dialect == "heidenhain" else None
    if args.gcode_flavor == "klartext":
        flavor, flavor_dialect = controllers.get("heidenhain").gcode, "heidenhain"
    elif args.gcode_flavor in OUTPUT_FLAVORS:
        flavor, flavor_dialect = OUTPUT_FLAVORS[args.gcode_flavor], args.gcode_flavor
    else:
        out_controller = controllers.get(args.gcode_flavor or result.dialect)
        flavor, flavor_dialect = out_controller.gcode, out_controller.dialect
    # render everything first, then write: a failure never leaves some files written and others not
    outputs: list[tuple[str, Callable[[], str | Iterable[str] | tuple[Path, bytes]]]] = []
    if args.json:
        outputs.append((args.json, lambda: result.json_chunks(samples=args.csv)))
    if args.gcode:
        from trcopt.io.gcode_program import plan_to_gcode_chunks  # (a plan without --gcode never loads them)
        from trcopt.io.klartext import plan_to_klartext

        outputs.append(
            (
                args.gcode,
                (lambda: plan_to_klartext(result, decimals=args.decimals, program_name=Path(args.program).name))
                if args.gcode_flavor == "klartext"
                else lambda: plan_to_gcode_chunks(
                    result,
                    flavor=flavor,
                    dialect=flavor_dialect,
                    decimals=args.decimals,
                    program_name=Path(args.program).name,
                ),
            )
        )
    if args.svg:
        from trcopt.io.svg import render_svg

        outputs.append(
            (args.svg, lambda: render_svg(result.programmed, result.toolpath, result.diagnostics, title=args.program))
        )
    if args.html:
        from trcopt.io.html_preview import render_html

        outputs.append(
            (
                args.html,
                lambda: render_html(
                    result.programmed, result.toolpath, result.diagnostics, result.timing,
                    title=args.program, source=result.source, summary=result.summary(),
                ),
            )
        )
    timing = result.timing
    if (args.csv or args.png) and timing is None:
        # the program stopped at an alarm before any motion, has no motion, or its timing
        # failed (a warning says why): there is no feed profile to write
        print(
            f"{args.program}: note: --csv/--png not written: no feed profile was computed "
            "(see the diagnostics above)"
        )
    elif timing is not None:
        from trcopt.io.feed_csv import csv_step, feed_csv_chunks

        if args.csv:
            step = args.csv_step or csv_step(timing.duration)
            outputs.append((args.csv, lambda: feed_csv_chunks(timing, step)))
        if args.png:
            from trcopt.io.plot import render_speed

            outputs.append((args.png, lambda: render_speed(timing, args.png)))
    # every output is written to a temporary file beside it first (streamed, never whole in
    # memory), and all are put in place only when all are complete: a failure never leaves some
    # files written and others not
    staged: list[StagedFile] = []
    try:
        with reporting(terminal_reporter(quiet=args.quiet)), stage("rendering the outputs", len(outputs)) as done:
            for name, make in outputs:
                content = make()
                if isinstance(content, (str, tuple)):
                    path, data = _as_file(name, content)
                    chunks: Iterable[str | bytes] = (data,)
                else:
                    path, chunks = Path(name), content
                try:
                    path.parent.mkdir(parents=True, exist_ok=True)
                except OSError as exc:
                    err(f"cannot create the folder of {path}: {exc.strerror or exc}", file=str(path), code="OUTPUT")
                    for st in staged:
                        st.discard()
                    return EXIT_USAGE
                staged.append(stage_chunks(path, chunks))
                done(1)
    except TrcoptError as exc:  # a non-finite number in the plan JSON (the key named), a cycle too long to sample
        for st in staged:
            st.discard()
        if isinstance(exc, OutputError):
            raise
        err_exc(exc, args.program)
        return EXIT_USAGE
    except BaseException:
        for st in staged:
            st.discard()
        raise
    for st in staged:
        st.commit()
    return EXIT_OK if result.ok else EXIT_ALARM


# --stream auto: programs from this size (about 150 000 blocks) are planned window by window; the
# whole plan holds about 3 KB a block and is faster (the window-by-window plan reads the program
# twice: the verification's part contour first)
STREAM_MIN_BYTES = 4 << 20


def _streamed(args: argparse.Namespace, opts: PlanOptions) -> Any:
    """The plan made window by window (:mod:`trcopt.pipeline.stream`) when ``--stream`` and the
    outputs allow it, else None (the whole program is planned: other outputs, options or program
    content that need it)."""
    mode = getattr(args, "stream", "auto")
    if mode == "off" or any(getattr(args, k, None) for k in ("svg", "html", "csv", "png")):
        return None
    if getattr(args, "gcode_flavor", None) == "klartext":
        return None
    try:
        if mode == "auto" and os.path.getsize(args.program) < STREAM_MIN_BYTES:
            return None
    except OSError:
        return None  # the whole plan reports the unreadable file
    from trcopt.pipeline.stream import Unstreamable, plan_streamed
    from trcopt.progress import reporting, stage, terminal_reporter

    reporter = terminal_reporter(quiet=getattr(args, "quiet", False))
    try:
        with reporting(reporter), stage(f"planning {Path(args.program).name} window by window"):
            return plan_streamed(
                args.program, opts, json=bool(getattr(args, "json", None)), gcode=bool(getattr(args, "gcode", None)),
                samples=getattr(args, "csv", None),
            )
    except Unstreamable:
        return None


def _as_file(path: str, content: str | tuple[Path, bytes]) -> tuple[Path, bytes]:
    """A rendered output as (file, bytes): text is UTF-8; a picture names its own file (a suffix
    may have been added)."""
    if isinstance(content, str):
        return Path(path), content.encode("utf-8")
    return content


