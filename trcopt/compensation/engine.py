"""The streaming driver of the SINUMERIK-style 2D tool radius compensation engine (spec R1–R30).

The engine streams: it reads canonical moves one by one and keeps only a bounded look-ahead window
(MD20240 blocks) plus the previous resolved block, so memory does not grow with program length.

Per compensation region (selection block … deselection block) the blocks are numbered: 0 is the
selection (approach) block, then the contour blocks, then the deselection (retract) block. Each
block's tool-centre *chain* (inserted elements + its offset) is resolved at its end against the
next block (corner rules), against later blocks (predictive search, CDON bottleneck detection)
and, when nothing is found, against the previous block (CDOF backward search) — then emitted.

This module owns the stream: which moves pass through uncompensated, the elements of a region and
the alarms of reading them (10750, 10753, 10754, 10757, 10758, 10762, ``TRC-SIDE-CHANGE``; 10751
for a first arc smaller than the tool), the order in which resolved blocks are emitted (a block
waits until the next junction can no longer trim it), the contour-violation check (R28), the
omission warnings (10763) and the segments of a resolved block. How a block ends is
:mod:`trcopt.compensation.junctions`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator

from trcopt.codes import Code
from trcopt.compensation.elements import LAM_TOL, Elem, ElemKind, Piece, make_programmed_geometry
from trcopt.compensation.junctions import JunctionResolver
from trcopt.compensation.lookahead import Join, Pending, Window, trim_end
from trcopt.config import TrcSettings
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan, alarm
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Line
from trcopt.geometry.vec import Vec2
from trcopt.modes import CollisionMode, Side
from trcopt.nc.model import Move, MoveKind
from trcopt.path import Role, Segment, new_segment

__all__ = ["compensate", "Compensator", "programmed_segment"]


def compensate(
    moves: Iterable[Move],
    settings: TrcSettings | None = None,
    diagnostics: list[Diagnostic] | None = None,
    complete: bool = True,
) -> Iterator[Segment]:
    """Tool-centre segments for canonical moves; diagnostics are appended to ``diagnostics``.

    An error-severity alarm stops the stream (the segments up to the alarm have been yielded).
    ``complete=False`` says the moves stop early (the front end raised an error), so a region
    still open at the end is not reported as a program without G40.
    """
    comp = Compensator(settings or TrcSettings(), diagnostics if diagnostics is not None else [], complete)
    return comp.run(moves)


class _Peekable:
    """The move stream; :meth:`next` gives None at its end."""

    def __init__(self, it: Iterator[Move]) -> None:
        self._it = it

    def next(self) -> Move | None:
        return next(self._it, None)


_LINE, _RAPID, _NONE, _G17 = MoveKind.LINE, MoveKind.RAPID, MoveKind.NONE, Plane.G17


def programmed_segment(m: Move, tol: float = 1e-3) -> Segment | None:
    """The uncompensated segment of a move (None for a block without motion)."""
    kind = m.kind
    if (kind is _LINE or kind is _RAPID) and m.plane is _G17 and not m.origin:
        # the common straight move in G17, as _any_programmed_segment makes it
        start, end = m.start, m.end
        if start == end:
            return None
        if kind is _RAPID:
            role = Role.RAPID
        elif math.hypot(end[0] - start[0], end[1] - start[1]) <= tol:  # Line.plane_length
            role = Role.POSITIONING
        else:
            role = Role.CONTOUR
        return new_segment(Line(start, end), _G17, role, m.span, m.feed_mm_s)
    return _any_programmed_segment(m, tol)


def makes_segment(m: Move) -> bool:
    """Whether :func:`programmed_segment` of ``m`` is a segment (not None), without making it."""
    kind = m.kind
    return kind is not _NONE and (kind is MoveKind.ARC or m.start != m.end)


def _any_programmed_segment(m: Move, tol: float) -> Segment | None:
    """:func:`programmed_segment` of any move."""
    kind = m.kind
    if kind is _NONE or (m.start == m.end and kind is not MoveKind.ARC):
        return None
    geom = make_programmed_geometry(m)
    if m.origin == "approach":
        role = Role.APPROACH
    elif m.origin == "retract":
        role = Role.RETRACT
    elif m.kind is MoveKind.RAPID:
        role = Role.RAPID
    elif geom.plane_length <= tol and m.kind is MoveKind.LINE:
        role = Role.POSITIONING
    else:
        role = Role.CONTOUR
    return Segment(geom, m.plane, role, m.span, m.feed_mm_s)


def _side_of(m: Move) -> int:
    """+1 / −1 / 0 after the sign normalisation (a negative radius swaps the side)."""
    # = m.comp.effective_side.sign, spelled out: it runs for every move and the two property
    # calls cost ~2 % of the engine's time
    c = m.comp
    side = c.side
    if side is Side.OFF:
        return 0
    s = 1 if side is Side.LEFT else -1
    return -s if c.radius < 0.0 else s


class Compensator:
    """Streams canonical moves into tool-centre segments (see module docstring)."""

    def __init__(self, settings: TrcSettings, diagnostics: list[Diagnostic], complete: bool = True) -> None:
        self.settings = settings
        self.diagnostics = diagnostics
        self.complete = complete
        self.tol = settings.tolerances.coincidence_mm
        self.junctions = JunctionResolver(settings)

    # ------------------------------------------------------------------ driver
    def run(self, moves: Iterable[Move]) -> Iterator[Segment]:
        it = _Peekable(iter(moves))
        try:
            while True:
                m = it.next()
                if m is None:
                    return
                if _side_of(m) == 0 or not m.moves_in_plane(self.tol):
                    yield from self._passthrough(m)
                    continue
                yield from self._region(m, it)
        except AlarmError as exc:
            self.diagnostics.append(exc.diagnostic)

    def _alarm(self, number: int, message: str, span: SourceSpan) -> AlarmError:
        return AlarmError(alarm(number, message, span))

    def _warn(self, code: Code, message: str, span: SourceSpan, number: int | None = None) -> None:
        if number == 10763 and self.settings.suppress_10763:
            return
        self.diagnostics.append(Diagnostic(Severity.WARNING, code, message, span, number))

    def _passthrough(self, m: Move) -> Iterator[Segment]:
        seg = programmed_segment(m, self.tol)
        if seg is not None:
            yield seg

    # ------------------------------------------------------------------ region elements
    def _elements(self, first: Move, it: _Peekable) -> Iterator[Elem]:
        s = _side_of(first)
        radius = first.comp.effective_radius
        if first.kind is MoveKind.ARC:
            raise self._alarm(10753, "tool radius compensation selected in a circular block (G2/G3)", first.span)
        if not first.comp.tool_active:
            raise self._alarm(10750, "tool radius compensation selected without an active tool (T/D)", first.span)
        yield Elem(0, ElemKind.APPROACH, first, make_programmed_geometry(first), s, 0.0, radius)
        index = 0
        dummies: list[Move] = []
        prev_r = radius
        while True:
            m = it.next()
            if m is None:
                return
            if not m.moves_in_plane(self.tol):
                if m.plane is not first.plane and m.comp.side is not Side.OFF:
                    raise self._alarm(10757, "plane change while tool radius compensation is active", m.span)
                dummies.append(m)
                limit = self.settings.cutcom_maxnum_dummy_blocks
                # generated lead sub-blocks (SAR P1→P2→P3) do not count against MD20250 (§D-20)
                if sum(1 for d in dummies if not d.origin) > limit:
                    raise self._alarm(
                        10762, f"too many blocks without plane motion in a row (> MD20250 = {limit})", m.span
                    )
                continue
            index += 1
            geom = make_programmed_geometry(m)
            side_m = _side_of(m)
            if side_m == 0:
                if m.kind is MoveKind.ARC:
                    raise self._alarm(10754, "tool radius compensation deselected in a circular block", m.span)
                yield Elem(index, ElemKind.RETRACT, m, geom, s, prev_r, 0.0, dummies)
                return
            if m.plane is not first.plane:
                raise self._alarm(10757, "plane change while tool radius compensation is active", m.span)
            if side_m != s:
                raise AlarmError(
                    Diagnostic(
                        Severity.ERROR,
                        Code.TRC_SIDE_CHANGE,
                        "compensation side changed (G41↔G42) without G40 in between; program G40 first",
                        m.span,
                    )
                )
            r = abs(m.comp.radius)
            elem = Elem(index, ElemKind.CONTOUR, m, geom, s, prev_r, r, dummies)
            if elem.variable and elem.degenerate:
                raise self._alarm(
                    10758, "curvature radius too small for the variable compensation value", m.span
                )
            yield elem
            prev_r = r
            dummies = []

    # ------------------------------------------------------------------ region processing
    def _region(self, first: Move, it: _Peekable) -> Iterator[Segment]:
        win = Window(self._elements(first, it))
        e0 = win.get(0)
        assert e0 is not None
        e1 = win.get(1)
        if e1 is None or e1.kind is ElemKind.RETRACT:
            # R3.5: G40 right after the selection block — no selection at all
            yield from self._passthrough(first)
            if e1 is not None:
                for d in e1.dummies:
                    yield from self._passthrough(d)
                yield from self._passthrough(e1.move)
            return
        if e1.degenerate:
            raise self._alarm(10751, "collision danger: first compensated arc is smaller than the tool", e1.span)

        i = 0
        chain = [Piece(e0, Role.APPROACH, 0.0, 1.0)]
        pending: Pending | None = None
        try:
            while True:
                a = win.get(i)
                assert a is not None
                b = win.get(i + 1)
                if b is None:
                    if self.complete:
                        self._warn(
                            Code.TRC_ACTIVE_AT_END,
                            "program ends with tool radius compensation active (no G40 block)",
                            a.span,
                        )
                    if pending is not None:
                        yield from self._emit(*pending)
                        pending = None
                    yield from self._emit(a, chain, [])
                    return
                join = self.junctions.resolve(win, i, chain, pending)
                if (join.backward is not None or join.backward_point is not None) and pending is not None:
                    prev_elem, prev_chain, prev_omitted = pending
                    if join.backward is not None:
                        trim_end(prev_chain, join.backward)
                    else:
                        prev_chain[-1].p1 = join.backward_point
                    skipped = [a] + [e for e in (win.get(k) for k in join.omitted) if e is not None]
                    pending = (prev_elem, prev_chain, prev_omitted + skipped)
                    for e in skipped:
                        self._omit_warning(e)
                else:
                    if join.replace is not None:
                        chain = join.replace
                    if join.end is not None:
                        trim_end(chain, join.end)
                    chain.extend(join.trailing)
                    col = None
                    if a.comp.collision is CollisionMode.CDON:
                        col = self.junctions.collision(win, i, chain, join.j)
                    if col is not None:
                        j2, end, next_chain = col
                        trim_end(chain, end)
                        join = Join(j2, next_chain, omitted=list(range(i + 1, j2)))
                    self._check_reversal(a, chain)
                    omitted = [o for o in (win.get(k) for k in join.omitted) if o is not None] if join.omitted else []
                    for o in omitted:
                        self._omit_warning(o)
                    if pending is not None:
                        yield from self._emit(*pending)
                    pending = (a, chain, omitted)
                i = join.j
                chain = join.next_chain
                win.drop_below(i - 1)
                nxt = win.get(i)
                assert nxt is not None
                if nxt.kind is ElemKind.RETRACT:
                    if pending is not None:
                        yield from self._emit(*pending)
                        pending = None
                    yield from self._emit(nxt, chain, [])
                    return
        except AlarmError:
            if pending is not None:
                yield from self._emit(*pending)
            raise

    def _omit_warning(self, e: Elem) -> None:
        self._warn(
            Code.ALARM_10763,
            "block omitted by collision detection: its plane path is not traversed (bottleneck)",
            e.span,
            10763,
        )

    def _check_reversal(self, a: Elem, chain: list[Piece]) -> None:
        """R28: an element whose remaining offset runs against its programmed direction."""
        if a.kind is not ElemKind.CONTOUR:
            return
        for p in chain:
            if p.main and p.lam1 < p.lam0 - LAM_TOL and a.kind is ElemKind.CONTOUR:
                if self.settings.strict:
                    raise self._alarm(10751, "collision danger: offset element runs reversed", a.span)
                self._warn(
                    Code.TRC_CONTOUR_VIOLATION,
                    "possible contour violation: the offset of this block runs against its programmed "
                    "direction (bottleneck not detected with CDOF; use CDON)",
                    a.span,
                )

    # ------------------------------------------------------------------ emission
    def _emit(self, elem: Elem, chain: list[Piece], omitted: list[Elem]) -> list[Segment]:
        """The segments of a resolved block: its dummy blocks at the chain start, its pieces with
        one linear applicate ramp over their plane length (§D-9), the omitted blocks' content at
        the chain end (R27)."""
        side = Side.LEFT if elem.side > 0 else Side.RIGHT
        out: list[Segment] = []
        if elem.dummies:
            start_pt = chain[0].start_point() if chain else (elem.prog.start[0], elem.prog.start[1])
            out.extend(s for s in (self._at_point(d, start_pt, side, elem.r0) for d in elem.dummies) if s)
        w0, w1 = elem.prog.start[2], elem.prog.end[2]
        radius = elem.r1 if elem.kind is not ElemKind.RETRACT else elem.r0
        plane = elem.plane
        if w0 == w1 and len(chain) == 1:  # the common 2D case: one piece
            piece = chain[0]
            geom = piece.geometry(w0, w0)
            if geom.plane_length > 1e-12:
                move = piece.elem.move
                out.append(Segment(geom, plane, piece.role, move.span, move.feed_mm_s, side, radius))
        else:
            flat = [p.geometry(w0, w0) for p in chain]
            lengths = [g.plane_length for g in flat]
            total = sum(lengths)
            acc = 0.0
            for piece, length, geom in zip(chain, lengths, flat, strict=True):
                wa = w0 + (w1 - w0) * (acc / total if total > 0 else 0.0)
                acc += length
                wb = w0 + (w1 - w0) * (acc / total if total > 0 else 1.0)
                if length <= 1e-12 and abs(wb - wa) <= 1e-12:
                    continue
                if w1 != w0:
                    geom = piece.geometry(wa, wb)
                move = piece.elem.move
                out.append(Segment(geom, plane, piece.role, move.span, move.feed_mm_s, side, radius))
        if omitted:
            end_pt = chain[-1].end_point() if chain else (elem.prog.end[0], elem.prog.end[1])
            for o in omitted:
                for m in (*o.dummies, o.move):
                    seg = self._at_point(m, end_pt, side, o.r1)
                    if seg is not None:
                        out.append(seg)
        return out

    def _at_point(self, m: Move, p: Vec2, side: Side, radius: float) -> Segment | None:
        """A block without plane motion executed at plane point p (applicate motion only)."""
        if m.kind is MoveKind.NONE:
            return None
        w0 = m.plane.to_uvw(m.start)[2]
        w1 = m.plane.to_uvw(m.end)[2]
        if abs(w1 - w0) <= 1e-12:
            return None
        geom = Line((p[0], p[1], w0), (p[0], p[1], w1))
        if m.origin in ("approach", "retract"):
            role = Role(m.origin)
        else:
            role = Role.RAPID if m.kind is MoveKind.RAPID else Role.POSITIONING
        return Segment(geom, m.plane, role, m.span, m.feed_mm_s, side, radius)
