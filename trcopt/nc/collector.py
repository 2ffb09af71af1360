"""The cyclic garbage collector paused while a reader builds a program's moves.

A reader allocates a few objects per block and frees none of them until the program is read; the
objects hold no reference cycles, so the cyclic collector would only walk them again and again
(about 10 % of reading a long program). :func:`collector_paused` switches it off for a block of
code and restores it as it was, also on an exception.
"""

from __future__ import annotations

import gc
from collections.abc import Callable, Iterator
from contextlib import contextmanager

__all__ = ["collector_paused", "kept_from_collector"]


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


@contextmanager
def kept_from_collector() -> Iterator[Callable[[], None]]:
    """A ``with`` block whose ``freeze()`` (the value of the ``with``) takes every object alive at
    that moment out of the cyclic collector's walks (:func:`gc.freeze`) until the block ends
    (:func:`gc.unfreeze`: they are collectable again, nothing is kept for good). A plan calls it once
    its program is read and compensated: the million objects of a long program are otherwise walked
    by every full collection the later stages trigger."""
    frozen = False

    def freeze() -> None:
        nonlocal frozen
        gc.freeze()
        frozen = True

    try:
        yield freeze
    finally:
        if frozen:
            gc.unfreeze()
