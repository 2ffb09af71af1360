"""What every subcommand shares: exit codes, the error line and the check of output paths.

Every error a command prints has one form, the compiler's and that of the diagnostics:
``file:line:col: error CODE (N…): message`` where the error has a place in a file, else
``file: error CODE: message`` with the file it concerns (``trcopt`` when it concerns none).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path

from trcopt.errors import TrcoptError

__all__ = ["EXIT_OK", "EXIT_ALARM", "EXIT_USAGE", "err", "err_exc", "check_outputs"]

EXIT_OK, EXIT_ALARM, EXIT_USAGE = 0, 1, 2


def err(message: str, *, file: str | None = None, code: str = "USAGE") -> None:
    """One error line on stderr: ``file: error CODE: message`` (``trcopt`` without a file)."""
    print(f"{file or 'trcopt'}: error {code}: {message}", file=sys.stderr)


def err_exc(exc: TrcoptError, file: str | None = None) -> None:
    """A :class:`TrcoptError` as an error line (at its place in a file when it has one)."""
    print(exc.format(file), file=sys.stderr)


def check_outputs(
    paths: Sequence[str | os.PathLike[str] | None], inputs: Sequence[str | os.PathLike[str]] = ()
) -> str | None:
    """Why the output files ``paths`` (None entries ignored) cannot be written, or None.

    Checked before any work starts: a path that is a folder, a path given twice, a path that is
    one of the ``inputs``, a parent that is a file or a folder that cannot be created or written.
    Missing parent folders are fine (they are created when the outputs are written).
    """
    seen: dict[Path, str] = {}
    sources = {Path(p).resolve() for p in inputs}
    for raw in paths:
        if raw is None:
            continue
        path = Path(raw)
        full = path.resolve()
        if full in seen:
            return f"{raw}: given for two outputs"
        seen[full] = str(raw)
        if full in sources:
            return f"{raw}: an output would overwrite an input"
        if path.is_dir():
            return f"{raw}: is a folder (an output is a file)"
        parent = full.parent
        while not parent.exists():
            parent = parent.parent
        if not parent.is_dir():
            return f"{raw}: {parent} is not a folder"
        if not os.access(parent, os.W_OK | os.X_OK):
            return f"{raw}: folder {parent} is not writable"
    return None
