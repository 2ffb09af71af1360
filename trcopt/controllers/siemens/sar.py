"""SINUMERIK smooth approach and retraction (SAR): SAR blocks → ordinary canonical moves.

A pre-pass between the NC front end and the compensation engine (spec §A.8, R36–R48). Each SAR
block — together with the block that defines P4 and the block that defines the tangent — is
expanded into the sub-movements P0→P1→P2→P3→P4 (retraction: P4→P3→P2→P1→P0), marked with
``origin="approach"``/``"retract"``. The compensation engine then handles the generated contour
exactly as if it had been programmed (R46): the activation (G41/G42) rides on P0→P1, the
applicate-only sub-moves are executed at the corner point, the lead circle is the internal
*programmed* circle of radius ρp = DISR + s·σ·R whose offset is the tool-centre radius DISR.

Feeds follow R43/R44 and §D-10/D-10a. Alarms (spec §A.9) are appended to ``diagnostics``; an
error stops the expansion (nothing is yielded after it). This module owns the expansion's state
and its order of sub-movements; the moves it builds and the tangents and feeds it reads from the
neighbouring blocks are :mod:`trcopt.controllers.siemens.sar_moves`, the lead geometry P0…P4 is
:func:`trcopt.compensation.leads.sar_points`.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import replace

from trcopt.codes import Code
from trcopt.compensation.leads import SarGeometry, sar_points
from trcopt.config import TrcSettings
from trcopt.controllers.siemens.sar_moves import (
    end_tangent,
    lead_move,
    programmed_feed,
    same_point,
    start_tangent,
    sub_move,
)
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan, alarm
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import LeadSegmentation, RetractEnd
from trcopt.nc.model import CompState, Move, MoveKind

__all__ = ["expand_sar", "PREPROCESSING_STOP"]

PREPROCESSING_STOP = Code.SAR_PREPROCESSING_STOP  # spec §A.9 gives no alarm number
_STOP_WORDS = ("STOPRE",)


def expand_sar(
    moves: Iterable[Move],
    settings: TrcSettings | None = None,
    diagnostics: list[Diagnostic] | None = None,
) -> Iterator[Move]:
    """Expand every SAR block into ordinary moves; other moves pass through unchanged.

    Parameters
    ----------
    moves:
        Canonical moves from :func:`trcopt.controllers.read_program` (program order).
    settings:
        Machine data: MD20202 ``wab_maxnum_dummy_blocks``, MD20204
        ``wab_clearance_tolerance_mm`` and the coincidence tolerance (mm).
    diagnostics:
        SAR alarms are appended here.

    Returns
    -------
    Iterator[Move]
        The same moves for a program without SAR; otherwise the SAR sub-movements in their place.
    """
    return _Expander(settings or TrcSettings(), diagnostics if diagnostics is not None else []).run(
        moves
    )


class _Stop(Exception):
    """An error alarm ended the expansion."""


class _Expander:
    def __init__(self, settings: TrcSettings, diagnostics: list[Diagnostic]) -> None:
        self.settings = settings
        self.diagnostics = diagnostics
        self.tol = settings.tolerances.coincidence_mm
        self.prev: Move | None = None  # the move before the current one (modal motion type, feed)
        self.modal_feed: float | None = None  # last F value in force, mm/s (also under G0)
        self.last_contour: Move | None = None  # last plane-moving move (retraction tangent)
        self.dummies_since_contour = 0
        self.restart: tuple[Vec3, Vec3] | None = None  # (front-end position, actual position)

    # ------------------------------------------------------------------ driver
    def run(self, moves: Iterable[Move]) -> Iterator[Move]:
        it = iter(moves)
        pending: list[Move] = []
        try:
            while True:
                m = pending.pop(0) if pending else next(it, None)
                if m is None:
                    return
                m = self._relocate(m)
                if m.sar is None:
                    self._note(m)
                    yield m
                elif m.sar.contour.is_approach:
                    out, rest = self._approach(m, it)
                    yield from out
                    pending = rest + pending
                else:
                    yield from self._retract(m)
        except _Stop:
            return

    def _fail(self, number: int | None, message: str, span: SourceSpan) -> _Stop:
        if number is None:
            self.diagnostics.append(Diagnostic(Severity.ERROR, PREPROCESSING_STOP, message, span))
        else:
            self.diagnostics.append(alarm(number, message, span))
        return _Stop()

    def _note(self, m: Move) -> None:
        """Track the modal state a later SAR block needs."""
        f = programmed_feed(m)
        if f is not None:
            self.modal_feed = f
        elif m.feed_mm_s is not None:
            self.modal_feed = m.feed_mm_s
        if m.moves_in_plane(self.tol):
            self.last_contour = m
            self.dummies_since_contour = 0
        elif m.kind is not MoveKind.NONE or m.actions:
            self.dummies_since_contour += 1
        self.prev = m

    def _relocate(self, m: Move) -> Move:
        """After a retraction that ends in P1/P2 the tool is not where the front end thinks.

        Axes a later block does not program keep the actual position; the correction ends when
        every axis has been programmed again (or at an arc, whose centre fixes its start).
        """
        if self.restart is None:
            return m
        front, actual = self.restart
        if not same_point(m.start, front, 1e-9) or m.kind is MoveKind.ARC:
            self.restart = None
            return m
        # an axis the block writes anew (its end differs from the front end's idea) is programmed
        (ex, ey, ez), (fx, fy, fz), (ax, ay, az) = m.end, front, actual
        end = (ax if ex == fx else ex, ay if ey == fy else ey, az if ez == fz else ez)
        differs = any(abs(f - a) > 1e-12 for f, a in zip(m.end, end, strict=True))
        self.restart = (m.end, end) if differs else None
        return replace(m, start=actual, end=end)

    def _points(
        self, sar: Move, p0: Vec3, p4: Vec3, t: Vec2, s: int, r: float, end_mode: RetractEnd = RetractEnd.PROGRAMMED
    ) -> SarGeometry:
        """The analytic SAR construction of block ``sar``; its alarm stops the expansion."""
        assert sar.sar is not None
        try:
            return sar_points(
                sar.sar,
                p0=p0,
                p4=p4,
                tangent=t,
                comp_side=s,
                radius=r,
                retract_end=end_mode,
                clearance_tolerance=self.settings.wab_clearance_tolerance_mm,
                span=sar.span,
            )
        except AlarmError as exc:
            self.diagnostics.append(exc.diagnostic)
            raise _Stop() from None

    # ------------------------------------------------------------------ approach
    def _approach(self, sar: Move, it: Iterator[Move]) -> tuple[list[Move], list[Move]]:
        assert sar.sar is not None
        limit = self.settings.wab_maxnum_dummy_blocks
        between: list[Move] = []  # blocks without plane motion between the SAR block and P4's block
        after: list[Move] = []  # ... between P4's block and the tangent block
        dummies = 0

        def pull(where: list[Move]) -> Move:
            nonlocal dummies
            while True:
                m = next(it, None)
                if m is None:
                    raise self._fail(
                        10744,
                        "no valid SAR direction: no traversing block follows the SAR block",
                        sar.span,
                    )
                if m.sar is not None:
                    raise self._fail(
                        10743,
                        "SAR programmed again before the approach direction is defined",
                        m.span,
                    )
                if any(a.upper().replace(" ", "") in _STOP_WORDS for a in m.actions):
                    raise self._fail(
                        None,
                        "preprocessing stop between the SAR block and the block that defines the "
                        "approach tangent",
                        m.span,
                    )
                if m.moves_in_plane(self.tol):
                    return m
                dummies += 1
                if dummies > limit:
                    raise self._fail(
                        10740,
                        f"too many blocks without traversing motion in SAR (> MD20202 = {limit})",
                        m.span,
                    )
                where.append(m)

        p4_block = sar if sar.moves_in_plane(self.tol) or sar.plane_programmed else pull(between)
        tangent_block = pull(after)
        plane = sar.plane
        t = start_tangent(tangent_block, plane)
        if t is None:
            raise self._fail(
                10744,
                "no valid SAR direction: the tangent block has no direction",
                tangent_block.span,
            )
        comp = sar.comp
        s = comp.effective_side.sign if comp.tool_active else 0
        r = comp.effective_radius if s else 0.0
        p0 = plane.to_uvw(sar.start)
        p4 = plane.to_uvw(p4_block.end)
        geo = self._points(sar, p0, p4, t, s, r)

        # feeds (R43, §D-10a)
        before_feed = (
            None if self.prev is None else self.prev.feed_mm_s
        )  # motion type before the SAR block
        before_kind = MoveKind.RAPID if before_feed is None else MoveKind.LINE
        f_sar = programmed_feed(sar)
        f_from = f_sar if f_sar is not None else self.modal_feed
        fad = sar.sar.fad[0] if sar.sar.fad is not None else None
        block_feed = p4_block.feed_mm_s if p4_block is not sar else None
        contour_feed = block_feed if block_feed is not None else f_from
        planar = sar.sar.segmentation is LeadSegmentation.PLANAR
        if planar:
            p23_feed = fad if fad is not None else f_from
        else:
            p23_feed = before_feed
            if fad is not None:
                contour_feed = fad

        sub = replace(comp, side_programmed=False)
        out: list[Move] = []
        pieces: list[tuple[Vec3, Vec3, MoveKind, float | None]] = [
            (geo.p0, geo.p1, before_kind, before_feed),
            (geo.p1, geo.p2, before_kind, before_feed),
        ]
        if planar:
            pieces.append(
                (
                    geo.p2,
                    geo.p3,
                    MoveKind.LINE if p23_feed is not None else MoveKind.RAPID,
                    p23_feed,
                )
            )
        first = True
        for a, b, kind, feed in pieces:
            if same_point(a, b, self.tol):
                continue
            out.append(
                sub_move(
                    plane,
                    a,
                    b,
                    kind=kind,
                    span=sar.span,
                    comp=comp if first else sub,
                    feed=feed,
                    actions=sar.actions if first else (),
                    origin="approach",
                )
            )
            first = False
        p3_xyz = plane.to_xyz(geo.p3)
        for d in between:  # executed where the SAR block's last sub-block ends (R45)
            out.append(replace(d, kind=MoveKind.NONE, start=p3_xyz, end=p3_xyz, origin="approach"))
        contour = lead_move(
            geo,
            plane,
            start=geo.p3,
            end=geo.p4,
            span=p4_block.span,
            comp=sub
            if first
            else (replace(p4_block.comp, side_programmed=False) if p4_block is not sar else sub),
            feed=contour_feed,
            actions=(sar.actions if first else ())
            + (p4_block.actions if p4_block is not sar else ()),
            origin="approach",
        )
        if (
            first
        ):  # every sub-move before the contour was dropped: the contour carries the selection
            contour = replace(contour, comp=comp)
        out.append(contour)
        for m in out:
            self._note(m)
        return out, after + [tangent_block]

    # ------------------------------------------------------------------ retraction
    def _retract(self, sar: Move) -> list[Move]:
        assert sar.sar is not None
        limit = self.settings.wab_maxnum_dummy_blocks
        last = self.last_contour
        if last is None:
            raise self._fail(
                10744, "no valid SAR direction: no contour block precedes the retraction", sar.span
            )
        if self.dummies_since_contour > limit:
            raise self._fail(
                10740,
                f"too many blocks without traversing motion in SAR (> MD20202 = {limit})",
                sar.span,
            )
        plane = sar.plane
        t = end_tangent(last, plane)
        if t is None:
            raise self._fail(
                10744, "no valid SAR direction: the last contour block has no direction", last.span
            )
        contour_comp = replace(
            self.prev.comp if self.prev is not None else last.comp, side_programmed=False
        )
        s = contour_comp.effective_side.sign if contour_comp.tool_active else 0
        r = contour_comp.effective_radius if s else 0.0
        u, v, w = plane.axes
        written = sar.sar.end_programmed
        if written[u] or written[v] or sar.plane_programmed:
            end_mode = RetractEnd.PROGRAMMED
        elif written[w]:
            end_mode = RetractEnd.APPLICATE_ONLY
        else:
            end_mode = RetractEnd.NONE
        p4 = plane.to_uvw(sar.start)
        geo = self._points(sar, plane.to_uvw(sar.end), p4, t, s, r, end_mode)

        # feeds (R44, §D-10): the old feed on the retraction contour, the SAR block's from P2 on
        old_feed = self.modal_feed
        fad = sar.sar.fad[0] if sar.sar.fad is not None else None
        planar = sar.sar.segmentation is LeadSegmentation.PLANAR
        contour_feed = fad if (fad is not None and not planar) else old_feed
        p32_feed = fad if (fad is not None and planar) else old_feed
        new_feed = sar.feed_mm_s
        new_kind = (
            MoveKind.RAPID if (sar.kind is MoveKind.RAPID or new_feed is None) else MoveKind.LINE
        )
        if sar.kind is MoveKind.NONE:
            new_kind = MoveKind.RAPID if new_feed is None else MoveKind.LINE

        out: list[Move] = [
            lead_move(
                geo,
                plane,
                start=geo.p4,
                end=geo.p3,
                span=sar.span,
                comp=contour_comp,
                feed=contour_feed,
                actions=(),
                origin="retract",
            )
        ]
        pieces: list[tuple[Vec3, Vec3, MoveKind, float | None, CompState]] = []
        if planar:
            kind = MoveKind.LINE if p32_feed is not None else MoveKind.RAPID
            pieces.append((geo.p3, geo.p2, kind, p32_feed, contour_comp))
        pieces.append((geo.p2, geo.p1, new_kind, new_feed, contour_comp))
        pieces.append((geo.p1, geo.p0, new_kind, new_feed, sar.comp))
        kept = [p for p in pieces if not same_point(p[0], p[1], self.tol)]
        if kept:  # the last sub-block carries the block's other content and its G40 (R46, R47)
            a, b, kind, feed, _ = kept[-1]
            kept[-1] = (a, b, kind, feed, sar.comp)
        for k, (a, b, kind, feed, comp) in enumerate(kept):
            out.append(
                sub_move(
                    plane,
                    a,
                    b,
                    kind=kind,
                    span=sar.span,
                    comp=comp,
                    feed=feed,
                    actions=sar.actions if k == len(kept) - 1 else (),
                    origin="retract",
                )
            )
        if not kept and (sar.actions or sar.comp != contour_comp):
            p0 = plane.to_xyz(geo.p0)
            out.append(
                Move(
                    kind=MoveKind.NONE,
                    start=p0,
                    end=p0,
                    plane=plane,
                    span=sar.span,
                    comp=sar.comp,
                    feed_mm_s=new_feed,
                    actions=sar.actions,
                    plane_programmed=False,
                    origin="retract",
                )
            )
        p0_xyz = plane.to_xyz(geo.p0)
        if not same_point(p0_xyz, sar.end, 1e-9):
            self.restart = (sar.end, p0_xyz)
        for m in out:
            self._note(m)
        return out
