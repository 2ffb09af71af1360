"""The lines of a program text by number without a list of them: :class:`SourceLines`.

``str.splitlines()`` of a million-block program makes a million string objects (tens of MB); a
writer that looks up the source line of each block needs only their offsets: one array of
integers, each line cut from the text when it is asked for. The line breaks are exactly those of
``str.splitlines()``.
"""

from __future__ import annotations

import re
from array import array
from collections.abc import Sequence
from typing import Any

__all__ = ["SourceLines"]

# the line boundaries of str.splitlines()
_BREAK = re.compile("\r\n|[\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029]")


class SourceLines(Sequence[str]):
    """``text.splitlines()`` as a sequence made on demand (same length, same items)."""

    def __init__(self, text: str) -> None:
        self.text = text
        starts, ends = array("q", [0]), array("q")
        for m in _BREAK.finditer(text):
            ends.append(m.start())
            starts.append(m.end())
        if starts[-1] == len(text):  # no line after a final break
            starts.pop()
        else:
            ends.append(len(text))
        self._starts, self._ends = starts, ends

    def __len__(self) -> int:
        return len(self._starts)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(i)
        return self.text[self._starts[i] : self._ends[i]]
