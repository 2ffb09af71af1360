"""Atomic output of text and bytes: a failure never leaves a half-written file behind.

The content goes to a temporary file in the destination's folder (same file system, so the final
``os.replace`` is atomic) which then replaces the destination in one step.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

from trcopt.codes import Code
from trcopt.errors import TrcoptError

__all__ = [
    "OutputError", "StagedFile", "stage_chunks", "write_text_atomic", "write_bytes_atomic", "write_chunks_atomic",
]


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
    return write_chunks_atomic(path, (data,))


def write_chunks_atomic(
    path: str | os.PathLike[str], chunks: Iterable[bytes | str], *, encoding: str = "utf-8"
) -> Path:
    """Write the pieces ``chunks`` (bytes, or text encoded in ``encoding``) one after the other to
    ``path`` atomically and return the path: the file is complete or not there, and the content
    is never held whole in memory (:func:`stage_chunks`, then :meth:`StagedFile.commit`).

    Raises
    ------
    OutputError
        As :func:`write_bytes_atomic`. An exception raised while the pieces are produced (an
        error of the writer, ``KeyboardInterrupt``) propagates; either way the destination is
        left untouched and no temporary file remains.
    """
    return stage_chunks(path, chunks, encoding=encoding).commit()


class StagedFile:
    """A complete output in a temporary file beside its destination, not yet in place: several
    outputs are staged first and put in place together (:meth:`commit`) or not at all
    (:meth:`discard`)."""

    def __init__(self, dest: Path, tmp_name: str) -> None:
        self.dest, self.tmp_name = dest, tmp_name

    def commit(self) -> Path:
        """Put the file in place (``os.replace``, atomic) and return its path."""
        try:
            # mkstemp creates 0600; give the file the permissions a plain open() would
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(self.tmp_name, 0o666 & ~umask)
            os.replace(self.tmp_name, self.dest)
        except OSError as exc:
            self.discard()
            raise OutputError(f"cannot write {self.dest}: {exc.strerror or exc}", self.dest) from exc
        return self.dest

    def discard(self) -> None:
        """Remove the temporary file (the destination is left as it was)."""
        try:
            os.unlink(self.tmp_name)
        except OSError:
            pass


def stage_chunks(path: str | os.PathLike[str], chunks: Iterable[bytes | str], *, encoding: str = "utf-8") -> StagedFile:
    """Write ``chunks`` to a temporary file beside ``path`` (flushed to disk) and return it staged.

    Raises
    ------
    OutputError
        The folder does not exist, is not writable, or the disk is full. Whatever is raised
        (also by the producer of the pieces), no temporary file remains.
    """
    dest = Path(path)
    folder = dest.parent if str(dest.parent) else Path(".")
    tmp_name: str | None = None
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{dest.name}.", suffix=".tmp", dir=folder)
        with os.fdopen(fd, "wb") as fh:
            for chunk in chunks:
                fh.write(chunk.encode(encoding) if isinstance(chunk, str) else chunk)
            fh.flush()
            os.fsync(fh.fileno())
        staged = StagedFile(dest, tmp_name)
        tmp_name = None
        return staged
    except OSError as exc:
        raise OutputError(f"cannot write {dest}: {exc.strerror or exc}", dest) from exc
    finally:
        if tmp_name is not None:
            try:
                os.unlink(tmp_name)
            except OSError:
                pass
