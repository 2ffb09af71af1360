"""What a reader that runs block by block needs of a program's lines without a list of them.

* :class:`OnDemand` — a sequence whose items (a line's statement, its lexed block) are made when
  asked for, a few thousand kept for a loop that runs its lines again;
* :func:`lines_matching` — the lines of a text in which a pattern occurs, found by searching the
  text as a whole (a reader's index of labels or structure keywords is made of those lines only).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

from trcopt.textlines import TextLines

__all__ = ["OnDemand", "lines_matching", "KEEP"]

T = TypeVar("T")
KEEP = 4096  # items an OnDemand sequence keeps
AHEAD = 512  # items made together (≤ KEEP)
_CHUNK = 1 << 22  # characters of a text searched at once


class OnDemand(Sequence[T]):
    """``n`` items, item ``i`` made by ``make(i)`` when it is asked for, with the :data:`AHEAD` - 1
    after it; of the items made, item ``i`` is kept until an item ``j`` with ``j % keep == i % keep``
    is made (``make`` must give equal items for equal ``i``: a kept item is given again)."""

    def __init__(self, n: int, make: Callable[[int], T], keep: int = KEEP) -> None:
        self._n, self.make, self._keep = n, make, keep
        self._at: list[int] = [-1] * keep  # the index of the item kept in each place
        self._items: list[Any] = [None] * keep

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self._n))]
        if i < 0:
            i += self._n
        place = i % self._keep
        if self._at[place] == i:
            return self._items[place]
        if not 0 <= i < self._n:
            raise IndexError(i)
        # the items after it are made with it: a program runs on (made in a run, they run faster)
        make, at, items, keep = self.make, self._at, self._items, self._keep
        for j in range(i, min(i + AHEAD, self._n)):
            p = j % keep
            if at[p] != j:
                items[p] = make(j)
                at[p] = j
        return items[place]


def lines_matching(lines: TextLines, pattern: re.Pattern[bytes]) -> Iterator[int]:
    """The indices, in order and each once, of the lines of ``lines.text`` in which ``pattern``
    matches the text with its ASCII letters in upper case (every other character is one byte
    ``?``, so that the offsets stay). A match must not span a line end."""
    text = lines.text
    start, last = 0, -1
    while start < len(text):
        stop = text.find("\n", start + _CHUNK)  # chunks end after a line end
        stop = len(text) if stop < 0 else stop + 1
        chunk = text[start:stop].encode("ascii", "replace").upper()
        for m in pattern.finditer(chunk):
            i = lines.index_of(start + m.start())
            if i != last:
                last = i
                yield i
        start = stop
