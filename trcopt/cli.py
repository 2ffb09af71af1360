"""Command line: ``trcopt plan PROGRAM …`` and the other subcommands.

Exit codes: 0 ok, 1 the program raised an alarm (outputs are still written, with the path up to
the alarm), 2 usage or I/O error. No traceback reaches the user for a problem in their files.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from . import __version__
from .errors import Severity, TrcoptError

__all__ = ["main", "build_parser"]

EXIT_OK, EXIT_ALARM, EXIT_USAGE = 0, 1, 2


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # usage errors → exit 2 with a one-line message
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")


def _add_plan_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("program", help="part program (.mpf/.spf Siemens, .h Heidenhain, .ngc RS274NGC)")
    p.add_argument("--dialect", default="auto", choices=["auto", "siemens", "heidenhain", "rs274"])
    p.add_argument(
        "--profile", default="auto", choices=["auto", "siemens", "heidenhain", "linuxcnc"],
        help="compensation semantics (default: by dialect; rs274 → linuxcnc)",
    )
    p.add_argument("--machine", metavar="FILE.toml", help="machine limits (default: embedded machine)")
    p.add_argument(
        "--tool-table", metavar="F",
        help="tool table: LinuxCNC .tbl (rs274) or TOML (heidenhain); default: beside the program",
    )
    p.add_argument(
        "--tool-unit", default="inch", choices=["inch", "mm"],
        help="length unit of a LinuxCNC tool table (default inch, LinuxCNC's machine unit)",
    )
    p.add_argument("--json", metavar="F", help="write the plan JSON (schema trcopt.plan/1)")
    p.add_argument("--gcode", metavar="F", help="write plain tool-centre G-code (G40 only)")
    p.add_argument(
        "--gcode-flavor", default=None, choices=["siemens", "rs274"], help="G-code flavour (default: by dialect)"
    )
    p.add_argument("--decimals", type=int, default=4, help="decimals in the written G-code (default 4)")
    p.add_argument("--svg", metavar="F", help="write an SVG picture of both paths")
    p.add_argument("--csv", metavar="F", help="write the feed profile as CSV (needs timing)")
    p.add_argument("--png", metavar="F", help="write a speed-profile picture (PNG or SVG by suffix)")
    p.add_argument("--no-timing", action="store_true", help="skip the time parameterisation")
    p.add_argument(
        "--corners", default="exact", choices=["exact", "optimal", "arc"],
        help="corner transitions: the controller's exact path, or optimised/circular blends within --tolerance",
    )
    p.add_argument("--tolerance", type=float, default=0.01, help="contour tolerance for --corners, mm (default 0.01)")
    p.add_argument(
        "--jerk", action="store_true",
        help="jerk-limited feed (needs jmax_mm_s3 on every machine axis; IPOPT per section, slower)",
    )
    p.add_argument(
        "--workers", type=_workers, default=0,
        help="processes for --corners optimal and --jerk (default 0: one per CPU core)",
    )
    p.add_argument("--strict", action="store_true", help="possible contour violations become alarm 10751")
    p.add_argument("--quiet", "-q", action="store_true", help="print diagnostics only")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="trcopt", description="Optimisation-based CNC toolpath planner.")
    parser.add_argument("--version", action="version", version=f"trcopt {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    p_plan = sub.add_parser("plan", help="plan a part program: tool-centre path, outputs, cycle time")
    _add_plan_arguments(p_plan)
    p_plan.set_defaults(handler=_run_plan)
    p_check = sub.add_parser("check", help="read and compensate a program; print diagnostics only")
    p_check.add_argument("program")
    p_check.add_argument("--dialect", default="auto", choices=["auto", "siemens", "heidenhain", "rs274"])
    p_check.add_argument("--strict", action="store_true")
    p_check.set_defaults(handler=_run_check)
    for register in _extra_commands():
        register(sub)
    return parser


def _extra_commands() -> list[Callable[[argparse._SubParsersAction], None]]:  # type: ignore[type-arg]
    """Subcommands owned by other modules (imported lazily, registered if present)."""
    from .kinematics.cli import register as register_orient
    from .optimize.cli import register as register_leadin

    return [register_orient, register_leadin]


def _err(message: str) -> None:
    print(f"trcopt: error: {message}", file=sys.stderr)


def _options(args: argparse.Namespace):  # type: ignore[no-untyped-def]
    from .config import DEFAULT_MACHINE, load_machine
    from .pipeline import PlanOptions

    machine = DEFAULT_MACHINE if not getattr(args, "machine", None) else load_machine(args.machine)
    return PlanOptions(
        dialect=args.dialect,
        profile=getattr(args, "profile", "auto"),
        machine=machine,
        timing=not getattr(args, "no_timing", True),
        strict=args.strict,
        tool_table=getattr(args, "tool_table", None),
        tool_unit=getattr(args, "tool_unit", "inch"),
        corners=getattr(args, "corners", "exact"),
        tolerance_mm=getattr(args, "tolerance", 0.01),
        jerk=getattr(args, "jerk", False),
        workers=getattr(args, "workers", 1),
    )


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


def _print_diagnostics(result) -> None:  # type: ignore[no-untyped-def]
    for d in result.diagnostics:
        stream = sys.stderr if d.severity is Severity.ERROR else sys.stdout
        print(d.format(), file=stream)


def _run_check(args: argparse.Namespace) -> int:
    from .pipeline import plan_file

    opts = _options(args)
    result = plan_file(args.program, opts)
    _print_diagnostics(result)
    return EXIT_OK if result.ok else EXIT_ALARM


def _run_plan(args: argparse.Namespace) -> int:
    from .io import dumps_plan, toolpath_to_gcode, write_text_atomic
    from .pipeline import plan_file

    opts = _options(args)
    result = plan_file(args.program, opts)
    _print_diagnostics(result)
    if not args.quiet:
        print(result.summary())
    flavor = args.gcode_flavor or ("rs274" if result.dialect == "rs274" else "siemens")
    # render everything first, then write: a failure never leaves some files half-written
    outputs: list[tuple[str, Callable[[], str]]] = []
    if args.json:
        outputs.append((args.json, lambda: dumps_plan(result.to_json(samples=args.csv))))
    if args.gcode:
        outputs.append(
            (
                args.gcode,
                lambda: toolpath_to_gcode(
                    result.toolpath, flavor=flavor, decimals=args.decimals, program_name=Path(args.program).name
                ),
            )
        )
    if args.svg:
        from .io.svg import render_svg

        outputs.append(
            (args.svg, lambda: render_svg(result.programmed, result.toolpath, result.diagnostics, title=args.program))
        )
    rendered = [(path, make()) for path, make in outputs]
    for path, text in rendered:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, text)
    if args.csv or args.png:
        if result.timing is None:
            _err("--csv/--png need the timing stage (drop --no-timing; see the diagnostics above)")
            return EXIT_USAGE
        if args.csv:
            result.timing.write_csv(args.csv)
        if args.png:
            result.timing.plot_speed(args.png)
    return EXIT_OK if result.ok else EXIT_ALARM


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "handler", None):
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(args.handler(args))
    except TrcoptError as exc:
        _err(str(exc))
        return EXIT_USAGE
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
