"""Heidenhain TNC conversational (Klartext) front end: program text → canonical moves.

Spec ``heidenhain_trc.md``. The reader builds the contour-level elements (L, LP, C, CR, CT, CP, CTP;
RND/CHF resolved between their neighbours; APPR/DEP through :mod:`trcopt.controllers.heidenhain.appr_dep`) and hands
them to the shared compensation engine as :class:`~trcopt.nc.model.Move` values with the Klartext
semantics mapped onto the engine's modes (see :mod:`trcopt.compensation.profiles`):

* RL/RR switch on in a straight-line block (the engine's NORM selection: the tool ends
  perpendicular to the next element), R0 switches off (perpendicular start), DEP and PGM CALL too;
* outside corners: transition arc; ``M97`` in the block that ends at the corner: intersection;
* paraxial ``R+``/``R−`` are not TRC: the reader lengthens/shortens the one-axis move by r;
* "tool radius too large" is checked here on the contour (:func:`.heidenhain_contour.radius_too_large`)
  so the program stops at that block as the control does.

Block labels are the TNC block numbers (``"15"``). Coordinates absolute mm, feeds mm/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from trcopt.controllers.heidenhain import appr_dep as sar
from trcopt.controllers.heidenhain.contour import (
    TOOL_RADIUS_TOO_LARGE,
    ContourError,
    Elem,
    apply_chf,
    apply_rnd,
    circle_about,
    circle_by_radius,
    circle_tangential,
    radius_too_large,
)
from trcopt.controllers.heidenhain.leads import _COMP, _FEED, _XYZ, LeadBlocks, _Appr, _Stop
from trcopt.controllers.heidenhain.lexer import Block, Word, lex_block
from trcopt.controllers.heidenhain.tooltable import (
    HhTool,
    compensation_value,
    find_tool_table,
    load_tool_table,
)
from trcopt.errors import ConfigError, Diagnostic, Severity, SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3
from trcopt.modes import CornerMode, Side
from trcopt.nc.modal import ReadOptions
from trcopt.nc.model import CompState, Move, MoveKind, NcProgram

__all__ = ["HeidenhainReader", "HeidenhainOptions", "read_heidenhain", "read_klartext"]

_AXIS_PLANE = {"Z": Plane.G17, "Y": Plane.G18, "X": Plane.G19}
_COORD = {"X": 0, "Y": 1, "Z": 2}
_MOTION = {"L", "LP", "C", "CR", "CT", "CP", "CTP"}
_ALLOWED: dict[str, set[str]] = {
    "L": _XYZ | _COMP | _FEED | {"M"},
    "LP": {"PR", "IPR", "PA", "IPA", "X", "Y", "Z", "IX", "IY", "IZ"} | _COMP | _FEED | {"M"},
    "C": _XYZ | {"DR+", "DR-"} | _COMP | _FEED | {"M"},
    "CR": _XYZ | {"R", "DR+", "DR-"} | _COMP | _FEED | {"M"},
    "CT": _XYZ | _COMP | _FEED | {"M"},
    "CP": {"PA", "IPA", "X", "Y", "Z", "IX", "IY", "IZ", "DR+", "DR-"} | _COMP | _FEED | {"M"},
    "CTP": {"PR", "IPR", "PA", "IPA", "X", "Y", "Z", "IX", "IY", "IZ"} | _COMP | _FEED | {"M"},
    "CC": _XYZ,
    "RND": {"R", "F"},
    "CHF": {"", "F"},
    "STOP": {"M"},
    "TOOL DEF": {"", "L", "R", "DL", "DR", "R2"},
    "TOOL CALL": {"", "S", "F", "DL", "DR", "DR2"},
}


@dataclass(frozen=True, slots=True)
class HeidenhainOptions:
    """Reader settings: ``appr_radius`` is the APPR/DEP CT/LCT radius reading (spec R9:
    ``"contour"``, recommended default, or ``"centre"``); ``tools`` preset tool table."""

    appr_radius: str = "contour"
    tools: dict[int, HhTool] = field(default_factory=dict)


class HeidenhainReader(LeadBlocks):
    """Reads one Klartext program (``read(text) -> NcProgram``); see the module docstring."""

    name = "heidenhain"

    def __init__(
        self, file: str = "<program>", tolerances=None, options: HeidenhainOptions | None = None
    ) -> None:  # type: ignore[no-untyped-def]
        from trcopt.config import Tolerances

        self.file = file
        self.tol = tolerances or Tolerances()
        self.opts = options or HeidenhainOptions()
        self.diags: list[Diagnostic] = []
        self.elems: list[Elem] = []
        self.pos: Vec3 = (0.0, 0.0, 0.0)
        self.plane = Plane.G17
        self.unit = 1.0
        self.pole: tuple[float, float] | None = None
        self.last_pa: float | None = None
        self.last_pr: float | None = None
        self.feed: float | None = None
        self.feed_auto: float | None = None
        self.last_rapid = False
        self.side = Side.OFF
        self.last_on_side = Side.OFF  # for the R0-between-RL-and-RR rule
        self.direction: bool | None = None  # last DR+/DR− (True = CCW)
        self.tools = dict(self.opts.tools)
        self.tool: HhTool | None = None
        self.dr_call = 0.0
        self.corner: tuple[str, float, float | None, SourceSpan] | None = None
        self.appr: _Appr | None = None
        self.blocks = 0
        self.ended = False

    # ------------------------------------------------------------------ driver
    def read(self, text: str) -> NcProgram:
        self._load_table()
        span = SourceSpan(self.file, 1, 1)
        for lineno, raw in enumerate(text.splitlines(), start=1):
            blk = lex_block(raw, lineno)
            if not blk.statement:
                continue
            self.blocks += 1
            span = SourceSpan(self.file, lineno, blk.column, blk.number)
            n_before = len(self.elems)
            try:
                self._block(blk, span)
            except (_Stop, ContourError, sar.LeadError) as exc:
                col = getattr(exc, "column", None) or blk.column
                where = getattr(exc, "span", None) or SourceSpan(self.file, lineno, col, blk.number)
                self._error(exc.code, exc.message, where)  # type: ignore[attr-defined]
                break
            for e in self.elems[n_before:]:
                e.extra.setdefault("plane", self.plane)
            if self.ended:
                break
        else:
            if self.appr is not None:
                self._error(
                    "E_APPR_NO_CONTOUR", "APPR without a following contour element", self.appr.span
                )
            elif self.corner is not None:
                self._error(
                    "E_SYNTAX",
                    f"{self.corner[0]} without a following contour element",
                    self.corner[3],
                )
        self._check_radius()
        moves = self._moves()
        return NcProgram(self.file, "heidenhain", tuple(moves), tuple(self.diags), self.blocks)

    def _load_table(self) -> None:
        path = find_tool_table(self.file)
        if path is None:
            return
        try:
            table = load_tool_table(path)
        except ConfigError as exc:
            self._warn(
                "W_TOOL_TABLE", f"tool table ignored: {exc.message}", SourceSpan(self.file, 1, 1)
            )
            return
        self.tools = {**table, **self.tools}

    def _error(self, code: str, message: str, span: SourceSpan) -> None:
        self.diags.append(Diagnostic(Severity.ERROR, code, message, span))

    def _warn(self, code: str, message: str, span: SourceSpan) -> None:
        self.diags.append(Diagnostic(Severity.WARNING, code, message, span))

    # ------------------------------------------------------------------ words
    def _words(self, blk: Block, allowed: set[str]) -> dict[str, Word]:
        out: dict[str, Word] = {}
        for w in blk.words:
            if w.address == "?":
                raise _Stop("E_SYNTAX", f"unknown word {w.text!r}", w.column)
            key = w.address
            if key not in allowed:
                what = f"word {w.text!r}" if key else f"{w.text!r}"
                raise _Stop("E_SYNTAX", f"{what} not allowed in a {blk.statement} block", w.column)
            if key == "M":
                out[f"M{int(w.value or 0)}"] = w
                continue
            if key in out and key:
                raise _Stop("E_SYNTAX", f"word {key} programmed twice", w.column)
            if key in _COMP and any(k in _COMP for k in out):
                raise _Stop(
                    "E_SYNTAX", "more than one compensation word (RL/RR/R0/R+/R-)", w.column
                )
            out[key or f"#{len(out)}"] = w
        return out

    def _target(self, words: dict[str, Word]) -> Vec3:
        p = list(self.pos)
        for key, w in words.items():
            axis = key[-1] if key in _XYZ else None
            if axis is None:
                continue
            v = float(w.value) * self.unit  # type: ignore[arg-type]
            i = _COORD[axis]
            p[i] = p[i] + v if key.startswith("I") else v
        return (p[0], p[1], p[2])

    def _feed_of(self, words: dict[str, Word]) -> tuple[float | None, bool]:
        """Feed of this block (mm/s, None = FMAX) and whether it is a rapid; updates the modal F."""
        if "FMAX" in words:
            return None, True
        if "FAUTO" in words:
            if self.feed_auto is None:
                raise _Stop("E_NO_FEED", "FAUTO without a feed in TOOL CALL", words["FAUTO"].column)
            return self.feed_auto, False
        if "F" in words:
            f = float(words["F"].value) * self.unit / 60.0  # type: ignore[arg-type]
            if self.unit != 1.0:
                f /= 10.0  # inch programs: F in 0.1 inch/min
            if f <= 0:
                raise _Stop("E_SYNTAX", "feed must be > 0", words["F"].column)
            self.feed = f
        return self.feed, False

    @staticmethod
    def _actions(words: dict[str, Word]) -> tuple[str, ...]:
        return tuple(k for k in words if k.startswith("M") and k[1:].isdigit())

    def _uvw(self, p: Vec3) -> Vec3:
        return self.plane.to_uvw(p)

    # ------------------------------------------------------------------ statements
    def _block(self, blk: Block, span: SourceSpan) -> None:
        st = blk.statement
        if st == "BEGIN PGM":
            units = [w.address for w in blk.words if w.address in ("MM", "INCH")]
            self.unit = 25.4 if units == ["INCH"] else 1.0
            return
        if st == "END PGM":
            self.ended = True
            if self.corner is not None:
                raise _Stop(
                    "E_SYNTAX",
                    f"{self.corner[0]} without a following contour element",
                    span=self.corner[3],
                )
            if self.appr is not None:
                raise _Stop(
                    "E_APPR_NO_CONTOUR",
                    "APPR without a following contour element",
                    span=self.appr.span,
                )
            return
        if st.startswith("BLK FORM"):
            return
        if st in ("TOOL DEF", "TOOL CALL"):
            self._tool(blk, self._words(blk, _ALLOWED[st]), span)
            return
        if st == "PGM CALL":
            self._no_open_corner(st)
            self.side = self.last_on_side = Side.OFF
            self._warn(
                "W_PGM_CALL",
                "PGM CALL: the called program is not executed; compensation cancelled",
                span,
            )
            return
        if st.startswith("APPR"):
            self._no_open_corner(st)
            self._appr_block(blk, span)
            return
        if st.startswith("DEP"):
            self._no_open_corner(st)
            self._dep_block(blk, span)
            return
        if st in ("RND", "CHF"):
            self._corner_block(blk, span)
            return
        if st == "CC":
            words = self._words(blk, _ALLOWED["CC"])
            c = self._uvw(self._target(words))
            self.pole = (c[0], c[1])
            self.last_pa = self.last_pr = None
            return
        if st == "STOP":
            self._words(blk, _ALLOWED["STOP"])
            return
        if st in _MOTION:
            self._motion(blk, self._words(blk, _ALLOWED[st]), span)
            return
        raise _Stop("E_SYNTAX", f"unknown or unsupported statement {blk.statement!r}", blk.column)

    def _no_open_corner(self, what: str) -> None:
        if self.corner is not None:
            raise _Stop(
                "E_SYNTAX", f"{self.corner[0]} must be followed by a contour element, not {what}"
            )
        if self.appr is not None and not what.startswith("CC"):
            raise _Stop(
                "E_APPR_NO_CONTOUR",
                f"APPR without a following contour element ({what} follows)",
                span=self.appr.span,
            )

    def _tool(self, blk: Block, words: dict[str, Word], span: SourceSpan) -> None:
        bare = [w for k, w in words.items() if k.startswith("#")]
        if not bare:
            raise _Stop("E_SYNTAX", f"{blk.statement} needs a tool number or name", blk.column)
        ident = bare[0].text.strip("\"'")
        if blk.statement == "TOOL DEF":
            if not ident.isdigit():
                raise _Stop("E_SYNTAX", "TOOL DEF needs a tool number", bare[0].column)
            n = int(ident)
            val = {
                k: float(w.value or 0.0) * self.unit
                for k, w in words.items()
                if not k.startswith("#")
            }
            self.tools[n] = HhTool(n, "", val.get("L", 0.0), val.get("R", 0.0), 0.0, 0.0)
            return
        if len(bare) < 2 or bare[1].text.upper() not in _AXIS_PLANE:
            raise _Stop("E_SYNTAX", "TOOL CALL needs the tool axis X, Y or Z", blk.column)
        if ident.isdigit() and int(ident) == 0:
            tool = HhTool(0)
        else:
            found = [
                t
                for t in self.tools.values()
                if (ident.isdigit() and t.number == int(ident)) or t.name == ident
            ]
            if not found:
                raise _Stop(
                    "E_TOOL_UNKNOWN",
                    f"tool {ident} is neither defined (TOOL DEF) nor in the tool table",
                    bare[0].column,
                )
            tool = found[0]
        self._no_open_corner("TOOL CALL")
        self.tool = tool
        self.plane = _AXIS_PLANE[bare[1].text.upper()]
        self.dr_call = float(words["DR"].value or 0.0) * self.unit if "DR" in words else 0.0
        if "F" in words:
            self.feed_auto = float(words["F"].value or 0.0) * self.unit / 60.0

    def _radius(self, column: int | None = None) -> float:
        if self.tool is None:
            raise _Stop("E_NO_TOOL", "radius compensation without a TOOL CALL", column)
        r = compensation_value(self.tool.radius, self.tool.dr, self.dr_call)
        if r < 0:
            raise _Stop(
                "E_TRC_NEG_RADIUS",
                f"compensation value R + DR_TAB + DR_CALL = {r:g} mm is negative",
                column,
            )
        return r

    # ------------------------------------------------------------------ motion
    def _comp_word(self, words: dict[str, Word]) -> str | None:
        for k in words:
            if k in _COMP:
                return k
        return None

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
            new = Side.LEFT if comp == "RL" else Side.RIGHT
            if self.side is Side.OFF and self.last_on_side not in (Side.OFF, new):
                raise _Stop(
                    "E_TRC_SIDE_SWITCH",
                    "RL/RR changed without an R0 traversing block in the working plane",
                    words[comp].column,
                )
            if self.side not in (Side.OFF, new):
                raise _Stop(
                    "E_TRC_SIDE_SWITCH",
                    "RL↔RR changed directly: program an R0 block in between",
                    words[comp].column,
                )
            if self.side is Side.OFF and st not in ("L", "LP"):
                raise _Stop(
                    "E_TRC_IN_CIRCLE",
                    "radius compensation can only be switched on in a straight-line block",
                    words[comp].column,
                )
            side = new
        elif comp == "R0":
            if self.side is not Side.OFF and st not in ("L", "LP"):
                raise _Stop(
                    "E_TRC_IN_CIRCLE",
                    "radius compensation can only be cancelled in a straight-line block",
                    words[comp].column,
                )
            side = Side.OFF
        radius = self._radius(words[comp].column if comp else None) if side is not Side.OFF else 0.0
        if comp in ("R+", "R-"):
            if self.side is not Side.OFF:
                raise _Stop(
                    "E_SYNTAX",
                    "paraxial R+/R- while RL/RR is active: program R0 first",
                    words[comp].column,
                )
            if st != "L":
                raise _Stop("E_SYNTAX", f"paraxial {comp} only in an L block", words[comp].column)
            target = self._paraxial(words, comp, target)
        e_uvw = self._uvw(target)
        moving_plane = math.hypot(e_uvw[0] - s_uvw[0], e_uvw[1] - s_uvw[1]) > 1e-9
        if side is Side.OFF and self.side is not Side.OFF:
            if not moving_plane:
                raise _Stop(
                    "E_SYNTAX", "R0 must be programmed in a block that moves in the working plane"
                )
        if not rapid and feed is None and (moving_plane or e_uvw[2] != s_uvw[2]):
            raise _Stop("E_NO_FEED", "no feed rate programmed (F or FMAX)")
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
                raise _Stop(
                    "E_APPR_NO_CONTOUR",
                    "APPR without a following contour element (no motion in the working plane)",
                    span=self.appr.span,
                )
            if side is not self.appr.side:
                raise _Stop(
                    "E_TRC_SIDE_SWITCH",
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
        self.side = side

    def _paraxial(self, words: dict[str, Word], comp: str, target: Vec3) -> Vec3:
        u, v, _ = self.plane.axes
        plane_words = [k for k in words if k in _XYZ and _COORD[k[-1]] in (u, v)]
        if len(plane_words) > 1:
            raise _Stop(
                "E_PARAXIAL_NOT_PARAXIAL",
                f"{comp} needs exactly one working-plane coordinate",
                words[comp].column,
            )
        if not plane_words:
            return target
        i = _COORD[plane_words[0][-1]]
        travel = target[i] - self.pos[i]
        if abs(travel) <= 1e-12:
            return target
        r = self._radius(words[comp].column)
        p = list(target)
        p[i] += (1.0 if comp == "R+" else -1.0) * math.copysign(r, travel)
        return (p[0], p[1], p[2])

    def _polar_target(self, words: dict[str, Word], line: bool) -> Vec3:
        if self.pole is None:
            raise _Stop("E_NO_POLE", "polar coordinates need a pole (CC)")
        s = self._uvw(self.pos)
        cur_angle = math.degrees(math.atan2(s[1] - self.pole[1], s[0] - self.pole[0]))
        cur_r = math.hypot(s[0] - self.pole[0], s[1] - self.pole[1])
        pa = self.last_pa if self.last_pa is not None else cur_angle
        pr = self.last_pr if self.last_pr is not None else cur_r
        if "PA" in words:
            pa = float(words["PA"].value)  # type: ignore[arg-type]
        elif "IPA" in words:
            pa = pa + float(words["IPA"].value)  # type: ignore[arg-type]
        if "PR" in words:
            pr = float(words["PR"].value) * self.unit  # type: ignore[arg-type]
        elif "IPR" in words:
            pr = pr + float(words["IPR"].value) * self.unit  # type: ignore[arg-type]
        if not line:
            pr = cur_r  # CP: radius = distance start–pole
        self.last_pa, self.last_pr = pa, pr
        w = self._uvw(self._target({k: v for k, v in words.items() if k in _XYZ}))[2]
        e = vec.polar(self.pole, pr, math.radians(pa))
        return self.plane.to_xyz((e[0], e[1], w))

    def _arc(self, st: str, words: dict[str, Word], elem: Elem) -> None:
        if "DR+" in words or "DR-" in words:
            self.direction = "DR+" in words
        elem.kind = MoveKind.ARC
        if st in ("C", "CP"):
            if self.pole is None:
                raise _Stop("E_NO_POLE", f"{st} needs a circle centre (CC)")
            if self.direction is None:
                raise _Stop("E_SYNTAX", f"{st} needs a direction of rotation DR+ or DR-")
            tol = max(self.tol.arc_end_radius_mm, 1e-6)
            circle_about(elem.start, elem.end, self.pole, tol)
            elem.center, elem.ccw = self.pole, self.direction
            if (
                st == "CP"
                and "IPA" in words
                and abs(float(words["IPA"].value or 0.0)) >= 360.0 - 1e-9
            ):  # type: ignore[arg-type]
                elem.turns = max(0, int(abs(float(words["IPA"].value or 0.0)) // 360.0) - 1)  # type: ignore[arg-type]
        elif st == "CR":
            if "R" not in words or not ("DR+" in words or "DR-" in words):
                raise _Stop("E_SYNTAX", "CR needs R and DR+ or DR-")
            elem.center = circle_by_radius(
                elem.start, elem.end, float(words["R"].value) * self.unit, "DR+" in words
            )  # type: ignore[arg-type]
            elem.ccw = "DR+" in words
        else:  # CT, CTP
            prev = self.elems[-1] if self.elems else None
            if (
                prev is None
                or self.corner is not None
                or vec.dist(prev.end[:2], elem.start[:2]) > 1e-6
            ):
                raise ContourError(
                    "E_CT_NO_TANGENT", f"{st} needs a preceding element in the working plane"
                )
            elem.center, elem.ccw = circle_tangential(elem.start, elem.end, prev.end_tangent())

    # ------------------------------------------------------------------ RND / CHF
    def _corner_block(self, blk: Block, span: SourceSpan) -> None:
        words = self._words(blk, _ALLOWED[blk.statement])
        prev = self.elems[-1] if self.elems else None
        if (
            prev is None
            or prev.kind is MoveKind.RAPID
            or self.corner is not None
            or self.appr is not None
        ):
            raise _Stop("E_SYNTAX", f"a contour must not start with {blk.statement}")
        if blk.statement == "RND":
            if "R" not in words:
                raise _Stop("E_SYNTAX", "RND needs a radius R")
            value = float(words["R"].value) * self.unit  # type: ignore[arg-type]
        else:
            bare = [w for w in blk.words if w.address == ""]
            if len(bare) != 1:
                raise _Stop("E_SYNTAX", "CHF needs one chamfer length")
            value = float(bare[0].text) * self.unit
        feed = float(words["F"].value) * self.unit / 60.0 if "F" in words else None  # type: ignore[arg-type]
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

    # ------------------------------------------------------------------ APPR / DEP
    def _check_radius(self) -> None:
        regions: list[list[Elem]] = []
        cur: list[Elem] | None = None
        for e in self.elems:
            moving = e.kind is MoveKind.ARC or vec.dist(e.start[:2], e.end[:2]) > 1e-9
            if e.side is Side.OFF:
                if moving:
                    cur = None
                continue
            if cur is None:
                cur = []
                regions.append(cur)
                continue  # the selection line
            if moving:
                cur.append(e)
        for region in regions:
            found = radius_too_large(region)
            if found is None:
                continue
            bad = region[found[0]]
            cut = next(i for i, e in enumerate(self.elems) if e.span.line == bad.span.line)
            del self.elems[cut:]
            self.diags = [
                d
                for d in self.diags
                if d.severity is not Severity.ERROR or d.span.line < bad.span.line
            ]
            self._error("E_TOOL_RADIUS_TOO_LARGE", f"{TOOL_RADIUS_TOO_LARGE}: {found[1]}", bad.span)
            return

    def _moves(self) -> list[Move]:
        moves: list[Move] = []
        m97_before = False
        for e in self.elems:
            plane = e.extra.get("plane", self.plane)
            assert isinstance(plane, Plane)
            comp = CompState(
                side=e.side,
                radius=e.radius,
                tool_active=e.tool_active,
                corner=CornerMode.INTERSECTION if m97_before else CornerMode.TRANSITION_CIRCLE,
                side_programmed=e.side_programmed,
            )
            m97_before = e.m97
            center = None
            if e.center is not None:
                center = plane.to_xyz((e.center[0], e.center[1], e.start[2]))
            actions = e.actions + (("M97",) if e.m97 and "M97" not in e.actions else ())
            moves.append(
                Move(
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
                )
            )
        return moves


def read_heidenhain(
    text: str, file: str = "<program>", tolerances=None, options: HeidenhainOptions | None = None
) -> NcProgram:  # type: ignore[no-untyped-def]
    """Read a Klartext program; never raises for a problem in the program (see the module docstring)."""
    return HeidenhainReader(file, tolerances, options).read(text)


def read_klartext(text: str, options: ReadOptions) -> NcProgram:
    """The controller's reader: ``options.tool_table`` is a TOML tool table (default: the one
    beside the program, see :func:`~trcopt.controllers.heidenhain.tooltable.find_tool_table`)."""
    hh = None if options.tool_table is None else HeidenhainOptions(tools=load_tool_table(options.tool_table))
    return read_heidenhain(text, file=options.file, tolerances=options.tolerances, options=hh)
