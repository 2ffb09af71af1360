"""Atomic output of text and bytes: a failure never leaves a half-written file behind.

The content goes to a temporary file in the destination's folder (same file system, so the final
``os.replace`` is atomic) which then replaces the destination in one step.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from trcopt.codes import Code
from trcopt.errors import TrcoptError

__all__ = ["OutputError", "write_text_atomic", "write_bytes_atomic"]


class OutputError(TrcoptError, OSError):
    """An output file could not be written; ``path`` names it."""

    def __init__(
        self, message: str, path: str | os.PathLike[str] | None = None, code: Code | str = Code.OUTPUT
    ) -> None:
        super().__init__(message, None, code)
        self.path = None if path is None else os.fspath(path)


def write_text_atomic(path: str | os.PathLike[str], text: str, *, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically and return the path.

    Parameters
    ----------
    path:
        Destination file; its folder must exist.
    text:
        Complete file content (written with ``\\n`` line ends, no newline translation).
    encoding:
        Text encoding, UTF-8 by default.

    Raises
    ------
    OutputError
        The folder does not exist, is not writable, or the disk is full; the destination is left
        untouched and no temporary file remains.
    """
    return write_bytes_atomic(path, text.encode(encoding))


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically and return the path.

    Parameters
    ----------
    path:
        Destination file; its folder must exist.
    data:
        Complete file content (a rendered picture, or encoded text).

    Raises
    ------
    OutputError
        The folder does not exist, is not writable, or the disk is full; the destination is left
        untouched and no temporary file remains.
    """
    dest = Path(path)
    folder = dest.parent if str(dest.parent) else Path(".")
    tmp_name: str | None = None
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{dest.name}.", suffix=".tmp", dir=folder)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        # mkstemp creates 0600; give the file the permissions a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_name, 0o666 & ~umask)
        os.replace(tmp_name, dest)
        tmp_name = None
    except OSError as exc:
        raise OutputError(f"cannot write {dest}: {exc.strerror or exc}", dest) from exc
    finally:
        if tmp_name is not None:
            try:
                os.unlink(tmp_name)
            except OSError:
                pass
    return dest
