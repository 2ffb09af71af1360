"""The lines of a program text by number without a list of them: :class:`TextLines`.

A list of the lines of a million-block program is a million string objects (tens of MB); a stage
that reads one line at a time, or looks up the source line of a block, needs only where each line
starts: one array of offsets, each line cut from the text when it is asked for. The lines are
those an editor numbers (:func:`trcopt.nc.text.program_lines`: split at LF, CR LF and CR only, a
final line end starts no line), so that line ``n`` is the line of a span with ``line=n``.
"""

from __future__ import annotations

import re
from array import array
from collections.abc import Iterator, Sequence
from typing import Any

__all__ = ["TextLines", "iter_lines"]

_LINE_END = re.compile(r"\r\n|\r|\n")


class TextLines(Sequence[str]):
    """``program_lines(text)`` as a sequence made on demand (same length, same items)."""

    def __init__(self, text: str) -> None:
        self.text = text
        if text.isascii() and len(text) > _VECTOR_FROM:
            starts, ends = _ascii_bounds(text)
        else:
            starts, ends = array("q", [0]), array("q")
            for m in _LINE_END.finditer(text):
                ends.append(m.start())
                starts.append(m.end())
        if starts[-1] == len(text):  # a final line end starts no line
            starts.pop()
        else:
            ends.append(len(text))
        self._starts, self._ends = starts, ends

    def __len__(self) -> int:
        return len(self._starts)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return self.text[self._starts[i] : self._ends[i]]  # an index out of range: IndexError


def iter_lines(text: str) -> Iterator[str]:
    """The lines of :class:`TextLines` one by one, found as they are asked for (a search for the
    first line that says something reads only up to it)."""
    start = 0
    for m in _LINE_END.finditer(text):
        yield text[start : m.start()]
        start = m.end()
    if start < len(text):
        yield text[start:]


_VECTOR_FROM = 1 << 16  # characters from which the line ends of an ASCII text are found with NumPy


def _ascii_bounds(text: str) -> tuple[array[int], array[int]]:
    """Line starts (with 0 and the start after the last end) and ends of an ASCII text, as the
    loop over ``_LINE_END`` finds them, found as whole arrays."""
    import numpy as np

    b = np.frombuffer(text.encode("ascii"), np.uint8)
    lf = np.flatnonzero(b == 10)
    cr = np.flatnonzero(b == 13)
    crlf = (lf > 0) & (b[np.maximum(lf - 1, 0)] == 13)  # an LF after a CR: one line end, at the CR
    lone_cr = cr[(cr + 1 >= len(b)) | (b[np.minimum(cr + 1, len(b) - 1)] != 10)]
    ends = np.concatenate((lf - crlf, lone_cr))
    after = np.concatenate((lf + 1, lone_cr + 1))
    order = np.argsort(ends, kind="stable")
    ends, after = ends[order], after[order]
    starts = array("q", [0])
    starts.frombytes(after.astype(np.int64).tobytes())
    out = array("q")
    out.frombytes(ends.astype(np.int64).tobytes())
    return starts, out
