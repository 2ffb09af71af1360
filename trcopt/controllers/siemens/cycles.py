"""SINUMERIK drilling cycles ``CYCLE81``, ``CYCLE82``, ``CYCLE83`` expanded into their moves, and
``MCALL`` (the modal call after every block with motion).

Parameters as in the Programming Manual Cycles (drilling cycles), in program units along the
applicate of the working plane (drilling towards −applicate)::

    CYCLE81(RTP, RFP, SDIS, DP, DPR)                    drilling, centring
    CYCLE82(RTP, RFP, SDIS, DP, DPR, DTB)               counterboring: dwell DTB s at the depth
    CYCLE83(RTP, RFP, SDIS, DP, DPR, FDEP, FDPR, DAM, DTB, DTS, FRF, VARI, _AXN, _MDEP, _VRT, _DTD, _DIS1)

The depth is ``DP`` (absolute) or ``RFP − DPR``; with both, ``DPR`` counts (as the manual says).
CYCLE81/82: G0 to ``RFP + SDIS``, G1 to the depth at the active feed, (dwell), G0 to ``RTP``.
CYCLE83: the first depth ``FDEP`` or ``RFP − FDPR`` at feed ×``FRF`` (empty: 1); each further
infeed is the previous one less ``DAM`` but not less than ``DAM`` (``DAM`` 0: equal infeeds), the
last one ends at the depth. ``VARI=1`` (swarf removal): after each infeed (and dwell ``DTB``) G0 to
``RFP + SDIS``, dwell ``DTS``, G0 back to ``_DIS1`` above the last depth (``_DIS1`` 0: automatic,
0.6 mm up to a depth of 30 mm, else depth/50, at most 7 mm), G1 on. ``VARI=0`` (chip breaking):
G1 back by ``_VRT`` (0: 1 mm) after each infeed. ``_AXN``, ``_MDEP``, ``_DTD`` and the trailing
parameters of newer cycle versions must be empty or 0; anything else is ``NC-CYCLE``. The cycle
keeps the caller's motion group (it runs as a SAVE subprogram).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from trcopt.codes import Code
from trcopt.controllers.siemens.block import Block
from trcopt.controllers.siemens.flow import Statement
from trcopt.controllers.siemens.lexer import Word
from trcopt.controllers.siemens.variables import Variables, _split
from trcopt.errors import SourceSpan
from trcopt.nc.modal import ModalState, fail
from trcopt.nc.model import MoveKind

__all__ = ["DrillingCycles", "CYCLES"]

CYCLES = {"CYCLE81": 5, "CYCLE82": 6, "CYCLE83": 17}
_NAMES = {
    "CYCLE81": ("RTP", "RFP", "SDIS", "DP", "DPR"),
    "CYCLE82": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB"),
    "CYCLE83": ("RTP", "RFP", "SDIS", "DP", "DPR", "FDEP", "FDPR", "DAM", "DTB", "DTS", "FRF", "VARI",
                "_AXN", "_MDEP", "_VRT", "_DTD", "_DIS1"),
}  # fmt: skip
_MUST_BE_ZERO = {"_AXN", "_MDEP", "_DTD"}
_MAX_INFEEDS = 10_000


class DrillingCycles:
    """The cycle part of :class:`~trcopt.controllers.siemens.reader.SiemensReader`."""

    state: ModalState
    variables: Variables
    geom_scale: float
    arc_ccw: bool
    circle: int
    absolute: bool
    mcall: tuple[str, str, int] | None

    if TYPE_CHECKING:  # provided by the reader

        def _at(self, span: SourceSpan, word: Word) -> SourceSpan: ...

        def _finish(self, b: Block, span: SourceSpan) -> None: ...

        def _feed_missing(self, span: SourceSpan) -> None: ...

    def _cycle_word(self, word: Word, b: Block, span: SourceSpan) -> None:
        if b.cycle is not None:
            raise fail(Code.NC_SYNTAX, "two cycle calls in one block", self._at(span, word))
        b.cycle = word

    def _mcall(self, st: Statement, span: SourceSpan) -> None:
        rest = st.rest
        if not rest:
            self.mcall = None
            return
        name, _, args = rest.partition("(")
        name = name.strip().upper()
        if name not in CYCLES or not args.endswith(")"):
            raise fail(
                Code.NC_UNSUPPORTED, f"MCALL {rest}: only the drilling cycles {', '.join(CYCLES)} are modelled", span
            )
        column = st.rest_column + rest.index("(") + 1
        self.mcall = (name, args[:-1], column)

    def _run_cycle(self, name: str, args_text: str, column: int, span: SourceSpan) -> None:
        """Append the moves of a drilling cycle at the current position."""
        values = self._cycle_arguments(name, args_text, column, span)
        k = self.geom_scale
        p = values
        rtp, rfp = p.get("RTP"), p.get("RFP")
        if rtp is None or rfp is None:
            raise fail(Code.NC_CYCLE, f"{name}: RTP and RFP must be given", span)
        sdis = p.get("SDIS") or 0.0
        dpr = p.get("DPR")
        depth = rfp - dpr if dpr else p.get("DP")
        if depth is None:
            raise fail(Code.NC_CYCLE, f"{name}: the depth DP or DPR must be given", span)
        if not rtp >= rfp + sdis - 1e-12 or not depth < rfp + sdis:
            given = f"RTP {rtp:g}, RFP {rfp:g}, SDIS {sdis:g}, depth {depth:g}"
            raise fail(Code.NC_CYCLE, f"{name}: expected RTP ≥ RFP + SDIS > depth ({given})", span)
        st = self.state
        saved = (st.motion, self.arc_ccw, self.circle, self.absolute)
        feed = st.feed_mm_s
        if feed is None:
            self._feed_missing(span)  # alarm 10860 (no F in force), G95 without a turning spindle
        try:
            self._drill(name, p, rfp + sdis, depth, k, span)
            self._cycle_move(MoveKind.RAPID, rtp * k, span)
        finally:
            st.motion, self.arc_ccw, self.circle, self.absolute = saved
            st.feed_mm_s = feed

    def _drill(self, name: str, p: dict[str, float], safe: float, depth: float, k: float, span: SourceSpan) -> None:
        self._cycle_move(MoveKind.RAPID, safe * k, span)
        if name != "CYCLE83":
            self._cycle_move(MoveKind.LINE, depth * k, span)
            if name == "CYCLE82" and p.get("DTB"):
                self._cycle_dwell(p["DTB"], span)
            return
        rfp = p["RFP"]
        first = rfp - p["FDPR"] if p.get("FDPR") else p.get("FDEP")
        if first is None:
            raise fail(Code.NC_CYCLE, "CYCLE83: the first depth FDEP or FDPR must be given", span)
        first = max(first, depth)
        dam = abs(p.get("DAM") or 0.0)
        frf = p.get("FRF") or 1.0
        vari = int(p.get("VARI") or 0)
        if not 0.0 < frf <= 1.0 or vari not in (0, 1):
            raise fail(Code.NC_CYCLE, f"CYCLE83: FRF {frf:g} must lie in (0, 1], VARI {vari} must be 0 or 1", span)
        st = self.state
        feed = st.feed_mm_s
        assert feed is not None  # checked by _run_cycle
        infeed = rfp - first
        level, count = first, 0
        st.feed_mm_s = feed * frf
        self._cycle_move(MoveKind.LINE, first * k, span)
        st.feed_mm_s = feed
        total = rfp - depth
        anticipation = p.get("_DIS1") or (0.6 if total <= 30.0 else min(total / 50.0, 7.0))
        vrt = p.get("_VRT") or 1.0
        while level > depth + 1e-12:
            count += 1
            if count > _MAX_INFEEDS:
                raise fail(Code.NC_CYCLE, f"CYCLE83: more than {_MAX_INFEEDS} infeeds", span)
            if p.get("DTB"):
                self._cycle_dwell(p["DTB"], span)
            infeed = max(infeed - dam, dam) if dam > 0.0 else infeed
            following = max(level - infeed, depth)
            if vari == 1:
                self._cycle_move(MoveKind.RAPID, safe * k, span)
                if p.get("DTS"):
                    self._cycle_dwell(p["DTS"], span)
                self._cycle_move(MoveKind.RAPID, (level + anticipation) * k, span)
            else:
                self._cycle_move(MoveKind.LINE, (level + vrt) * k, span)
            self._cycle_move(MoveKind.LINE, following * k, span)
            level = following
        if p.get("DTB"):
            self._cycle_dwell(p["DTB"], span)

    def _cycle_arguments(self, name: str, text: str, column: int, span: SourceSpan) -> dict[str, float]:
        names = _NAMES[name]
        parts = _split(text) if text.strip() else []
        values: dict[str, float] = {}
        for i, (part, offset) in enumerate(parts):
            if not part.strip():
                continue
            value = self.variables.evaluate(part, span, column + offset)
            if i >= len(names) or (names[i] in _MUST_BE_ZERO and value != 0.0):
                what = names[i] if i < len(names) else f"parameter {i + 1}"
                raise fail(Code.NC_CYCLE, f"{name}: {what}={value:g} is not modelled by trcopt", span)
            values[names[i]] = value
        return values

    def _cycle_move(self, kind: MoveKind, w_value: float, span: SourceSpan) -> None:
        b = Block()
        b.motion = (0 if kind is MoveKind.RAPID else 1, span.column)
        b.axes[self.state.plane.axes[2]] = (w_value, True)
        self._finish(b, span)

    def _cycle_dwell(self, seconds: float, span: SourceSpan) -> None:
        b = Block()
        b.dwell = True
        b.actions.extend(["G4", f"F{seconds:g}"])
        self._finish(b, span)
