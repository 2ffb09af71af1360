"""The contour elements of the Klartext reader: L, LP, C, CR, CT, CP, CTP and RND/CHF (spec §5, §6).

:class:`MotionBlocks` turns a motion block into a contour-level :class:`~.contour.Elem`: its target
(Cartesian or polar), the compensation word (RL/RR switch on only in a straight line, R0 off in a
block that moves in the working plane, no direct RL↔RR), the paraxial R+/R− lengthening or
shortening (not TRC), the arc constructions (C and CP about the pole, CR by radius, CT/CTP
tangential), and a pending RND/CHF resolved between its two neighbours. An APPR waiting for this
element is finished here (:mod:`trcopt.controllers.heidenhain.leads`).
"""

from __future__ import annotations

import math

from trcopt.codes import Code
from trcopt.controllers.heidenhain.contour import (
    ContourError,
    Elem,
    apply_chf,
    apply_rnd,
    circle_about,
    circle_by_radius,
    circle_tangential,
)
from trcopt.controllers.heidenhain.leads import LeadBlocks
from trcopt.controllers.heidenhain.lexer import Block, Word
from trcopt.controllers.heidenhain.state import (
    ALLOWED_WORDS,
    AXIS_INDEX,
    COORDINATE_WORDS,
    BlockError,
    number,
)
from trcopt.errors import SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.vec import Vec3
from trcopt.modes import Side
from trcopt.nc.model import MoveKind

__all__ = ["MotionBlocks"]


class MotionBlocks(LeadBlocks):
    """Motion blocks and RND/CHF on top of the APPR/DEP handling."""

    def _motion(self, blk: Block, words: dict[str, Word], span: SourceSpan) -> None:
        st = blk.statement
        comp = self._comp_word(words)
        feed, rapid = self._feed_of(words)
        start = self.pos
        s_uvw = self._uvw(start)
        if st in ("L", "LP"):
            target = self._target(words) if st == "L" else self._polar_target(words, line=True)
        elif st in ("CP", "CTP"):
            target = self._polar_target(words, line=st == "CTP")
        else:
            target = self._target(words)
        side = self.side
        side_programmed = comp in ("RL", "RR", "R0")
        if comp in ("RL", "RR"):
            new = self._side_of(comp)
            if self.side is Side.OFF and self.last_on_side not in (Side.OFF, new):
                raise BlockError(
                    Code.HH_TRC_SIDE_SWITCH,
                    "RL/RR changed without an R0 traversing block in the working plane",
                    words[comp].column,
                )
            if self.side not in (Side.OFF, new):
                raise BlockError(
                    Code.HH_TRC_SIDE_SWITCH,
                    "RL↔RR changed directly: program an R0 block in between",
                    words[comp].column,
                )
            if self.side is Side.OFF and st not in ("L", "LP"):
                raise BlockError(
                    Code.HH_TRC_IN_CIRCLE,
                    "radius compensation can only be switched on in a straight-line block",
                    words[comp].column,
                )
            side = new
        elif comp == "R0":
            if self.side is not Side.OFF and st not in ("L", "LP"):
                raise BlockError(
                    Code.HH_TRC_IN_CIRCLE,
                    "radius compensation can only be cancelled in a straight-line block",
                    words[comp].column,
                )
            side = Side.OFF
        self._m120(words, side)
        radius = self._radius(words[comp].column if comp else None) if side is not Side.OFF else 0.0
        if comp in ("R+", "R-"):
            if self.side is not Side.OFF:
                raise BlockError(
                    Code.HH_SYNTAX,
                    "paraxial R+/R- while RL/RR is active: program R0 first",
                    words[comp].column,
                )
            if st != "L":
                raise BlockError(Code.HH_SYNTAX, f"paraxial {comp} only in an L block", words[comp].column)
            target = self._paraxial(words, comp, target)
        e_uvw = self._uvw(target)
        moving_plane = math.hypot(e_uvw[0] - s_uvw[0], e_uvw[1] - s_uvw[1]) > 1e-9
        if side is Side.OFF and self.side is not Side.OFF:
            if not moving_plane:
                raise BlockError(
                    Code.HH_SYNTAX, "R0 must be programmed in a block that moves in the working plane"
                )
        if not rapid and feed is None and (moving_plane or e_uvw[2] != s_uvw[2]):
            raise BlockError(Code.HH_NO_FEED, "no feed rate programmed (F or FMAX)")
        kind = MoveKind.RAPID if rapid else MoveKind.LINE
        elem = Elem(
            kind,
            s_uvw,
            e_uvw,
            span,
            side,
            radius,
            None if rapid else feed,
            actions=self._actions(words),
            m97="M97" in words,
            side_programmed=side_programmed,
            tool_active=self.tool is not None,
        )
        if st in ("C", "CR", "CT", "CP", "CTP"):
            self._arc(st, words, elem)
        if elem.kind is not MoveKind.ARC and not moving_plane and e_uvw[2] == s_uvw[2]:
            self._commit_side(side, moving_plane)
            self._append_plain(elem)  # no motion: keep the M functions only
            return
        if self.corner is not None:
            self._resolve_corner(elem)
        if self.appr is not None:
            if not moving_plane and elem.kind is not MoveKind.ARC:
                raise BlockError(
                    Code.HH_APPR_NO_CONTOUR,
                    "APPR without a following contour element (no motion in the working plane)",
                    span=self.appr.span,
                )
            if side is not self.appr.side:
                raise BlockError(
                    Code.HH_TRC_SIDE_SWITCH,
                    "the element after APPR must keep the APPR compensation side",
                )
            self._finish_appr(elem)
        self._commit_side(side, moving_plane)
        self.elems.append(elem)
        self.pos = target
        self.last_rapid = rapid

    def _append_plain(self, elem: Elem) -> None:
        if elem.actions and self.elems:
            last = self.elems[-1]
            last.actions = last.actions + elem.actions

    def _commit_side(self, side: Side, moving_plane: bool) -> None:
        if side is not Side.OFF:
            self.last_on_side = side
        elif moving_plane:
            self.last_on_side = Side.OFF
        if side is Side.OFF:
            self._m120_off()
        self.side = side

    def _paraxial(self, words: dict[str, Word], comp: str, target: Vec3) -> Vec3:
        if not self.frame.rigid_axes(self.plane):
            raise BlockError(
                Code.HH_NOT_MODELLED,
                f"paraxial {comp} under a rotation or scaling cycle is not modelled",
                words[comp].column,
            )
        u, v, _ = self.plane.axes
        plane_words = [k for k in words if k in COORDINATE_WORDS and AXIS_INDEX[k[-1]] in (u, v)]
        if len(plane_words) > 1:
            raise BlockError(
                Code.HH_PARAXIAL_NOT_PARAXIAL,
                f"{comp} needs exactly one working-plane coordinate",
                words[comp].column,
            )
        if not plane_words:
            return target
        i = AXIS_INDEX[plane_words[0][-1]]
        travel = target[i] - self.pos[i]
        if abs(travel) <= 1e-12:
            return target
        r = self._radius(words[comp].column)
        p = list(target)
        p[i] += (1.0 if comp == "R+" else -1.0) * math.copysign(r, travel)
        return (p[0], p[1], p[2])

    def _arc(self, st: str, words: dict[str, Word], elem: Elem) -> None:
        if "DR+" in words or "DR-" in words:
            self.direction = "DR+" in words
        elem.kind = MoveKind.ARC
        self._length(1.0, f"a {st} arc")  # circles only under an even scaling of the plane
        mirrored = self._mirrored()
        if st in ("C", "CP"):
            if self.pole is None:
                raise BlockError(Code.HH_NO_POLE, f"{st} needs a circle centre (CC)")
            if self.direction is None:
                raise BlockError(Code.HH_SYNTAX, f"{st} needs a direction of rotation DR+ or DR-")
            tol = max(self.tol.arc_end_radius_mm, 1e-6)
            pole = self._pole_work()
            circle_about(elem.start, elem.end, pole, tol)
            elem.center, elem.ccw = pole, self.direction != mirrored
            if st == "CP" and "IPA" in words and abs(number(words["IPA"])) >= 360.0 - 1e-9:
                elem.turns = max(0, int(abs(number(words["IPA"])) // 360.0) - 1)
        elif st == "CR":
            if "R" not in words or not ("DR+" in words or "DR-" in words):
                raise BlockError(Code.HH_SYNTAX, "CR needs R and DR+ or DR-")
            ccw = ("DR+" in words) != mirrored
            elem.center = circle_by_radius(elem.start, elem.end, self._length(number(words["R"])), ccw)
            elem.ccw = ccw
        else:  # CT, CTP
            prev = self.elems[-1] if self.elems else None
            if (
                prev is None
                or self.corner is not None
                or vec.dist(prev.end[:2], elem.start[:2]) > 1e-6
            ):
                raise ContourError(
                    Code.HH_CT_NO_TANGENT, f"{st} needs a preceding element in the working plane"
                )
            elem.center, elem.ccw = circle_tangential(elem.start, elem.end, prev.end_tangent())

    # ------------------------------------------------------------------ RND / CHF
    def _corner_block(self, blk: Block, span: SourceSpan) -> None:
        words = self._words(blk, ALLOWED_WORDS[blk.statement])
        prev = self.elems[-1] if self.elems else None
        if (
            prev is None
            or prev.kind is MoveKind.RAPID
            or self.corner is not None
            or self.appr is not None
        ):
            raise BlockError(Code.HH_SYNTAX, f"a contour must not start with {blk.statement}")
        if blk.statement == "RND":
            if "R" not in words:
                raise BlockError(Code.HH_SYNTAX, "RND needs a radius R")
            value = self._length(number(words["R"]), "RND")
        else:
            bare = [w for w in blk.words if w.address == ""]
            if len(bare) != 1:
                raise BlockError(Code.HH_SYNTAX, "CHF needs one chamfer length")
            value = self._length(float(bare[0].text) if bare[0].value is None else bare[0].value, "CHF")
        feed = number(words["F"]) * self.unit / 60.0 if "F" in words else None
        self.corner = (blk.statement, value, feed, span)

    def _resolve_corner(self, elem: Elem) -> None:
        assert self.corner is not None
        what, value, feed, span = self.corner
        prev = self.elems[-1]
        if what == "RND":
            ins = apply_rnd(prev, elem, value, span)
        else:
            ins = apply_chf(prev, elem, value, span)
        ins.feed = feed if feed is not None else prev.feed
        ins.side, ins.radius, ins.tool_active = elem.side, elem.radius, elem.tool_active
        self.elems.append(ins)
        self.corner = None
