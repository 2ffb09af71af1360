"""APPR/DEP blocks of the Klartext reader: the approach and departure leads (spec §7).

:class:`LeadBlocks` reads APPR LT/LN/CT/LCT (and their polar forms) and DEP LT/LN/CT/LCT: an APPR
block waits (:class:`~.state.PendingApproach`) until the first contour element fixes the lead's
tangent, then becomes the lead elements PS→PH→PA; a DEP block becomes PE→PN at once. The geometry
of the points PS, PH, PA, PE, PN is :mod:`trcopt.controllers.heidenhain.appr_dep`; the contour
elements are :mod:`trcopt.controllers.heidenhain.motion`.
"""

from __future__ import annotations

from trcopt.codes import Code
from trcopt.controllers.heidenhain import appr_dep as sar
from trcopt.controllers.heidenhain.contour import Elem
from trcopt.controllers.heidenhain.lexer import Block
from trcopt.controllers.heidenhain.state import (
    COMPENSATION_WORDS,
    COORDINATE_WORDS,
    FEED_WORDS,
    BlockError,
    PendingApproach,
    ReaderState,
)
from trcopt.errors import SourceSpan
from trcopt.geometry import vec
from trcopt.modes import Side
from trcopt.nc.model import MoveKind

__all__ = ["LeadBlocks", "LEAD_WORDS"]

#: The words of an APPR block (a DEP block: without the compensation words).
LEAD_WORDS = (
    COORDINATE_WORDS | {"PR", "PA", "IPR", "IPA", "LEN", "CCA", "R"} | COMPENSATION_WORDS | FEED_WORDS | {"M", "LA"}
)


def _lead_kind(blk: Block) -> str:
    """The kind word of an APPR/DEP block (``LT``, ``LN``, ``CT``, ``LCT`` or a polar ``P…``); a
    block without one (``DEP LEN12 F500``) is an error at the statement."""
    parts = blk.statement.split()
    if len(parts) < 2:
        raise BlockError(
            Code.HH_SYNTAX,
            f"{parts[0]} needs its kind: LT, LN, CT, LCT (or PLT, PLN, PCT, PLCT) right after {parts[0]}",
            blk.column,
        )
    return parts[1]


class LeadBlocks(ReaderState):
    """APPR/DEP handling on top of the reader's state and word access."""

    def _appr_block(self, blk: Block, span: SourceSpan) -> None:
        words = self._words(blk, LEAD_WORDS)
        kind = _lead_kind(blk)
        if self.side is not Side.OFF:
            raise BlockError(Code.HH_SYNTAX, "APPR while radius compensation is active: program R0 first")
        comp = self._comp_word(words)
        if comp is None or comp not in ("RL", "RR", "R0"):
            raise BlockError(Code.HH_SYNTAX, f"APPR {kind} needs RL, RR or R0")
        feed_before = None if self.last_rapid else self.feed
        feed, rapid = self._feed_of(words)
        polar = kind.startswith("P")
        target = self._polar_target(words, line=True) if polar else self._target(words)
        side = Side.OFF if comp == "R0" else self._side_of(comp)
        if side is not Side.OFF and self.last_on_side not in (Side.OFF, side):
            raise BlockError(
                Code.HH_TRC_SIDE_SWITCH,
                "RL/RR changed without an R0 traversing block",
                words[comp].column,
            )
        r = self._radius(words[comp].column) if side is not Side.OFF else 0.0
        self._m120(words, side)
        if side is Side.OFF:
            self._warn(
                Code.HH_APPR_R0, "APPR with R0: path computed with radius 0 on side RR (iTNC 530)", span
            )
        vals = {
            k: float(w.value)
            for k, w in words.items()
            if w.value is not None and k in ("LEN", "CCA", "R")
        }
        need = {"LT": ("LEN",), "LN": ("LEN",), "CT": ("CCA", "R"), "LCT": ("R",)}[kind.lstrip("P")]
        for name in need:
            if name not in vals:
                raise BlockError(Code.HH_SYNTAX, f"APPR {kind} needs {name}")
        if kind.lstrip("P") == "LCT" and feed is None and not rapid:
            raise BlockError(Code.HH_APPR_NO_FEED, "APPR LCT without a programmed feed rate")
        self.appr = PendingApproach(
            kind.lstrip("P"),
            self.pos,
            target,
            side,
            r,
            vals,
            feed_before,
            None if rapid else feed,
            "F" in words,
            span,
            self._actions(words),
            self._length(1.0, f"APPR {kind}"),
        )
        self.side = side
        if side is not Side.OFF:
            self.last_on_side = side
        self.pos = target
        self.last_rapid = rapid

    def _finish_appr(self, first: Elem) -> None:
        a = self.appr
        assert a is not None
        ps, pa = self._uvw(a.ps), self._uvw(a.pa)
        s = a.side.sign if a.side is not Side.OFF else -1
        t = first.start_tangent()
        ps2, pa2 = (ps[0], ps[1]), (pa[0], pa[1])
        v, ref = a.words, self.opts.appr_radius
        try:
            if a.kind == "LT":
                lead = sar.appr_lt(ps2, pa2, t, s, a.r, v["LEN"] * a.scale)
            elif a.kind == "LN":
                lead = sar.appr_ln(ps2, pa2, t, s, a.r, v["LEN"] * a.scale)
            elif a.kind == "CT":
                lead = sar.appr_ct(ps2, pa2, t, s, a.r, v["CCA"], v["R"] * a.scale, ref)
            else:
                lead = sar.appr_lct(ps2, pa2, t, s, a.r, v["R"] * a.scale, ref)
        except sar.LeadError as exc:
            raise BlockError(exc.code, exc.message, span=a.span) from None
        if a.feed_before is None and a.kind != "LCT":
            self._warn(
                Code.HH_APPR_RAPID, "PS→PH is traversed at FMAX (the last positioning was FMAX)", a.span
            )
        out: list[Elem] = []
        w_ps, w_pa = ps[2], pa[2]
        for k, piece in enumerate(lead.pieces):
            w0 = w_ps if k == 0 else w_pa
            feed = a.feed if (k > 0 or a.kind == "LCT") else a.feed_before
            side = a.side if piece.compensated else Side.OFF
            e = Elem(
                MoveKind.LINE if piece.center is None else MoveKind.ARC,
                (*piece.start, w0),
                (*piece.end, w0),
                a.span,
                side,
                a.r if side is not Side.OFF else 0.0,
                feed,
                piece.center,
                piece.ccw,
                actions=a.actions if k == 0 else (),
                origin="approach",
                side_programmed=k == 0,
                tool_active=self.tool is not None,
            )
            if feed is None and e.kind is MoveKind.LINE:
                e.kind = MoveKind.RAPID
            out.append(e)
            if k == 0 and abs(w_pa - w_ps) > 1e-12:  # R7: plane first, then the tool axis
                nxt_side = a.side if lead.pieces[1].compensated else Side.OFF
                out.append(
                    Elem(
                        MoveKind.LINE,
                        (*piece.end, w_ps),
                        (*piece.end, w_pa),
                        a.span,
                        nxt_side,
                        e.radius if nxt_side is not Side.OFF else 0.0,
                        a.feed,
                        origin="approach",
                        tool_active=e.tool_active,
                    )
                )
        self.elems.extend(out)
        self.appr = None

    def _dep_block(self, blk: Block, span: SourceSpan) -> None:
        words = self._words(blk, LEAD_WORDS - COMPENSATION_WORDS)
        kind = _lead_kind(blk).lstrip("P")
        last = self.elems[-1] if self.elems else None
        if last is None or vec.dist(last.end[:2], self._uvw(self.pos)[:2]) > 1e-6:
            raise BlockError(Code.HH_SYNTAX, "DEP needs a preceding contour element")
        if last.origin == "retract":
            # the element before is a departure itself: it has left the contour, there is no
            # contour element (and, after a DEP CT ending in its start point, no tangent) to leave
            raise BlockError(Code.HH_SYNTAX, "DEP needs a preceding contour element, not another DEP")
        side, r = self.side, last.radius
        if side is Side.OFF:
            self._warn(
                Code.HH_DEP_R0,
                "DEP without radius compensation: computed with radius 0 on side RR",
                span,
            )
            r = 0.0
        s = side.sign if side is not Side.OFF else -1
        feed, rapid = self._feed_of(words)
        vals = {
            k: float(w.value)
            for k, w in words.items()
            if w.value is not None and k in ("LEN", "CCA", "R")
        }
        need = {"LT": ("LEN",), "LN": ("LEN",), "CT": ("CCA", "R"), "LCT": ("R",)}[kind]
        for name in need:
            if name not in vals:
                raise BlockError(Code.HH_SYNTAX, f"DEP {kind} needs {name}")
        pe = self._uvw(self.pos)
        pe2, t, ref = (pe[0], pe[1]), last.end_tangent(), self.opts.appr_radius
        scale = self._length(1.0, f"DEP {kind}")
        w_end = pe[2]
        if kind == "LT":
            lead = sar.dep_lt(pe2, t, s, r, vals["LEN"] * scale)
        elif kind == "LN":
            lead = sar.dep_ln(pe2, t, s, r, vals["LEN"] * scale)
        elif kind == "CT":
            lead = sar.dep_ct(pe2, t, s, r, vals["CCA"], vals["R"] * scale, ref)
        else:
            pn = self._uvw(
                self._polar_target(words, line=True)
                if blk.statement.endswith("PLCT")
                else self._target(words)
            )
            w_end = pn[2]
            lead = sar.dep_lct(pe2, t, s, r, (pn[0], pn[1]), vals["R"] * scale, ref)
        block_feed = None if rapid else feed
        for k, piece in enumerate(lead.pieces):
            eside = side if piece.compensated else Side.OFF
            e = Elem(
                MoveKind.LINE if piece.center is None else MoveKind.ARC,
                (*piece.start, pe[2]),
                (*piece.end, pe[2]),
                span,
                eside,
                r if eside is not Side.OFF else 0.0,
                block_feed,
                piece.center,
                piece.ccw,
                actions=self._actions(words) if k == 0 else (),
                origin="retract",
                side_programmed=not piece.compensated,
                tool_active=self.tool is not None,
            )
            if block_feed is None and e.kind is MoveKind.LINE:
                e.kind = MoveKind.RAPID
            self.elems.append(e)
        pn_uv = lead.pieces[-1].end
        if abs(w_end - pe[2]) > 1e-12:  # R7: plane first, then the tool axis
            self.elems.append(
                Elem(
                    MoveKind.LINE,
                    (*pn_uv, pe[2]),
                    (*pn_uv, w_end),
                    span,
                    Side.OFF,
                    0.0,
                    block_feed,
                    origin="retract",
                )
            )
        self.pos = self.plane.to_xyz((pn_uv[0], pn_uv[1], w_end))
        self.side = Side.OFF
        self.last_on_side = Side.OFF
        self._m120_off()
