"""M120 LA n: the TNC's radius-compensated look-ahead, as the shared engine's collision detection.

With ``M120 LA n`` the TNC calculates the radius-compensated path n blocks ahead of the current
block, checks it for undercuts and tool-path intersections, and does not machine the pieces of
the contour the tool would damage (a step or a slot narrower than the tool, an inside arc
smaller than the tool). That is the engine's bottleneck detection (SINUMERIK ``CDON``, spec
R26): the tool-centre path of a block is intersected with the paths of the following blocks up
to a limit, and the blocks in between are omitted (warning 10763; without M120 an omission stays
the profile's "Tool radius too large" error). The limit is the block's LA
instead of the machine datum MD20240, so the reader gives each move of an M120 section
``CollisionMode.CDON`` and its LA (:class:`LookAheadMove`); a move without an LA (a plain
:class:`~trcopt.nc.model.Move`) keeps the engine's settings.

:func:`compensate_heidenhain` runs the engine with the per-block limit under the Heidenhain
profile (as :func:`~trcopt.compensation.profiles.compensate_with_profile` does with the plain
engine). A bottleneck that LA blocks do not reach stays "Tool radius too large".
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, fields

from trcopt.codes import Code
from trcopt.compensation.elements import Elem, Piece
from trcopt.compensation.engine import Compensator
from trcopt.compensation.junctions import JunctionResolver
from trcopt.compensation.lookahead import Join, Pending, Window
from trcopt.compensation.profiles import ControllerProfile, map_diagnostic, mapped_stream
from trcopt.config import TrcSettings
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.nc.model import Move
from trcopt.path import Segment

__all__ = ["LookAheadMove", "lookahead_of", "compensate_heidenhain", "M120_OMITTED"]

M120_OMITTED = "M120: contour piece not machined, the tool would damage the contour (block omitted)"


@dataclass(frozen=True, slots=True)
class LookAheadMove(Move):
    """A move under ``M120 LA n``: ``lookahead`` = n, the blocks the control calculates ahead."""

    lookahead: int = 0

    @classmethod
    def of(cls, move: Move, lookahead: int) -> LookAheadMove:
        """``move`` under ``M120 LA lookahead``."""
        return cls(**{f.name: getattr(move, f.name) for f in fields(move)}, lookahead=lookahead)


def lookahead_of(move: Move) -> int:
    """The M120 look-ahead of a move (0: none, the engine's own limit applies)."""
    return move.lookahead if isinstance(move, LookAheadMove) else 0


class _Resolver(JunctionResolver):
    """The engine's junction rules with the search limit of the block being resolved: its LA."""

    @contextmanager
    def _limit(self, elem: Elem | None) -> Iterator[None]:
        n = lookahead_of(elem.move) if elem is not None else 0
        if not n:
            yield
            return
        saved = self.settings
        self.settings = saved.with_(cutcom_maxnum_check_blocks=n)
        try:
            yield
        finally:
            self.settings = saved

    def collision(
        self, win: Window, i: int, chain: list[Piece], j_adjacent: int
    ) -> tuple[int, tuple[int, float], list[Piece]] | None:
        with self._limit(win.get(i)):
            return super().collision(win, i, chain, j_adjacent)

    def _search_beyond(
        self, win: Window, i: int, chain: list[Piece], pending: Pending | None, reason: str
    ) -> Join:
        with self._limit(win.get(i)):
            return super()._search_beyond(win, i, chain, pending, reason)


class _Compensator(Compensator):
    def __init__(self, settings: TrcSettings, diagnostics: list[Diagnostic], complete: bool = True) -> None:
        super().__init__(settings, diagnostics, complete)
        self.junctions = _Resolver(settings)


def compensate_heidenhain(
    moves: Iterable[Move],
    profile: ControllerProfile,
    settings: TrcSettings | None = None,
    diagnostics: list[Diagnostic] | None = None,
    complete: bool = True,
) -> Iterator[Segment]:
    """The engine with the per-block M120 limit under ``profile``: diagnostics mapped by the
    profile, and a warning the profile maps to an error stops the stream."""
    out = diagnostics if diagnostics is not None else []
    raw: list[Diagnostic] = []
    under_m120: set[SourceSpan] = set()

    def watched() -> Iterator[Move]:
        for m in moves:
            if lookahead_of(m):
                under_m120.add(m.span)
            yield m

    def mapped(d: Diagnostic) -> Diagnostic:
        if d.alarm == 10763 and d.span in under_m120:
            return Diagnostic(Severity.WARNING, Code.ALARM_10763, M120_OMITTED, d.span, 10763)
        return map_diagnostic(profile, d)

    engine = _Compensator(profile.engine_settings(settings), raw, complete)
    yield from mapped_stream(engine.run(watched()), raw, out, mapped)
