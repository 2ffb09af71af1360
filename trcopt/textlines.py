"""The lines of a program text by number without a list of them: :class:`TextLines`.

A list of the lines of a million-block program is a million string objects (tens of MB); a stage
that reads one line at a time, or looks up the source line of a block, needs only where each line
starts: one array of offsets (4 bytes a line) and one byte a line for the length of its line end,
each line cut from the text when it is asked for. The lines are those an editor numbers
(:func:`trcopt.nc.text.program_lines`: split at LF, CR LF and CR only, a final line end starts no
line), so that line ``n`` is the line of a span with ``line=n``.
"""

from __future__ import annotations

import re
from array import array
from bisect import bisect_right
from collections.abc import Iterator, Sequence
from typing import Any

__all__ = ["TextLines", "iter_lines"]

_LINE_END = re.compile(r"\r\n|\r|\n")
_VECTOR_FROM = 1 << 16  # characters from which the line ends of an ASCII text are found with NumPy
_CHUNK = 1 << 20  # characters of an ASCII text looked at at once (the temporary arrays stay small)


class TextLines(Sequence[str]):
    """``program_lines(text)`` as a sequence made on demand (same length, same items)."""

    def __init__(self, text: str) -> None:
        self.text = text
        # the start of every line and, after the last, the start of the line that would follow
        # (the text's length + 1 when the text does not end with a line end); the length of
        # every line's end beyond one character (1 for CR LF)
        self._starts = array("i" if len(text) < 2**31 - 2 else "q", [0])
        self._long = bytearray()
        if text.isascii() and len(text) > _VECTOR_FROM:
            self._ascii(text)
        else:
            for m in _LINE_END.finditer(text):
                self._starts.append(m.end())
                self._long.append(m.end() - m.start() - 1)
        if self._starts[-1] != len(text):  # a last line without a line end
            self._starts.append(len(text) + 1)
            self._long.append(0)
        self._n = len(self._long)

    def _ascii(self, text: str) -> None:
        """The line ends of an ASCII text as whole arrays, over chunks that end just after an LF
        (no CR LF is cut)."""
        import numpy as np

        at = 0
        while at < len(text):
            stop = text.find("\n", at + _CHUNK)
            stop = len(text) if stop < 0 else stop + 1
            b = np.frombuffer(text[at:stop].encode("ascii"), np.uint8)
            lf = np.flatnonzero(b == 10)
            cr = np.flatnonzero(b == 13)
            crlf = (lf > 0) & (b[np.maximum(lf - 1, 0)] == 13)  # an LF after a CR: one line end
            lone_cr = cr[(cr + 1 >= len(b)) | (b[np.minimum(cr + 1, len(b) - 1)] != 10)]
            after = np.concatenate((lf + 1, lone_cr + 1))
            long = np.concatenate((crlf, np.zeros(len(lone_cr), bool)))
            order = np.argsort(after, kind="stable")
            self._starts.frombytes((after[order] + at).astype(self._starts.typecode).tobytes())
            self._long.extend(long[order].astype(np.uint8).tobytes())
            at = stop

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self._n))]
        if i < 0:
            i += self._n
        if not 0 <= i < self._n:
            raise IndexError(i)
        return self.text[self._starts[i] : self._starts[i + 1] - 1 - self._long[i]]

    def index_of(self, offset: int) -> int:
        """The index of the line at character ``offset`` of the text (a line end belongs to its line)."""
        return bisect_right(self._starts, offset, 0, self._n) - 1


def iter_lines(text: str) -> Iterator[str]:
    """The lines of :class:`TextLines` one by one, found as they are asked for (a search for the
    first line that says something reads only up to it)."""
    start = 0
    for m in _LINE_END.finditer(text):
        yield text[start : m.start()]
        start = m.end()
    if start < len(text):
        yield text[start:]
