"""The cyclic garbage collector paused while a reader builds a program's moves.

A reader allocates a few objects per block and frees none of them until the program is read; the
objects hold no reference cycles, so the cyclic collector would only walk them again and again
(about 10 % of reading a long program). :func:`collector_paused` switches it off for a block of
code and restores it as it was, also on an exception.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["collector_paused"]


@contextmanager
def collector_paused() -> Iterator[None]:
    """Run the ``with`` block with the cyclic garbage collector off (restored as it was)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()
