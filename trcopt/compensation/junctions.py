"""How each block of a region ends: the corner rules between neighbours and the searches over
later and earlier blocks when the neighbour alone does not resolve the corner.

:class:`JunctionResolver` answers, for block i of a region, a :class:`~.lookahead.Join`:

* the junction with the next block (spec R14–R25): tangential, outside (G450 transition circle,
  DISC conic, G451 intersection — :mod:`trcopt.compensation.corners`), inside (bounded
  intersection nearest the next block's start), or the selection / deselection junction
  (:mod:`trcopt.compensation.selection`);
* an inside corner without an intersection, or a degenerate next block: the predictive search
  over later blocks (R25.3/R25.4, R30; up to MD20240 blocks, the blocks in between omitted), then
  the CDOF backward search against the previous block, then what the approach / retraction
  strategy makes of an unresolved first or last corner (KONT behind the contour, G461/G462,
  R32–R35); else alarm 10751;
* with CDON, the bottleneck detection (R26): the last later block whose chain the chain of block
  i meets, the blocks in between omitted.
"""

from __future__ import annotations

from trcopt.compensation import corners as cn
from trcopt.compensation.elements import LAM_TOL, ElemKind, Piece, _point2
from trcopt.compensation.lookahead import (
    Join,
    Pending,
    Window,
    first_hit,
    line_distance,
    walk_first,
    walk_hit,
)
from trcopt.compensation.selection import approach_join, auxiliary, retract_behind, retract_join
from trcopt.config import TrcSettings
from trcopt.errors import AlarmError, alarm
from trcopt.geometry import vec
from trcopt.geometry.intersect import intersections
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.modes import ApproachMode, ApproachStrategy, CollisionMode
from trcopt.path import Role

__all__ = ["JunctionResolver"]


class JunctionResolver:
    """The junction rules of one compensation run (settings and coincidence tolerance, mm)."""

    def __init__(self, settings: TrcSettings) -> None:
        self.settings = settings
        self.tol = settings.tolerances.coincidence_mm

    # ------------------------------------------------------------------ the next block
    def resolve(self, win: Window, i: int, chain: list[Piece], pending: Pending | None) -> Join:
        """How block i (its chain so far: ``chain``) ends and which block starts next."""
        a = win.get(i)
        b = win.get(i + 1)
        assert a is not None and b is not None
        if a.kind is ElemKind.APPROACH:
            return approach_join(a, b, self.settings)
        if b.kind is ElemKind.RETRACT:
            return retract_join(a, b, i, self.settings)
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
                nxt = Piece(b, b.role, best.lam_b, 1.0)
                # nearly parallel offsets: the two parameters of their intersection give points up
                # to ~eps/δ apart; a line starts where the other element now ends (no gap)
                if isinstance(b.prog, Line):
                    nxt.p0 = _point2(last.end_carrier(), best.lam_a)
                elif isinstance(a.prog, Line):
                    last.p1 = _point2(b.off_start, best.lam_b)
                return Join(i + 1, [nxt], end=(len(chain) - 1, best.lam_a))
            nxt = Piece(b, b.role, 0.0, 1.0)
            if isinstance(b.prog, Line):
                nxt.p0 = last.end_point()
            elif last.main and isinstance(a.prog, Line) and last.lam1 == 1.0:
                last.p1 = b.off_start.point2(0.0)
            return Join(i + 1, [nxt])
        if kind is cn.JunctionKind.OUTSIDE:
            mode, disc = cn.corner_mode_for(a, b)
            out = cn.outside_corner(a, b, delta, self.settings, mode, disc)
            end = None if out.lam_a is None else (len(chain) - 1, out.lam_a)
            return Join(i + 1, out.leading + [Piece(b, b.role, out.lam_b, 1.0)], end=end)
        return self._inside(win, i, chain, pending)

    def _inside(self, win: Window, i: int, chain: list[Piece], pending: Pending | None) -> Join:
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
            return Join(i + 1, [Piece(b, b.role, max(lam_b, 0.0), 1.0)], end=(k, lam_a))
        return self._search_beyond(win, i, chain, pending, reason="inside")

    # ------------------------------------------------------------------ later and earlier blocks
    def _search_beyond(
        self,
        win: Window,
        i: int,
        chain: list[Piece],
        pending: Pending | None,
        reason: str,
    ) -> Join:
        """R25.3/R25.4/R30: predictive search over later blocks, then backwards; else 10751."""
        a = win.get(i)
        assert a is not None
        if reason == "degenerate" and a.comp.collision is not CollisionMode.CDON:
            b = win.get(i + 1)
            assert b is not None
            raise AlarmError(alarm(10751, "collision danger: inside arc smaller than the tool radius", b.span))
        n = self.settings.cutcom_maxnum_check_blocks
        for j in range(i + 2, i + n + 1):
            c = win.get(j)
            if c is None:
                break
            if c.degenerate:
                continue
            if c.kind is ElemKind.RETRACT and c.comp.strategy is not ApproachStrategy.G460:
                break  # R31: only G460 includes the retraction block in the search
            found = first_hit(chain, self._full_chain(win, j), self.tol)
            if found is None and c.kind is not ElemKind.RETRACT:
                collinear = self._collinear_join(chain, c.off_start)
                if collinear is not None:
                    found = (collinear[1], collinear[2], [Piece(c, c.role, 0.0, 1.0)])
            if found is not None:
                k, lam_a, rest = found
                return Join(j, rest, end=(k, lam_a), omitted=list(range(i + 1, j)))
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
                return Join(i + 1, [Piece(b, b.role, lam_b, 1.0)], backward=(k, lam_a))
        strategy_join = self._strategy_extension(win, i, chain, pending)
        if strategy_join is not None:
            return strategy_join
        raise AlarmError(
            alarm(
                10751,
                "collision danger: no intersection of the tool-centre path found "
                f"within {n} blocks (MD20240)",
                a.span,
            )
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
        if carrier.distance2(target.start2) > self.tol and line_distance(carrier, target.start2) > self.tol:
            return None
        lam_a = carrier.param_of(target.start2)
        if lam_a < last.lam0 - LAM_TOL:
            return None
        return (0.0, len(chain) - 1, lam_a)

    def _strategy_extension(self, win: Window, i: int, chain: list[Piece], pending: Pending | None) -> Join | None:
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
                hit = first_hit(app_chain, self._full_chain(win, i + 1), self.tol)
                if hit is None:
                    return None
                k, lam, rest = hit
                return Join(i + 1, rest, backward=(k, lam))
            strategy = app.comp.strategy
            if strategy is ApproachStrategy.G460:
                return None
            start = a.off_start.point2(0.0)
            back = (-a.start_tangent()[0], -a.start_tangent()[1])
            aux = auxiliary(strategy, (a.prog.start[0], a.prog.start[1]), start, back, a.r0)
            found: tuple[int, Vec2, list[Piece]] | None = None
            for j in range(i + 1, i + n + 1):
                c = win.get(j)
                if c is None:
                    break
                hit2 = walk_hit(aux, self._full_chain(win, j))
                if hit2 is not None:
                    found = (j, hit2[0], hit2[1])
                    if a.comp.collision is not CollisionMode.CDON:
                        break
                if c.kind is ElemKind.RETRACT:
                    break
            if found is None:
                return None
            j, point, rest = found
            return Join(j, rest, backward_point=point, omitted=list(range(i + 1, j)))
        r = win.get(i + 2)
        if r is not None and r.kind is ElemKind.RETRACT:
            e_pt = (r.prog.start[0], r.prog.start[1])
            if retract_behind(b, r):
                hit = first_hit(chain, self._full_chain(win, i + 2), self.tol)
                if hit is None:
                    return None
                k, lam, rest = hit
                return Join(i + 2, rest, end=(k, lam), omitted=[i + 1])
            strategy = r.comp.strategy
            if strategy is ApproachStrategy.G460:
                return None
            aux = auxiliary(strategy, e_pt, b.off_end.point2(1.0), b.end_tangent(), b.r1)
            met = walk_first(aux, chain, use_end=True)
            if met is None:
                return None
            k, lam, point = met
            return Join(i + 2, [Piece(r, Role.RETRACT, 0.0, 1.0, p0=point)], end=(k, lam), omitted=[i + 1])
        return None

    def _search_carrier(self, win: Window, j: int) -> Line | Arc:
        """The geometry block j is searched with (the actual line for a NORM retraction)."""
        c = win.get(j)
        assert c is not None
        if c.kind is ElemKind.RETRACT:
            prev = win.get(j - 1)
            if prev is not None:
                p = prev.off_end.point2(1.0)
                return Line((p[0], p[1], c.prog.start[2]), c.prog.end)
        return c.off_start

    def _full_chain(self, win: Window, j: int) -> list[Piece]:
        """Block j's chain as the adjacent corner rules build it (untrimmed at inside corners)."""
        c = win.get(j)
        prev = win.get(j - 1)
        assert c is not None and prev is not None
        if c.kind is ElemKind.RETRACT:
            if retract_behind(prev, c):
                lead = retract_join(prev, c, j - 1, self.settings)  # bypass circle / extension, then the line
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

    # ------------------------------------------------------------------ bottleneck detection
    def collision(
        self, win: Window, i: int, chain: list[Piece], j_adjacent: int
    ) -> tuple[int, tuple[int, float], list[Piece]] | None:
        """R26 CDON: the last later block (up to MD20240) whose chain the chain of block i meets:
        (that block, where block i's chain ends, that block's chain from the meeting point)."""
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
                hit = first_hit(chain, self._full_chain(win, j), self.tol)
                if hit is not None:
                    found = (j, (hit[0], hit[1]), hit[2])
            if c.kind is ElemKind.RETRACT:
                break
        return found
