"""The look-ahead vocabulary of the engine: the window over a region's elements, the record of a
resolved junction, and the intersection searches on tool-centre chains.

* :class:`Window` — the bounded look-ahead buffer (MD20240 blocks) over one region's elements;
* :class:`Join` — how block i ends and block j starts (trim, inserted pieces, omitted blocks,
  backward trim of the previous block);
* :data:`Pending` — a resolved block waiting to be emitted;
* :func:`first_hit` — where a chain first meets the chain of a later block;
* :func:`walk_first` / :func:`walk_hit` — the first point met walking along an auxiliary element
  (G461 circle, G462 line);
* :func:`trim_end`, :func:`restart`, :func:`line_distance` — the small edits and measures these
  searches share.

Parameters λ are the pieces' own (0 at the carrier's start, 1 at its end); lengths in mm.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

from trcopt.compensation.elements import LAM_TOL, Elem, Piece
from trcopt.geometry import vec
from trcopt.geometry.intersect import intersections
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2

__all__ = [
    "Window",
    "Join",
    "Pending",
    "trim_end",
    "first_hit",
    "walk_first",
    "walk_hit",
    "restart",
    "line_distance",
]

Pending = tuple[Elem, list[Piece], list[Elem]]
"""A resolved block not yet emitted: its element, its tool-centre chain and the blocks omitted
after it. A later junction may still trim its chain (CDOF backward search)."""

# the window keeps this many elements before dropping the ones behind the current block
_WINDOW_KEEP = 16


class Window:
    """Look-ahead buffer over the elements of one region, indexed by block number in the region."""

    def __init__(self, source: Iterator[Elem]) -> None:
        self._src = source
        self._buf: dict[int, Elem] = {}
        self._hi = -1
        self._done = False

    def get(self, k: int) -> Elem | None:
        """Element k (read from the source as far as needed); None after the region's end."""
        while k > self._hi and not self._done:
            try:
                e = next(self._src)
            except StopIteration:
                self._done = True
                break
            self._hi += 1
            self._buf[self._hi] = e
        return self._buf.get(k)

    def drop_below(self, k: int) -> None:
        """Forget the elements before k (once the buffer has grown past a few blocks)."""
        if len(self._buf) > _WINDOW_KEEP:
            for key in [key for key in self._buf if key < k]:
                del self._buf[key]


@dataclass(slots=True)
class Join:
    """How block i ends and block j starts."""

    j: int
    next_chain: list[Piece]
    end: tuple[int, float] | None = None  # trim block i's chain at (piece index, λ)
    trailing: list[Piece] = field(default_factory=list)
    replace: list[Piece] | None = None  # replace block i's chain entirely
    omitted: list[int] = field(default_factory=list)
    backward: tuple[int, float] | None = None  # trim the previous block's chain here; omit block i
    backward_point: Vec2 | None = None  # ... or end the previous block's last piece at this point


def trim_end(chain: list[Piece], end: tuple[int, float]) -> None:
    """End ``chain`` at (piece index, λ): later pieces are dropped; a negative index counts from
    the end."""
    k, lam = end
    if k < 0:
        k += len(chain)
    del chain[k + 1 :]
    chain[k].lam1 = lam
    chain[k].p1 = None


def first_hit(chain: list[Piece], full: list[Piece], tol: float) -> tuple[int, float, list[Piece]] | None:
    """Where ``chain`` first meets the chain ``full`` of a later block, nearest the start of
    ``full``; returns (piece index in chain, λ there, the rest of ``full`` from the hit).

    A meeting point within ``tol`` (mm) of the chain's start does not count.
    """
    start_pt = chain[0].start_point()
    best: tuple[int, float, int, float] | None = None
    for k, piece in enumerate(chain):
        carrier_a = piece.end_carrier()
        lo_a, hi_a = min(piece.lam0, piece.lam1), max(piece.lam0, piece.lam1)
        for m, q in enumerate(full):
            lo_b, hi_b = min(q.lam0, q.lam1), max(q.lam0, q.lam1)
            for h in intersections(carrier_a, q.start_carrier(), 1e-9):
                if not (lo_a - LAM_TOL <= h.lam_a <= hi_a + LAM_TOL):
                    continue
                if not (lo_b - LAM_TOL <= h.lam_b <= hi_b + LAM_TOL):
                    continue
                if vec.dist(h.point, start_pt) <= tol:
                    continue
                key = (m, h.lam_b, k, h.lam_a)
                if best is None or key[:2] < best[:2]:
                    best = key
    if best is None:
        return None
    m, lam_b, k, lam_a = best
    rest = full[m:]
    rest[0] = restart(rest[0], lam_b)
    return k, lam_a, rest


def walk_first(aux: Line | Arc, pieces: list[Piece], use_end: bool) -> tuple[int, float, Vec2] | None:
    """First point met walking along ``aux`` that lies on one of ``pieces``: (piece index, λ on
    that piece, point)."""
    best: tuple[float, int, float, Vec2] | None = None
    for m, q in enumerate(pieces):
        lo, hi = min(q.lam0, q.lam1), max(q.lam0, q.lam1)
        carrier = q.end_carrier() if use_end else q.start_carrier()
        for h in intersections(aux, carrier, 1e-9):
            if h.lam_a > 1e-9 and lo - LAM_TOL <= h.lam_b <= hi + LAM_TOL and (best is None or h.lam_a < best[0]):
                best = (h.lam_a, m, h.lam_b, h.point)
    return None if best is None else (best[1], best[2], best[3])


def walk_hit(aux: Line | Arc, full: list[Piece]) -> tuple[Vec2, list[Piece]] | None:
    """First point met walking along ``aux`` on the chain ``full``, and the rest of the chain."""
    met = walk_first(aux, full, use_end=False)
    if met is None:
        return None
    m, lam_b, point = met
    rest = full[m:]
    rest[0] = restart(rest[0], lam_b)
    return point, rest


def restart(piece: Piece, lam: float) -> Piece:
    """A copy of ``piece`` that starts at λ = ``lam`` (its fixed start point dropped)."""
    return Piece(piece.elem, piece.role, lam, piece.lam1, piece.main, piece.carrier, None, piece.p1)


def line_distance(line: Line, p: Vec2) -> float:
    """Distance (mm) from p to the carrier (infinite line) of ``line``."""
    d = line.direction2()
    return abs(vec.cross(d, vec.sub(p, line.start2)))
