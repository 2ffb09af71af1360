"""RS274NGC feed modes ``G93``, ``G94``, ``G95`` as LinuxCNC's interpreter runs them.

* ``G94`` (the default): ``F`` in program units per minute. ``G95``: ``F`` in program units per
  revolution of the spindle; the path feed is F × S with S the programmed spindle speed (the
  interpreter checks the speed alone: ``M3``/``M4``/``M5`` do not change it).
* Every ``G94``/``G95`` word — also the mode in force — sets the feed rate to 0 (``convert_feed_mode``);
  the feed mode acts before the ``F`` of its block, which then sets the new feed rate.
* ``G93`` (inverse time): every ``G1``/``G2``/``G3`` needs its own ``F`` (1/minutes); the move runs
  at its programmed length × F (units/min; the length of the programmed path, before cutter
  compensation, a helix with its axial travel; a move of length zero at 0.1), which stays the
  interpreter's feed rate (``#<_feed>``) until the next. ``F`` in a block without such a move sets
  nothing. Canned cycles refuse inverse time.
* LinuxCNC's errors, with its messages: a feed move at feed rate 0 (``Cannot do g1 with zero feed
  rate``, ``Cannot make arc with zero feed rate``), under G95 at spindle speed 0 (``Cannot feed with
  zero spindle speed in feed per rev mode``), under G93 without F (``F word missing with inverse time
  g1 move`` / ``… arc move``), a canned cycle under G93 (``Cannot use inverse time feed with canned
  cycles``). Two cases LinuxCNC's interpreter accepts but whose moves never end are ``NC-FEED-MODE``
  (trcopt cannot time them): a canned cycle under G95 at spindle speed 0, an inverse-time ``F0``.
"""

from __future__ import annotations

import dataclasses
import math

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_motion import NgcState, Stop
from trcopt.controllers.linuxcnc.ngc_words import Words
from trcopt.geometry.vec import Vec3
from trcopt.nc.model import Move

__all__ = [
    "arc_length", "check_cycle_feed", "check_cycle_speed", "check_feed", "inverse_time_arc", "inverse_time_line",
    "set_feed_mode",
]  # fmt: skip

_ZERO_SPEED = "Cannot feed with zero spindle speed in feed per rev mode"
INVERSE_TIME_ZERO_LENGTH_RATE = 0.1  # LinuxCNC's feed rate of an inverse-time move of length zero


def set_feed_mode(g: float, st: NgcState, actions: list[str]) -> None:
    """A G93/G94/G95 word of the block (before its F)."""
    st.feed_mode = g
    if g != 93.0:
        st.feed = 0.0
    if g != 94.0:
        actions.append(f"G{g:g}")  # the output writes feeds per minute and names the mode in a comment


def check_feed(w: Words, st: NgcState, arc: bool) -> None:
    """LinuxCNC's feed checks of a G1 (``arc``: G2/G3) move."""
    if st.feed_mode == 93.0:
        if "F" not in w.values:
            raise Stop(Code.LCNC_WORDS, f"F word missing with inverse time {'arc' if arc else 'g1'} move", w.gcol(1))
        return
    if st.feed == 0.0:
        message = "Cannot make arc with zero feed rate" if arc else "Cannot do g1 with zero feed rate"
        raise Stop(Code.LCNC_WORDS, message, w.gcol(1))
    if st.feed_mode == 95.0 and st.speed == 0.0:
        raise Stop(Code.LCNC_WORDS, _ZERO_SPEED, w.gcol(1))


def check_cycle_feed(w: Words, st: NgcState) -> None:
    """The feed checks of a canned cycle (after LinuxCNC's zero feed rate check)."""
    if st.feed_mode == 93.0:
        raise Stop(Code.LCNC_CYCLE, "Cannot use inverse time feed with canned cycles", w.gcol(1))


def check_cycle_speed(w: Words, st: NgcState) -> None:
    """A canned cycle under G95 at spindle speed 0: LinuxCNC runs it at feed 0 (it never ends)."""
    if st.feed_mode == 95.0 and st.speed == 0.0:
        raise Stop(
            Code.NC_FEED_MODE,
            "canned cycle under G95 (feed per revolution) at spindle speed 0: its feed F × S is zero (LinuxCNC's "
            "interpreter runs it, the axes would not move); trcopt cannot time it",
            w.gcol(1),
        )


def _inverse_rate(length_mm: float, w: Words, st: NgcState) -> None:
    f = w.values["F"]
    length = length_mm / st.unit
    rate = INVERSE_TIME_ZERO_LENGTH_RATE if length == 0.0 else length * f
    if not rate > 0.0:
        raise Stop(
            Code.NC_FEED_MODE,
            f"inverse time F{f:g}: the move would never end (LinuxCNC's interpreter runs it at feed 0); trcopt "
            "cannot time it",
            w.col("F"),
        )
    st.feed = rate


def inverse_time_line(st: NgcState, end: Vec3, w: Words) -> None:
    """The feed rate of an inverse-time G1 from the current point to ``end`` (mm)."""
    _inverse_rate(math.dist(st.pos, end), w, st)


def inverse_time_arc(move: Move, w: Words, st: NgcState) -> Move:
    """An inverse-time G2/G3 move with its feed rate."""
    _inverse_rate(arc_length(move), w, st)
    return dataclasses.replace(move, feed_mm_s=st.feed_mm_s)


def arc_length(move: Move) -> float:
    """The length of an arc move (mm), a helix with its axial travel (LinuxCNC's ``find_arc_length``):
    the sweep from the start to the end about the centre in the move's sense, a whole turn when they
    coincide, and ``turns`` more whole turns."""
    assert move.center is not None
    plane = move.plane
    s, e, c = plane.to_uvw(move.start), plane.to_uvw(move.end), plane.to_uvw(move.center)
    radius = math.hypot(s[0] - c[0], s[1] - c[1])
    alpha = math.atan2(s[1] - c[1], s[0] - c[0])
    beta = math.atan2(e[1] - c[1], e[0] - c[0])
    if move.ccw:
        if beta <= alpha:
            beta += 2.0 * math.pi
        theta = beta - alpha
    else:
        if alpha <= beta:
            alpha += 2.0 * math.pi
        theta = alpha - beta
    theta += 2.0 * math.pi * move.turns
    dw = e[2] - s[2]
    return radius * theta if dw == 0.0 else math.hypot(radius * theta, dw)
