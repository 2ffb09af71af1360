"""The Klartext reader's contour elements as moves: :class:`MoveMaker` (one element → one
:class:`~trcopt.nc.model.Move`) and :class:`ElementOutput` (the elements of a program read block by
block, given as moves as soon as nothing can change them any more).

An element is final once the reader has added the next one (RND/CHF trim the element before them,
a block without motion adds its M functions to it). A final element is given when the "tool
radius too large" check (:func:`~.contour.radius_too_large`, region by region as
:meth:`~.reader.HeidenhainReader._check_radius` cuts the whole program) can no longer cut the
program before it: that check runs along (:class:`~.contour.RegionCheck`); the elements from the
first place it may still cut at (the last element of the open region, or a problem that a later
one may outrank) and those of the same block before it are held. Once the check cuts, the elements
from the cut on are dropped; the reader's error diagnostics from the cut block on make way for the
check's error when the program ends (:meth:`ElementOutput.diagnostics`).
"""

from __future__ import annotations

from collections.abc import Callable

from trcopt.codes import Code
from trcopt.controllers.heidenhain.contour import TOOL_RADIUS_TOO_LARGE, Elem, RegionCheck
from trcopt.controllers.heidenhain.m120 import LookAheadMove
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.plane import Plane
from trcopt.modes import CollisionMode, CornerMode, Side
from trcopt.nc.model import EXACT_PATH, CompState, Move, MoveKind, PathControl

__all__ = ["MoveMaker", "ElementOutput"]


class MoveMaker:
    """Elements → moves in program order: the path control in force (``controls``: (executed
    block, path control from there on), as the reader collects them), M97 of the element before
    (intersection at the corner), the M120 look-ahead; the first M90 is warned about (``warn``)."""

    def __init__(
        self, controls: list[tuple[int, PathControl]], plane: Callable[[], Plane],
        warn: Callable[[Code, str, SourceSpan], None],
    ) -> None:  # fmt: skip
        self.controls, self.plane, self.warn = controls, plane, warn
        self.next_control = 0
        self.control = EXACT_PATH
        self.m97_before = False
        self.warned_m90 = False

    def move(self, e: Elem) -> Move:
        seq = e.extra.get("seq", 0)
        assert isinstance(seq, int)
        controls = self.controls
        while self.next_control < len(controls) and controls[self.next_control][0] <= seq:
            self.control = controls[self.next_control][1]
            self.next_control += 1
        if "M90" in e.actions and not self.warned_m90:
            self.warned_m90 = True
            self.warn(
                Code.NC_PATH_CONTROL,
                "M90 (constant contouring speed at corners in servo-lag operation) is not modelled; "
                "the corners are planned with a stop as without a path-control mode",
                e.span,
            )
        plane = e.extra.get("plane")
        if plane is None:
            plane = self.plane()
        assert isinstance(plane, Plane)
        lookahead = e.extra.get("lookahead", 0) if e.side is not Side.OFF else 0
        assert isinstance(lookahead, int)
        comp = CompState(
            side=e.side,
            radius=e.radius,
            tool_active=e.tool_active,
            corner=CornerMode.INTERSECTION if self.m97_before else CornerMode.TRANSITION_CIRCLE,
            collision=CollisionMode.CDON if lookahead else CollisionMode.CDOF,
            side_programmed=e.side_programmed,
        )
        self.m97_before = e.m97
        center = None
        if e.center is not None:
            center = plane.to_xyz((e.center[0], e.center[1], e.start[2]))
        actions = e.actions + (("M97",) if e.m97 and "M97" not in e.actions else ())
        move = Move(
            e.kind,
            plane.to_xyz(e.start),
            plane.to_xyz(e.end),
            plane,
            e.span,
            comp,
            e.feed,
            center,
            e.ccw if e.kind is MoveKind.ARC else None,
            e.turns,
            actions,
            origin=e.origin,
            control=self.control,
        )
        return LookAheadMove.of(move, lookahead) if lookahead else move


class ElementOutput:
    """The final elements of a program read block by block → its moves (module docstring):
    :meth:`add` each final element in order, :meth:`ready` gives the moves that can be given,
    :meth:`end` the rest when the program has ended."""

    def __init__(self, maker: MoveMaker) -> None:
        self.maker = maker
        self.pending: list[Elem] = []  # final elements not given yet, from place `base` on
        self.base = 0
        self.region: RegionCheck | None = None
        self.cut: tuple[Elem, int | None, str] | None = None  # the first element cut, its diag mark, detail
        self._out: list[Elem] = []

    def add(self, e: Elem) -> None:
        """The next final element (as :meth:`~.reader.HeidenhainReader._check_radius` walks them)."""
        if self.cut is not None:
            return  # the program is cut before it
        at = self.base + len(self.pending)
        self.pending.append(e)
        moving = e.kind is MoveKind.ARC or vec.dist(e.start[:2], e.end[:2]) > 1e-9
        if e.side is Side.OFF:
            if moving:
                self._close()
            return
        if self.region is None:
            self.region = RegionCheck()  # the selection line
            return
        if e.extra.get("lookahead"):
            # under M120 the look-ahead leaves out what the tool cannot machine (engine CDON)
            self._close()
            if self.cut is None:
                self.region = RegionCheck()
            return
        if moving:
            self.region.add(e, at)
            if self.region.arc is not None:
                self._cut(self.region.arc)

    def ready(self) -> list[Move]:
        """The moves of the elements that the check can no longer cut."""
        pending = self.pending
        if self.cut is None and len(pending) > 1:
            # the block of the last element may go on with the next one: held with it
            bound = self._block_start(self.base + len(pending) - 1)
            if self.region is not None:
                held = self.region.open_from
                if held is not None and held < bound:
                    bound = self._block_start(held)
            if bound > self.base:
                self._out.extend(pending[: bound - self.base])
                del pending[: bound - self.base]
                self.base = bound
        if not self._out:
            return []
        move = self.maker.move
        out = [move(e) for e in self._out]
        self._out.clear()
        return out

    def end(self) -> list[Move]:
        """The moves left once every element is added: the last region is checked whole."""
        self._close()
        if self.cut is None:
            self._out.extend(self.pending)
            self.pending.clear()
        return self.ready()

    def diagnostics(self, diags: list[Diagnostic]) -> list[Diagnostic]:
        """The reader's diagnostics ``diags`` after a cut (as ``_check_radius`` leaves them)."""
        if self.cut is None:
            return diags
        bad, mark, detail = self.cut
        if mark is None:
            mark = len(diags)
        kept = [d for i, d in enumerate(diags) if d.severity is not Severity.ERROR or i < mark]
        message = f"{TOOL_RADIUS_TOO_LARGE}: {detail}"
        return [*kept, Diagnostic(Severity.ERROR, Code.HH_TOOL_RADIUS_TOO_LARGE, message, bad.span)]

    def _close(self) -> None:
        region, self.region = self.region, None
        if region is None or self.cut is not None:
            return
        region.end()
        if region.found is not None:
            self._cut(region.found)

    def _cut(self, found: tuple[int, str]) -> None:
        """The check cuts at the element at place ``found[0]``: the whole block goes."""
        at, detail = found
        bad = self.pending[at - self.base]
        cut = self._block_start(at)
        first = self.pending[cut - self.base]
        mark = first.extra.get("diag_mark")
        assert mark is None or isinstance(mark, int)
        self.cut = (bad, mark, detail)
        self._out.extend(self.pending[: cut - self.base])
        self.pending.clear()
        self.region = None

    def _block_start(self, at: int) -> int:
        """The first place of the elements before ``at`` that are of the same block (the same
        span and executed block) as the element at ``at``."""
        pending, base = self.pending, self.base
        e = pending[at - base]
        span, seq = e.span, e.extra.get("seq")
        while at > base and pending[at - 1 - base].span == span and pending[at - 1 - base].extra.get("seq") == seq:
            at -= 1
        return at
