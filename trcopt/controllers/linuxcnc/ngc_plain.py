"""A plain motion line executed without decoding its words: the common block of CAM programs.

A plain motion line (:data:`~trcopt.controllers.linuxcnc.ngc_flow.PLAIN_MOTION`: an optional
``N`` number, then ``G0``/``G1``, ``X``, ``Y``, ``Z``, ``F`` with plain numbers, each at most once,
at least one axis, every number within a float's range) is what
:func:`~trcopt.controllers.linuxcnc.ngc_words.decode` and
:func:`~trcopt.controllers.linuxcnc.ngc_exec.execute_block` would run as: the feed (an ``F``
action), the motion mode, one straight move from the current point to the end point (absolute or
incremental), nothing else. :func:`execute_plain` does exactly that when the block cannot fail
in the state it runs in (under G94: with G93/G95 the feed is not the F, the line runs the general
way); otherwise it changes nothing and returns False, and the caller reads and executes the line as
any other (which then raises the error LinuxCNC gives, at its column).
"""

from __future__ import annotations

from trcopt.controllers.linuxcnc.ngc_exec import Emit, comp_state, shifted
from trcopt.controllers.linuxcnc.ngc_expr import Parameters
from trcopt.controllers.linuxcnc.ngc_motion import NgcState
from trcopt.errors import SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.modes import Side
from trcopt.nc.model import MoveKind, new_move

__all__ = ["execute_plain"]

_RAPID, _LINE, _G17 = MoveKind.RAPID, MoveKind.LINE, Plane.G17


def execute_plain(
    plain: tuple[str | None, str | None, str | None, str | None, str | None],
    span: SourceSpan,
    st: NgcState,
    emit: Emit,
    params: Parameters,
) -> bool:
    """Run a plain motion line (G, X, Y, Z, F numbers as written, None: no such word) as
    ``execute_block`` runs it and set the parameters a block leaves (#5420…#5422, whether
    compensation is on); False (and nothing changed) when it would not simply move."""
    g, x, y, z, f = plain
    if st.feed_mode != 94.0:
        return False  # G93/G95: the feed of the move is not F (trcopt.controllers.linuxcnc.ngc_feed)
    if g is None:
        motion = st.motion  # the modal motion: only G0/G1 are plain (arcs, cycles, none: not)
        if motion != 0.0 and motion != 1.0:
            return False
    else:
        motion = float(g)  # 0.0 or 1.0 by the pattern
    feed = st.feed if f is None else float(f)
    if motion == 1.0 and feed == 0.0:
        return False  # "Cannot do g1 with zero feed rate"
    unit, pos = st.unit, st.pos
    if st.absolute:
        ex = pos[0] if x is None else float(x) * unit
        ey = pos[1] if y is None else float(y) * unit
        ez = pos[2] if z is None else float(z) * unit
    else:
        ex = pos[0] if x is None else pos[0] + float(x) * unit
        ey = pos[1] if y is None else pos[1] + float(y) * unit
        ez = pos[2] if z is None else pos[2] + float(z) * unit
    # the block runs: the same state changes as execute_block's, in its order
    actions: tuple[str, ...] = ()
    if f is not None:
        st.feed = feed
        actions = (f"F{feed:g}",)
    cycle = st.cycle
    cycle.initial = None
    cycle.motion = None
    st.motion = motion
    plane = st.plane
    if plane is _G17:
        plane_programmed = x is not None or y is not None
    else:
        iu, iv, _ = plane.axes
        written = (x is not None, y is not None, z is not None)
        plane_programmed = written[iu] or written[iv]
    rapid = motion == 0.0
    end = (ex, ey, ez)
    move = new_move(  # positional (a third faster than keywords): … center, ccw, turns, actions, sar, …
        _RAPID if rapid else _LINE, pos, end, plane, span, comp_state(st, False), None if rapid else st.feed_mm_s,
        None, None, 0, actions, None, plane_programmed, "", st.control,
    )  # fmt: skip
    emit(shifted(move, st))
    st.pos = end
    # the parameters every block leaves (as the reader sets them after a block): the current point, comp on
    numbered = params.numbered
    numbered[5420] = ex / unit
    numbered[5421] = ey / unit
    numbered[5422] = ez / unit
    params.comp_on = st.side is not Side.OFF
    return True
