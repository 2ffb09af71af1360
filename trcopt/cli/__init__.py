"""Command line: ``trcopt COMMAND …``, subcommands from a lazy registry.

Each subcommand lives in its own module with an ``add_arguments(parser)`` function that also sets
the ``handler`` default. :data:`COMMANDS` names the module and the one-line help of each; a
module is imported only when its command is run or asked for its help, so ``trcopt --help``
loads none of the numerical stack. Adding a subcommand is one module plus one line here.

Exit codes: 0 ok, 1 the program raised an alarm (outputs are still written, with the path up to
the alarm), 2 usage or I/O error. No traceback reaches the user for a problem in their files.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence
from typing import NamedTuple

from trcopt import __version__
from trcopt.cli.common import EXIT_USAGE, err, err_exc
from trcopt.errors import TrcoptError

__all__ = ["main", "build_parser", "COMMANDS", "Command"]


class Command(NamedTuple):
    """A subcommand: the module holding it, the name of its arguments function, its help line."""

    module: str
    arguments: str
    help: str


COMMANDS: dict[str, Command] = {
    "plan": Command("trcopt.cli.plan", "add_arguments", "plan a part program: tool-centre path, outputs, cycle time"),
    "check": Command("trcopt.cli.plan", "add_check_arguments", "read and compensate a program; print diagnostics only"),
    "orient": Command("trcopt.cli.orient", "add_arguments", "solve a toolholder ($TC_CARR) for a tool orientation"),
    "leadin": Command(
        "trcopt.cli.leadin",
        "add_arguments",
        "optimal lead-in into the compensated contour, compared with G147/G247/G347",
    ),
    "batch": Command("trcopt.cli.batch", "add_arguments", "plan many programs × option sets into one results table"),
}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]  # usage errors → exit 2, one line
        # the usage, then the error line in the one form of every error (``trcopt: error USAGE: …``)
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"trcopt: error USAGE: {self.prog}: {message}\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser; only ``command``'s module is imported to add its arguments (all when None)."""
    parser = _Parser(prog="trcopt", description="Optimisation-based CNC toolpath planner.")
    parser.add_argument("--version", action="version", version=f"trcopt {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, cmd in COMMANDS.items():
        p = sub.add_parser(name, help=cmd.help)
        if command is None or command == name:
            getattr(importlib.import_module(cmd.module), cmd.arguments)(p)
    return parser


def _command(argv: Sequence[str]) -> str:
    """The subcommand named in ``argv`` ("" when none): the first word that is not an option."""
    return next((a for a in argv if not a.startswith("-")), "")


def main(argv: Sequence[str] | None = None) -> int:
    args_in = list(sys.argv[1:] if argv is None else argv)
    try:
        # the parser imports the command's module: Ctrl-C there is an interrupt like any other
        parser = build_parser(_command(args_in) or "")
        args = parser.parse_args(args_in)
        if not getattr(args, "handler", None):
            parser.print_help()
            return EXIT_USAGE
        status = int(args.handler(args))
        sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's flush at exit
        return status
    except TrcoptError as exc:
        err_exc(exc)
        return EXIT_USAGE
    except KeyboardInterrupt:
        # Ctrl-C: every output is written atomically, so none is left half-written; no traceback
        return EXIT_INTERRUPTED
    except MemoryError:
        # a resource limit, not a bug: a clear line (every output is staged, none is half-written)
        err(
            "out of memory: the plan needs more memory than this machine has (a program that runs one "
            "contour very many times makes the verification compare every pass with every other)",
            code="MEMORY",
        )
        return EXIT_USAGE
    except BrokenPipeError:
        # the reader of standard output went away (``trcopt plan X | head -1``): stop quietly.
        # Python's SIGPIPE note: point stdout at devnull so the flush at exit raises nothing
        _silence_stdout()
        return EXIT_BROKEN_PIPE


EXIT_INTERRUPTED = 130  # 128 + SIGINT, the status a shell reports for a process stopped by Ctrl-C
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, the status a shell reports for a process killed by SIGPIPE


def _silence_stdout() -> None:
    """Redirect the process's standard output to the null device (after a broken pipe)."""
    import os

    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # replaced by an object without a descriptor
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, fd)
    os.close(devnull)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
