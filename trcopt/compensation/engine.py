"""The SINUMERIK-style 2D tool radius compensation engine (spec R1–R30).

The engine streams: it reads canonical moves one by one and keeps only a bounded look-ahead window
(MD20240 blocks) plus the previous resolved block, so memory does not grow with program length.

Per compensation region (selection block … deselection block) the blocks are numbered: 0 is the
selection (approach) block, then the contour blocks, then the deselection (retract) block. Each
block's tool-centre *chain* (inserted elements + its offset) is resolved at its end against the
next block (corner rules), against later blocks (predictive search, CDON bottleneck detection)
and, when nothing is found, against the previous block (CDOF backward search) — then emitted.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

from trcopt.compensation import corners as cn
from trcopt.compensation.elements import Elem, ElemKind, Piece, make_programmed_geometry
from trcopt.config import TrcSettings
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan, alarm
from trcopt.geometry import vec
from trcopt.geometry.intersect import intersections
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.modes import ApproachMode, ApproachStrategy, CollisionMode, Side
from trcopt.nc.model import Move, MoveKind
from trcopt.path import Role, Segment

__all__ = ["compensate", "Compensator", "programmed_segment"]

LAM_TOL = 1e-9


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
    def __init__(self, it: Iterator[Move]) -> None:
        self._it = it

    def next(self) -> Move | None:
        return next(self._it, None)


class _Window:
    """Look-ahead buffer over the elements of one region."""

    def __init__(self, source: Iterator[Elem]) -> None:
        self._src = source
        self._buf: dict[int, Elem] = {}
        self._hi = -1
        self._done = False

    def get(self, k: int) -> Elem | None:
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
        if len(self._buf) > 16:
            for key in [key for key in self._buf if key < k]:
                del self._buf[key]


@dataclass(slots=True)
class _Join:
    """How block i ends and block j starts."""

    j: int
    next_chain: list[Piece]
    end: tuple[int, float] | None = None  # trim block i's chain at (piece index, λ)
    trailing: list[Piece] = field(default_factory=list)
    replace: list[Piece] | None = None  # replace block i's chain entirely
    omitted: list[int] = field(default_factory=list)
    backward: tuple[int, float] | None = None  # trim the previous block's chain here; omit block i
    backward_point: Vec2 | None = None  # ... or end the previous block's last piece at this point


def programmed_segment(m: Move, tol: float = 1e-3) -> Segment | None:
    """The uncompensated segment of a move (None for a block without motion)."""
    if m.kind is MoveKind.NONE or (m.start == m.end and m.kind is not MoveKind.ARC):
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


def _plane_moving(m: Move, tol: float) -> bool:
    kind = m.kind
    if kind is MoveKind.NONE:
        return False
    if kind is MoveKind.ARC:
        return True
    iu, iv, _ = m.plane.axes
    a, b = m.start, m.end
    return math.hypot(b[iu] - a[iu], b[iv] - a[iv]) > tol


def _side_of(m: Move) -> int:
    """+1 / −1 / 0 after the sign normalisation (a negative radius swaps the side)."""
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

    # ------------------------------------------------------------------ driver
    def run(self, moves: Iterable[Move]) -> Iterator[Segment]:
        it = _Peekable(iter(moves))
        try:
            while True:
                m = it.next()
                if m is None:
                    return
                if _side_of(m) == 0 or not _plane_moving(m, self.tol):
                    yield from self._passthrough(m)
                    continue
                yield from self._region(m, it)
        except AlarmError as exc:
            self.diagnostics.append(exc.diagnostic)

    def _alarm(self, number: int, message: str, span: SourceSpan) -> AlarmError:
        return AlarmError(alarm(number, message, span))

    def _warn(self, code: str, message: str, span: SourceSpan, number: int | None = None) -> None:
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
            if not _plane_moving(m, self.tol):
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
                        "TRC-SIDE-CHANGE",
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
        win = _Window(self._elements(first, it))
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
        pending: tuple[Elem, list[Piece], list[Elem]] | None = None
        try:
            while True:
                a = win.get(i)
                assert a is not None
                b = win.get(i + 1)
                if b is None:
                    if self.complete:
                        self._warn(
                            "TRC-ACTIVE-AT-END",
                            "program ends with tool radius compensation active (no G40 block)",
                            a.span,
                        )
                    if pending is not None:
                        yield from self._emit(*pending)
                        pending = None
                    yield from self._emit(a, chain, [])
                    return
                join = self._junction(win, i, chain, pending)
                if (join.backward is not None or join.backward_point is not None) and pending is not None:
                    prev_elem, prev_chain, prev_omitted = pending
                    if join.backward is not None:
                        self._trim_end(prev_chain, join.backward)
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
                        self._trim_end(chain, join.end)
                    chain.extend(join.trailing)
                    col = self._collision(win, i, chain, join.j) if a.comp.collision is CollisionMode.CDON else None
                    if col is not None:
                        j2, end, next_chain = col
                        self._trim_end(chain, end)
                        join = _Join(j2, next_chain, omitted=list(range(i + 1, j2)))
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
            "10763",
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
                    "TRC-CONTOUR-VIOLATION",
                    "possible contour violation: the offset of this block runs against its programmed "
                    "direction (bottleneck not detected with CDOF; use CDON)",
                    a.span,
                )

    @staticmethod
    def _trim_end(chain: list[Piece], end: tuple[int, float]) -> None:
        k, lam = end
        if k < 0:
            k += len(chain)
        del chain[k + 1 :]
        chain[k].lam1 = lam
        chain[k].p1 = None

    # ------------------------------------------------------------------ junctions
    def _junction(
        self, win: _Window, i: int, chain: list[Piece], pending: tuple[Elem, list[Piece], list[Elem]] | None
    ) -> _Join:
        a = win.get(i)
        b = win.get(i + 1)
        assert a is not None and b is not None
        if a.kind is ElemKind.APPROACH:
            return self._approach(a, b)
        if b.kind is ElemKind.RETRACT:
            return self._retract(a, b, i)
        if b.degenerate:
            return self._search_beyond(win, i, chain, pending, reason="degenerate")
        kind, delta = cn.classify(a, b, self.settings)
        if kind is cn.JunctionKind.TANGENTIAL:
            # the offsets meet within the coincidence tolerance: join them at their intersection
            # next to the joint; without one (exactly parallel), a straight side takes the other's
            # end point, so the path has no gap (only an arc-to-arc joint keeps its ≤ 1 µm)
            last = chain[-1]
            joint = last.end_point()
            near = [h for h in intersections(a.off_end, b.off_start) if vec.dist(h.point, joint) <= 10 * self.tol]
            if near and last.main:
                best = min(near, key=lambda h: vec.dist(h.point, joint))
                return _Join(i + 1, [Piece(b, b.role, best.lam_b, 1.0)], end=(len(chain) - 1, best.lam_a))
            nxt = Piece(b, b.role, 0.0, 1.0)
            if isinstance(b.prog, Line):
                nxt.p0 = last.end_point()
            elif last.main and isinstance(a.prog, Line) and last.lam1 == 1.0:
                last.p1 = b.off_start.point2(0.0)
            return _Join(i + 1, [nxt])
        if kind is cn.JunctionKind.OUTSIDE:
            mode, disc = cn.corner_mode_for(a, b)
            out = cn.outside_corner(a, b, delta, self.settings, mode, disc)
            end = None if out.lam_a is None else (len(chain) - 1, out.lam_a)
            return _Join(i + 1, out.leading + [Piece(b, b.role, out.lam_b, 1.0)], end=end)
        return self._inside(win, i, chain, pending)

    def _approach(self, a: Elem, b: Elem) -> _Join:
        p0, p1 = (a.prog.start[0], a.prog.start[1]), (a.prog.end[0], a.prog.end[1])
        mode = a.comp.approach
        t1 = b.start_tangent()
        s_point = b.off_start.point2(0.0)
        if mode in (ApproachMode.KONTT, ApproachMode.KONTC):
            if a.move.kind is not MoveKind.LINE:
                raise AlarmError(
                    Diagnostic(
                        Severity.ERROR,
                        "TRC-KONTT-BLOCK",
                        f"{mode.value} needs a G1 approach block",
                        a.span,
                    )
                )
            piece = cn.approach_polynomial(a, b, mode is ApproachMode.KONTC)
            return _Join(b.index, [Piece(b, b.role, 0.0, 1.0)], replace=[piece])
        if mode is ApproachMode.KONT and cn.behind(p1, p0, t1, a.side):
            if vec.dist(p0, p1) <= a.r1:
                raise self._alarm(10755, "KONT approach not possible: start point within the tool radius", a.span)
            delta = vec.deflection(vec.unit(vec.sub(p1, p0)), t1)
            corner, disc = cn.corner_mode_for(a, b)
            out = cn.outside_corner(
                a, b, delta, self.settings, corner, disc, arc_owner_is_a=True, arc_role=Role.APPROACH
            )
            end = None if out.lam_a is None else (0, out.lam_a)
            return _Join(b.index, [Piece(b, b.role, out.lam_b, 1.0)], end=end, trailing=out.trailing)
        # NORM (and KONT in front): straight to S = P1 + R·n1
        return _Join(b.index, [Piece(b, b.role, 0.0, 1.0)], replace=[Piece(a, Role.APPROACH, 0.0, 1.0, p1=s_point)])

    def _retract(self, a: Elem, b: Elem, i: int) -> _Join:
        e_pt, t_pt = (b.prog.start[0], b.prog.start[1]), (b.prog.end[0], b.prog.end[1])
        mode = b.comp.approach
        t_e = a.end_tangent()
        if mode in (ApproachMode.KONTT, ApproachMode.KONTC):
            if b.move.kind is not MoveKind.LINE:
                raise AlarmError(
                    Diagnostic(Severity.ERROR, "TRC-KONTT-BLOCK", f"{mode.value} needs a G1 retraction block", b.span)
                )
            return _Join(i + 1, [cn.retract_polynomial(a, b, mode is ApproachMode.KONTC)])
        if mode is ApproachMode.KONT and cn.behind(e_pt, t_pt, t_e, a.side):
            if vec.dist(t_pt, e_pt) <= b.r0:
                raise self._alarm(10756, "KONT retraction not possible: end point within the tool radius", b.span)
            delta = vec.deflection(t_e, vec.unit(vec.sub(t_pt, e_pt)))
            corner, disc = cn.corner_mode_for(a, b)
            out = cn.outside_corner(a, b, delta, self.settings, corner, disc, arc_role=Role.RETRACT)
            end = None if out.lam_a is None else (-1, out.lam_a)
            return _Join(i + 1, out.leading + [Piece(b, b.role, out.lam_b, 1.0)], end=end)
        return _Join(i + 1, [Piece(b, Role.RETRACT, 0.0, 1.0, p0=a.off_end.point2(1.0))])

    def _inside(
        self, win: _Window, i: int, chain: list[Piece], pending: tuple[Elem, list[Piece], list[Elem]] | None
    ) -> _Join:
        """R25: inside corner — bounded intersection with the next block (nearest its start)."""
        b = win.get(i + 1)
        assert b is not None
        best: tuple[float, int, float] | None = None
        for k, piece in enumerate(chain):
            lo = min(0.0, piece.lam0) if piece.main else None
            for h in piece.hits(b.off_start, use_end=True, lo=lo):
                if -LAM_TOL <= h.lam_b <= 1.0 + LAM_TOL and (best is None or h.lam_b < best[0]):
                    best = (h.lam_b, k, h.lam_a)
        if best is not None:
            lam_b, k, lam_a = best
            return _Join(i + 1, [Piece(b, b.role, max(lam_b, 0.0), 1.0)], end=(k, lam_a))
        return self._search_beyond(win, i, chain, pending, reason="inside")

    def _search_beyond(
        self,
        win: _Window,
        i: int,
        chain: list[Piece],
        pending: tuple[Elem, list[Piece], list[Elem]] | None,
        reason: str,
    ) -> _Join:
        """R25.3/R25.4/R30: predictive search over later blocks, then backwards; else 10751."""
        a = win.get(i)
        assert a is not None
        if reason == "degenerate" and a.comp.collision is not CollisionMode.CDON:
            b = win.get(i + 1)
            assert b is not None
            raise self._alarm(10751, "collision danger: inside arc smaller than the tool radius", b.span)
        n = self.settings.cutcom_maxnum_check_blocks
        for j in range(i + 2, i + n + 1):
            c = win.get(j)
            if c is None:
                break
            if c.degenerate:
                continue
            if c.kind is ElemKind.RETRACT and c.comp.strategy is not ApproachStrategy.G460:
                break  # R31: only G460 includes the retraction block in the search
            found = self._first_hit(chain, self._full_chain(win, j))
            if found is None and c.kind is not ElemKind.RETRACT:
                collinear = self._collinear_join(chain, c.off_start)
                if collinear is not None:
                    found = (collinear[1], collinear[2], [Piece(c, c.role, 0.0, 1.0)])
            if found is not None:
                k, lam_a, rest = found
                return _Join(j, rest, end=(k, lam_a), omitted=list(range(i + 1, j)))
            if c.kind is ElemKind.RETRACT:
                break
        b = win.get(i + 1)
        assert b is not None
        # CDOF backward search: the next block's offset against the previous block's chain
        if (
            pending is not None
            and a.kind is ElemKind.CONTOUR
            and (pending[0].kind is not ElemKind.APPROACH or pending[0].comp.strategy is ApproachStrategy.G460)
        ):
            prev_elem, prev_chain, _ = pending
            best2: tuple[float, int, float] | None = None
            for k, piece in enumerate(prev_chain):
                for h in piece.hits(b.off_start, use_end=True):
                    if -LAM_TOL <= h.lam_b <= 1.0 + LAM_TOL and (best2 is None or h.lam_b < best2[0]):
                        best2 = (h.lam_b, k, h.lam_a)
            if best2 is not None:
                lam_b, k, lam_a = best2
                return _Join(i + 1, [Piece(b, b.role, lam_b, 1.0)], backward=(k, lam_a))
        strategy_join = self._strategy_extension(win, i, chain, pending)
        if strategy_join is not None:
            return strategy_join
        raise self._alarm(
            10751,
            "collision danger: no intersection of the tool-centre path found "
            f"within {n} blocks (MD20240)",
            a.span,
        )

    def _collinear_join(self, chain: list[Piece], target: object) -> tuple[float, int, float] | None:
        """Offsets on one straight line, same direction (a degenerate block between two collinear
        lines): the path continues straight to the start of the later block."""
        last = chain[-1]
        carrier = last.end_carrier()
        if not (isinstance(carrier, Line) and isinstance(target, Line)):
            return None
        da, db = carrier.direction2(), target.direction2()
        if abs(vec.cross(da, db)) > 1e-12 or vec.dot(da, db) <= 0.0:
            return None
        if carrier.distance2(target.start2) > self.tol and _line_distance(carrier, target.start2) > self.tol:
            return None
        lam_a = carrier.param_of(target.start2)
        if lam_a < last.lam0 - LAM_TOL:
            return None
        return (0.0, len(chain) - 1, lam_a)

    def _strategy_extension(
        self, win: _Window, i: int, chain: list[Piece], pending: tuple[Elem, list[Piece], list[Elem]] | None
    ) -> _Join | None:
        """What the approach/retraction strategy makes of an unresolved first or last corner.

        KONT with the start/end point behind the contour (R35): the inserted bypass element or the
        straight approach/retraction line meets the neighbouring block. Otherwise G461/G462
        (R32–R34): the first (last) block's offset is extended by an auxiliary circle around its
        programmed start (end) point or by its tangent, intersected with the following (preceding)
        blocks; the block itself is omitted. G460 has no such extension (alarm 10751, §D-13).
        """
        a = win.get(i)
        b = win.get(i + 1)
        assert a is not None and b is not None
        n = self.settings.cutcom_maxnum_check_blocks
        if pending is not None and pending[0].kind is ElemKind.APPROACH:
            app, app_chain, _ = pending
            p0, p1 = (app.prog.start[0], app.prog.start[1]), (app.prog.end[0], app.prog.end[1])
            if app.comp.approach is ApproachMode.KONT and cn.behind(p1, p0, a.start_tangent(), a.side):
                hit = self._first_hit(app_chain, self._full_chain(win, i + 1))
                if hit is None:
                    return None
                k, lam, rest = hit
                return _Join(i + 1, rest, backward=(k, lam))
            strategy = app.comp.strategy
            if strategy is ApproachStrategy.G460:
                return None
            start = a.off_start.point2(0.0)
            back = (-a.start_tangent()[0], -a.start_tangent()[1])
            aux = _auxiliary(strategy, (a.prog.start[0], a.prog.start[1]), start, back, a.r0)
            found: tuple[int, Vec2, list[Piece]] | None = None
            for j in range(i + 1, i + n + 1):
                c = win.get(j)
                if c is None:
                    break
                hit2 = _walk_hit(aux, self._full_chain(win, j))
                if hit2 is not None:
                    found = (j, hit2[0], hit2[1])
                    if a.comp.collision is not CollisionMode.CDON:
                        break
                if c.kind is ElemKind.RETRACT:
                    break
            if found is None:
                return None
            j, point, rest = found
            return _Join(j, rest, backward_point=point, omitted=list(range(i + 1, j)))
        r = win.get(i + 2)
        if r is not None and r.kind is ElemKind.RETRACT:
            e_pt = (r.prog.start[0], r.prog.start[1])
            if self._retract_behind(b, r):
                hit = self._first_hit(chain, self._full_chain(win, i + 2))
                if hit is None:
                    return None
                k, lam, rest = hit
                return _Join(i + 2, rest, end=(k, lam), omitted=[i + 1])
            strategy = r.comp.strategy
            if strategy is ApproachStrategy.G460:
                return None
            aux = _auxiliary(strategy, e_pt, b.off_end.point2(1.0), b.end_tangent(), b.r1)
            met = _walk_first(aux, chain, use_end=True)
            if met is None:
                return None
            k, lam, point = met
            return _Join(i + 2, [Piece(r, Role.RETRACT, 0.0, 1.0, p0=point)], end=(k, lam), omitted=[i + 1])
        return None

    @staticmethod
    def _retract_behind(last: Elem, r: Elem) -> bool:
        """KONT retraction with the end point behind the contour (R14, R18)."""
        e_pt, t_pt = (r.prog.start[0], r.prog.start[1]), (r.prog.end[0], r.prog.end[1])
        return r.comp.approach is ApproachMode.KONT and cn.behind(e_pt, t_pt, last.end_tangent(), last.side)

    def _search_carrier(self, win: _Window, j: int):  # type: ignore[no-untyped-def]
        """The geometry block j is searched with (the actual line for a NORM retraction)."""
        c = win.get(j)
        assert c is not None
        if c.kind is ElemKind.RETRACT:
            prev = win.get(j - 1)
            if prev is not None:
                p = prev.off_end.point2(1.0)
                return Line((p[0], p[1], c.prog.start[2]), c.prog.end)
        return c.off_start

    # ------------------------------------------------------------------ collision detection
    def _full_chain(self, win: _Window, j: int) -> list[Piece]:
        """Block j's chain as the adjacent corner rules build it (untrimmed at inside corners)."""
        c = win.get(j)
        prev = win.get(j - 1)
        assert c is not None and prev is not None
        if c.kind is ElemKind.RETRACT:
            if self._retract_behind(prev, c):
                lead = self._retract(prev, c, j - 1)  # bypass circle / extension, then the line
                ext = [Piece(prev, prev.role, 1.0, lead.end[1])] if lead.end is not None else []
                return ext + lead.next_chain
            carrier = self._search_carrier(win, j)
            return [Piece(c, Role.RETRACT, 0.0, 1.0, main=False, carrier=carrier)]
        if prev.kind is ElemKind.APPROACH or prev.degenerate:
            return [Piece(c, c.role, 0.0, 1.0)]
        kind, delta = cn.classify(prev, c, self.settings)
        if kind is cn.JunctionKind.OUTSIDE:
            mode, disc = cn.corner_mode_for(prev, c)
            out = cn.outside_corner(prev, c, delta, self.settings, mode, disc)
            return out.leading + [Piece(c, c.role, out.lam_b, 1.0)]
        return [Piece(c, c.role, 0.0, 1.0)]

    def _first_hit(self, chain: list[Piece], full: list[Piece]) -> tuple[int, float, list[Piece]] | None:
        """Where ``chain`` first meets the chain ``full`` of a later block, nearest the start of
        ``full``; returns (piece index in chain, λ there, the rest of ``full`` from the hit)."""
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
                    if vec.dist(h.point, start_pt) <= self.tol:
                        continue
                    key = (m, h.lam_b, k, h.lam_a)
                    if best is None or key[:2] < best[:2]:
                        best = key
        if best is None:
            return None
        m, lam_b, k, lam_a = best
        rest = full[m:]
        rest[0] = _restart(rest[0], lam_b)
        return k, lam_a, rest

    def _collision(
        self, win: _Window, i: int, chain: list[Piece], j_adjacent: int
    ) -> tuple[int, tuple[int, float], list[Piece]] | None:
        """R26 CDON: the last later block (up to MD20240) whose chain the chain of block i meets."""
        a = win.get(i)
        assert a is not None
        if a.comp.collision is not CollisionMode.CDON or a.kind is ElemKind.RETRACT:
            return None
        if a.kind is ElemKind.APPROACH and a.comp.strategy is not ApproachStrategy.G460:
            return None
        n = self.settings.cutcom_maxnum_check_blocks
        found: tuple[int, tuple[int, float], list[Piece]] | None = None
        for j in range(max(i + 2, j_adjacent + 1), i + n + 1):
            c = win.get(j)
            if c is None:
                break
            if c.kind is ElemKind.RETRACT and c.comp.strategy is not ApproachStrategy.G460:
                break
            if not c.degenerate:
                hit = self._first_hit(chain, self._full_chain(win, j))
                if hit is not None:
                    found = (j, (hit[0], hit[1]), hit[2])
            if c.kind is ElemKind.RETRACT:
                break
        return found

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

AUX_LINE_MM = 1.0e5  # length of the G462 tangent extension searched for an intersection


def _auxiliary(strategy: ApproachStrategy, center: Vec2, start: Vec2, direction: Vec2, radius: float) -> Line | Arc:
    """G461: the circle of the tool radius around the programmed point, walked from ``start`` in
    ``direction``; G462: the straight extension from ``start`` along ``direction``."""
    if strategy is ApproachStrategy.G462 or radius <= 0.0:
        end = (start[0] + AUX_LINE_MM * direction[0], start[1] + AUX_LINE_MM * direction[1], 0.0)
        return Line((start[0], start[1], 0.0), end)
    radial = vec.sub(start, center)
    ccw = vec.dot(vec.rot90(radial), direction) > 0.0
    sweep = (2.0 * math.pi - 1e-9) * (1.0 if ccw else -1.0)
    return Arc(center, vec.norm(radial), math.atan2(radial[1], radial[0]), sweep)


def _walk_first(aux: Line | Arc, pieces: list[Piece], use_end: bool) -> tuple[int, float, Vec2] | None:
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


def _walk_hit(aux: Line | Arc, full: list[Piece]) -> tuple[Vec2, list[Piece]] | None:
    """First point met walking along ``aux`` on the chain ``full``, and the rest of the chain."""
    met = _walk_first(aux, full, use_end=False)
    if met is None:
        return None
    m, lam_b, point = met
    rest = full[m:]
    rest[0] = _restart(rest[0], lam_b)
    return point, rest


def _line_distance(line: Line, p: Vec2) -> float:
    """Distance from p to the carrier (infinite line) of ``line``."""
    d = line.direction2()
    return abs(vec.cross(d, vec.sub(p, line.start2)))


def _restart(piece: Piece, lam: float) -> Piece:
    return Piece(piece.elem, piece.role, lam, piece.lam1, piece.main, piece.carrier, None, piece.p1)
