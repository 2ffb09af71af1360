"""One RS274NGC block executed as LinuxCNC's interpreter does.

LinuxCNC does not execute a block's words in the order written but in a fixed order
(``execute_block``): the comment (messages), the feed mode, F, S, T, ``M6``/``M61``, the spindle and coolant
M codes, then the G codes — dwell, plane, units, cutter compensation, tool length offset
(``G43``/``G43.1``/``G43.2``/``G49``), work system (``G54``…``G59.3``), path control, distance
modes, retract mode (``G98``/``G99``), the non-modal group (``G10``, ``G28``/``G30`` and their
``.1``, ``G52``, ``G92`` family), then the motion (``G0``…``G3``, canned cycles, ``G80``, with
``G53``), and last the stops (``M0``/``M1``/``M2``/``M30``/``M60``). Words are checked first as
LinuxCNC's ``check_items`` does (two codes of one modal group, a word no code uses), with its
messages. The feed modes G93/G94/G95 act first (:mod:`~trcopt.controllers.linuxcnc.ngc_feed`). Known
LinuxCNC codes trcopt does not model (``G33``, ``G38.x``, ``G76``, ``G96``, ``M62``…, …) stop the
read with ``NC-UNSUPPORTED`` naming the code.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_cycles import CYCLES, CycleError, run_cycle
from trcopt.controllers.linuxcnc.ngc_feed import (
    check_cycle_feed,
    check_cycle_speed,
    check_feed,
    inverse_time_arc,
    inverse_time_line,
    set_feed_mode,
)
from trcopt.controllers.linuxcnc.ngc_motion import INCH, NgcState, Stop, arc_move, compensation_on, path_control
from trcopt.controllers.linuxcnc.ngc_offsets import SYSTEM_WORDS, OffsetError
from trcopt.controllers.linuxcnc.ngc_words import Words
from trcopt.errors import SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3
from trcopt.modes import Side
from trcopt.nc.model import CompState, Move, MoveKind, new_move

__all__ = ["Emit", "comp_state", "execute_block", "shifted"]

_PLANES = {17.0: Plane.G17, 18.0: Plane.G18, 19.0: Plane.G19}
_COMP_ON = "with cutter radius compensation on"
_CYCLES = frozenset(CYCLES)
Emit = Callable[[Move], None]


def _comp_check(st: NgcState, message: str, col: int = 0) -> None:
    if st.side is not Side.OFF:
        raise Stop(Code.LCNC_COMP_ACTIVE, message, col)


def execute_block(w: Words, span: SourceSpan, st: NgcState, emit: Emit, arc_tol: float, message: str | None) -> bool:
    """Run one decoded block, emit its moves (the first carries the block's other words as
    actions; a block without motion emits a move of kind NONE); True when the program ends.
    Raises :class:`Stop`."""
    actions: list[str] = [] if message is None else [message]
    out: list[Move] = []

    def first_takes_actions(move: Move) -> None:
        if not out and move.actions != tuple(actions):
            move = dataclasses.replace(move, actions=tuple(actions))
        out.append(move)
        emit(move)

    # the feed mode (G93/G94/G95: trcopt.controllers.linuxcnc.ngc_feed), F, S, T
    feed_mode = w.g.get(5)
    if feed_mode is not None:
        set_feed_mode(feed_mode, st, actions)
    if "F" in w.values:
        f = w.values["F"]
        if st.feed_mode != 93.0:  # inverse time: the F of a G1/G2/G3 gives its move's feed
            st.feed = f
        actions.append(f"F{f:g}")
    if "S" in w.values:
        st.speed = w.values["S"]
        actions.append(f"S{st.speed:g}")
    if "T" in w.values:
        t = int(round(w.values["T"]))
        if t != 0 and st.tools and t not in st.tools:  # no table at all: tools without data
            raise Stop(Code.LCNC_TOOL_NOT_FOUND, f"Requested tool {t} not found in the tool table", w.col("T"))
        st.selected_tool = t
        actions.append(f"T{t}")
    # M codes: tool change, spindle, coolant
    if w.m:  # a block without M codes skips them all
        m6 = w.m.get(6)
        if m6 == 6:
            if st.selected_tool is None:
                raise Stop(Code.LCNC_WORDS, "Need tool prepared -Txx- for toolchange", w.mcol(6))
            _comp_check(st, "Cannot change tools with cutter radius compensation on", w.mcol(6))
            st.spindle = 0
            st.spindle_tool = st.selected_tool
            st.offsets.params.numbered[5400] = float(st.spindle_tool)
            actions.append("M6")
        elif m6 == 61:
            q = w.values.get("Q", -1.0)
            t = int(round(q))
            if t < 0:
                raise Stop(Code.LCNC_WORDS, "Need non-negative Q-word to specify tool number with M61", w.mcol(6))
            if t != 0 and st.tools and t not in st.tools:
                raise Stop(Code.LCNC_TOOL_NOT_FOUND, f"Requested tool {t} not found in the tool table", w.mcol(6))
            st.spindle_tool = t
            st.offsets.params.numbered[5400] = float(t)
            actions.append(f"M61 Q{t}")
        m7 = w.m.get(7)
        if m7 is not None:
            st.spindle = {3: 1, 4: -1, 5: 0}[m7]
            actions.append(f"M{m7}")
        m8 = w.m.get(8)
        if m8 is not None:
            st.mist, st.flood = (m8 == 7 or (st.mist and m8 != 9)), (m8 == 8 or (st.flood and m8 != 9))
            actions.append(f"M{m8}")
        if 9 in w.m:
            actions.append(f"M{w.m[9]}")
    # G codes in LinuxCNC's order
    if len(w.g) > (1 in w.g):  # G codes other than the motion's (group 1)
        if w.g.get(0) == 4.0:
            actions.append(f"G4 P{w.values['P']:g}")
        plane_word = w.g.get(2)
        if plane_word is not None:
            if _PLANES[plane_word] is not st.plane:
                _comp_check(st, "Cannot change planes with cutter radius compensation on", w.gcol(2))
            st.plane = _PLANES[plane_word]
        g = w.g.get(6)
        if g is not None:
            unit = INCH if g == 20.0 else 1.0  # allowed under compensation: LinuxCNC converts its state
            st.unit = unit
            if st.machine_mm is None:
                st.machine_mm = unit
        g = w.g.get(7)
        if g is not None:
            if g != 40.0:
                if st.plane is Plane.G19:
                    message = "Cutter radius compensation allowed only in XY, XZ planes"
                    raise Stop(Code.LCNC_YZ_PLANE, message, w.gcol(7))
                if st.side is not Side.OFF:
                    raise Stop(Code.LCNC_COMP_ALREADY_ON, "Cannot turn cutter radius comp on when on", w.gcol(7))
            compensation_on(g, w.values, st, st.tools)
        g = w.g.get(8)
        if g is not None:
            _tool_length(g, w, st)
        system_word = w.g.get(12)
        if system_word is not None:
            _comp_check(st, "Cannot change coordinate systems with cutter radius compensation on", w.gcol(12))
            system = SYSTEM_WORDS[system_word]
            st.pos = _offset_call(lambda: st.offsets.select(system, st.pos))
        g = w.g.get(13)
        if g is not None:
            path_control(g, w.values, st, w.gcol(13))
        g = w.g.get(3)
        if g is not None:
            st.absolute = g == 90.0
        g = w.g.get(4)
        if g is not None:
            st.ijk_absolute = g == 90.1
        g = w.g.get(10)
        if g is not None:
            st.cycle.retract_old = g == 98.0
    stop = w.m.get(4)
    if stop is not None:
        actions.append(f"M{stop}")
    g0 = w.g.get(0)
    if g0 is not None and g0 not in (4.0, 53.0):
        _modal_zero(g0, w, st, span, first_takes_actions)
    if w.motion is not None:
        _motion(w, st, span, first_takes_actions, actions, arc_tol)
    if not out:
        emit(_shifted(_none(st, span, actions, 7 in w.g), st))
    return stop in (2, 30)


def _offset_call(fn: Callable[[], Vec3]) -> Vec3:
    try:
        return fn()
    except OffsetError as exc:
        raise Stop(exc.code, exc.message) from None


def _axes(w: Words, st: NgcState) -> dict[int, float]:
    return {i: w.values[a] * st.unit for i, a in enumerate("XYZ") if a in w.values}


def _tool_length(g: float, w: Words, st: NgcState) -> None:
    _comp_check(st, "Cannot change tool offset with cutter radius compensation on", w.gcol(8))
    if g == 49.0:
        new: Vec3 = (0.0, 0.0, 0.0)
    elif g == 43.1:
        cur, axes = list(st.offsets.tool), _axes(w, st)
        for i, v in axes.items():
            cur[i] = v
        new = (cur[0], cur[1], cur[2])
    else:
        entry = st.spindle_entry()
        if "H" in w.values:
            h = int(round(w.values["H"]))
            if h != 0:
                found = st.tools.get(h)
                if found is None:
                    raise Stop(Code.LCNC_TOOL_NOT_FOUND, f"Requested tool {h} not found in the tool table", w.col("H"))
                entry = found
        elif g == 43.2 and not _axes(w, st):
            raise Stop(Code.LCNC_WORDS, "G43.2: No axes specified and H word missing", w.gcol(8))
        add: Vec3 = (st.user_mm(entry.offset[0]), st.user_mm(entry.offset[1]), st.user_mm(entry.offset[2]))
        if g == 43.2:
            if "H" in w.values and _axes(w, st):
                raise Stop(Code.LCNC_WORDS, "G43.2: Can not have both H and axis words", w.gcol(8))
            cur = list(st.offsets.tool)
            if "H" in w.values:
                cur = [cur[i] + add[i] for i in range(3)]
            else:
                for i, v in _axes(w, st).items():
                    cur[i] += v
            new = (cur[0], cur[1], cur[2])
        else:
            new = add
    st.pos = st.offsets.set_tool(new, st.pos)


def _modal_zero(g: float, w: Words, st: NgcState, span: SourceSpan, emit: Emit) -> None:
    off = st.offsets
    if g == 10.0:
        _g10(w, st)
    elif g in (28.0, 30.0):
        _comp_check(st, "Cannot use g28 or g30 with cutter radius comp", w.gcol(0))
        which = int(g)
        waypoint = _end(w, st, _axes(w, st))
        _straight(st, waypoint, True, span, emit, ())
        home = _offset_call(lambda: off.reference(which))
        given = [a in w.values for a in "XYZ"]
        if not any(given):
            given = [True, True, True]
        end = tuple(home[i] if given[i] else waypoint[i] for i in range(3))
        # the move to the reference point is a move in machine coordinates (written as G53)
        at = off.machine((end[0], end[1], end[2]))
        home_span = dataclasses.replace(span, machine=tuple(at[i] if given[i] else None for i in range(3)))
        _straight(st, (end[0], end[1], end[2]), True, home_span, emit, ())
    elif g in (28.1, 30.1):
        _comp_check(st, "Cannot set reference point with cutter compensation in effect", w.gcol(0))
        off.save_reference(int(g), st.pos)
    else:  # G52, G92 family
        _comp_check(st, "Cannot change axis offsets with cutter radius comp", w.gcol(0))
        if g == 92.0:
            st.pos = off.g92(_axes(w, st), st.pos)
        elif g == 52.0:
            st.pos = off.g52(_axes(w, st), st.pos)
        elif g in (92.1, 92.2):
            st.pos = off.g92_cancel(g == 92.2, st.pos)
        else:
            st.pos = off.g92_restore(st.pos)


def _g10(w: Words, st: NgcState) -> None:
    l_word = w.values.get("L", -1.0)
    p = w.values.get("P", 0.0)
    p_int = int(p + 0.5) if p >= 0 else int(p - 0.5)
    if l_word not in (0.0, 1.0, 2.0, 10.0, 11.0, 20.0):
        raise Stop(Code.LCNC_OFFSET, "Line with G10 does not have L0, L1, L10, L11, L2, or L20", w.gcol(0))
    if (p + 0.0001) - p_int > 0.0002:
        raise Stop(Code.LCNC_OFFSET, "P value not an integer with G10", w.col("P"))
    lw = int(l_word)
    if lw in (2, 20) and not 0 <= p_int <= 9:
        raise Stop(Code.LCNC_OFFSET, f"P value out of range (0-9) with G10 L{lw}", w.col("P"))
    if lw in (1, 10, 11) and p_int < 1:
        raise Stop(Code.LCNC_OFFSET, f"P value out of range with G10 L{lw}", w.col("P"))
    if lw in (0, 11):
        raise Stop(Code.NC_UNSUPPORTED, f"G10 L{lw} is not supported by the rs274 reader", w.gcol(0))
    axes = _axes(w, st)
    if lw in (2, 20):
        if "R" in w.values:
            if lw == 20:
                raise Stop(Code.LCNC_OFFSET, "R not allowed in G10 L20", w.col("R"))
            if w.values["R"] != 0.0:
                raise Stop(Code.NC_UNSUPPORTED, "a rotated coordinate system (G10 L2 R) is not supported", w.col("R"))
        system = p_int or st.offsets.index
        if system == st.offsets.index:
            _comp_check(st, "Cannot change the active coordinate system with cutter radius compensation on", w.gcol(0))
        st.pos = _offset_call(lambda: st.offsets.set_origin(p_int, axes, lw == 20, st.pos))
        return
    entry = st.tools.get(p_int)
    if entry is None:
        raise Stop(Code.LCNC_TOOL_NOT_FOUND, f"Requested tool {p_int} not found in the tool table", w.col("P"))
    if not any(k in w.values for k in "XYZRQIJ"):
        raise Stop(Code.LCNC_OFFSET, "G10 L1 without offsets has no effect", w.gcol(0))
    mu = st.machine_unit()
    if lw == 1:
        for i, v in axes.items():
            entry.offset[i] = v / mu
    else:  # L10: the offset that makes the current point the given coordinate
        here = [st.pos[i] + st.offsets.tool[i] for i in range(3)]
        for i, v in axes.items():
            entry.offset[i] = (here[i] - v) / mu
    if "R" in w.values:
        entry.diameter = w.values["R"] * st.unit * 2.0 / mu
    if "Q" in w.values:
        q = w.values["Q"]
        if abs(q - round(q)) > 0.0001:
            raise Stop(Code.LCNC_OFFSET, "Q number in G10 is not an integer", w.col("Q"))
        if q > 9:
            raise Stop(Code.LCNC_OFFSET, "Invalid tool orientation", w.col("Q"))
        entry.orientation = int(round(q))


def _end(w: Words, st: NgcState, axes: dict[int, float]) -> Vec3:
    """The end point of a move: absolute or incremental words (program coordinates, mm)."""
    end = list(st.pos)
    for i, v in axes.items():
        end[i] = v if st.absolute else st.pos[i] + v
    return (end[0], end[1], end[2])


def _comp(st: NgcState, side_programmed: bool) -> CompState:
    # the state of the block before is reused while it is the same (the same radius object:
    # a radius of -0.0 or NaN is never taken for another value)
    inch = st.unit != 1.0
    last = _LAST_COMP[0]
    if (
        last is not None and last.radius is st.radius_mm and last.side is st.side
        and last.side_programmed is side_programmed and last.inch is inch and last.orientation == st.orientation
    ):  # fmt: skip
        return last
    comp = CompState(
        side=st.side, radius=st.radius_mm, tool_active=True, side_programmed=side_programmed, inch=inch,
        orientation=st.orientation,
    )
    _LAST_COMP[0] = comp
    return comp


_LAST_COMP: list[CompState | None] = [None]
_LAST_SHIFT: list[tuple[Vec3, Vec3, Vec3 | None, Vec3] | None] = [None]


def _shifted(move: Move, st: NgcState) -> Move:
    """The move in the output frame (the G54 system at the start)."""
    off = st.offsets
    last = _LAST_SHIFT[0]  # (origin, axis, base, shift): the shift while the offsets are the same
    if last is not None and off.loaded and last[0] is off.origin and last[1] is off.axis and last[2] is off.base:
        d = last[3]
    else:
        d = off.fixed((0.0, 0.0, 0.0))
        _LAST_SHIFT[0] = (off.origin, off.axis, off.base, d)
    if d == (0.0, 0.0, 0.0):
        return move

    def sh(p: Vec3) -> Vec3:
        return (p[0] + d[0], p[1] + d[1], p[2] + d[2])

    return new_move(  # dataclasses.replace(move, start=…, end=…, center=…)
        move.kind, sh(move.start), sh(move.end), move.plane, move.span, move.comp, move.feed_mm_s,
        None if move.center is None else sh(move.center), move.ccw, move.turns, move.actions, move.sar,
        move.plane_programmed, move.origin, move.control,
    )  # fmt: skip


comp_state, shifted = _comp, _shifted  # for the plain motion line (ngc_plain)


def _straight(
    st: NgcState, end: Vec3, rapid: bool, span: SourceSpan, emit: Emit, actions: tuple[str, ...],
    side_programmed: bool = False, plane_programmed: bool = True,
) -> None:  # fmt: skip
    kind = MoveKind.RAPID if rapid else MoveKind.LINE
    move = new_move(  # positional (a third faster than keywords): … center, ccw, turns, actions, sar, …
        kind, st.pos, end, st.plane, span, _comp(st, side_programmed), None if rapid else st.feed_mm_s,
        None, None, 0, actions, None, plane_programmed, "", st.control,
    )  # fmt: skip
    emit(_shifted(move, st))
    st.pos = end


def _motion(w: Words, st: NgcState, span: SourceSpan, emit: Emit, actions: list[str], arc_tol: float) -> None:
    motion = w.motion
    assert motion is not None
    side_programmed = 7 in w.g
    if motion not in _CYCLES:
        st.cycle.initial = None
        st.cycle.motion = None
    if motion == 80.0:
        st.motion = None
        return
    st.motion = motion
    axes = _axes(w, st)
    if motion in _CYCLES:
        if st.feed == 0.0:
            raise Stop(Code.LCNC_WORDS, "Cannot feed with zero feed rate", w.gcol(1))
        check_cycle_feed(w, st)
        _comp_check(st, "Cannot use canned cycles with cutter compensation on", w.gcol(1))
        check_cycle_speed(w, st)
        clearance = st.peck_clearance.get(motion, 0.05 if st.machine_unit() == INCH else 1.0)
        plane = st.plane.name if st.plane.name in ("G17", "G18", "G19") else st.plane.value
        try:
            moves, pos = run_cycle(
                motion, w.values, st.unit, st.absolute, plane, st.pos, st.cycle, st.spindle, clearance
            )
        except CycleError as exc:
            code = exc.code if exc.code in (Code.NC_UNSUPPORTED, Code.NC_LOOP_LIMIT) else Code.LCNC_CYCLE
            raise Stop(code, exc.message, w.gcol(1)) from None
        for rapid, end in moves:
            _straight(st, end, rapid, span, emit, ())
        st.pos = pos
        return
    if w.g.get(0) == 53.0:
        if motion not in (0.0, 1.0):
            raise Stop(Code.LCNC_OFFSET, "Must use g0 or g1 with g53", w.gcol(0))
        if not st.absolute:
            raise Stop(Code.LCNC_OFFSET, "Cannot use g53 incremental", w.gcol(0))
        if st.radius_mm != 0.0:  # LinuxCNC runs a move under a zero radius uncompensated
            _comp_check(st, "Cannot use g53 with cutter radius comp", w.gcol(0))
        end = st.offsets.machine_end(axes, st.pos)
        span = dataclasses.replace(span, machine=tuple(axes.get(i) for i in range(3)))
    else:
        end = _end(w, st, axes)
    iu, iv, _ = st.plane.axes
    plane_programmed = "XYZ"[iu] in w.values or "XYZ"[iv] in w.values
    if motion in (2.0, 3.0):
        check_feed(w, st, True)
        if not axes and not any(k in w.values for k in "IJKR"):
            raise Stop(Code.NC_SYNTAX, "G2/G3 without end point or centre")
        move = arc_move(
            st, w.values, st.pos, end, span, _comp(st, side_programmed), tuple(actions), plane_programmed,
            motion == 3.0, arc_tol,
        )  # fmt: skip
        if st.feed_mode == 93.0:
            move = inverse_time_arc(move, w, st)
        emit(_shifted(move, st))
        st.pos = end
        return
    if motion == 1.0:
        check_feed(w, st, False)  # also a G1 without axis words
    if not axes:
        return
    if motion == 1.0 and st.feed_mode == 93.0:
        inverse_time_line(st, end, w)
    _straight(st, end, motion == 0.0, span, emit, tuple(actions), side_programmed, plane_programmed)


def _none(st: NgcState, span: SourceSpan, actions: list[str], side_programmed: bool) -> Move:
    return new_move(
        MoveKind.NONE, st.pos, st.pos, st.plane, span, _comp(st, side_programmed), st.feed_mm_s,
        actions=tuple(actions), control=st.control,
    )  # fmt: skip
