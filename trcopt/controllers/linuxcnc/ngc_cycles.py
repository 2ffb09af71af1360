"""Canned cycles ``G73 G74 G81``–``G89`` expanded into moves as LinuxCNC's interpreter emits them.

A cycle block positions in the plane at rapid, then runs the cycle along the axis normal to the
plane (Z in G17, Y in G18, X in G19) between the R plane and the bottom, and retracts to the R
plane (``G99``, the default) or to the height the cycle started from (``G98``, when that is
above R). ``L`` repeats the cycle; in ``G91`` the plane position moves by X/Y on every repeat, R
is measured from the starting height and the bottom from R. The modal values (R, the bottom, P,
Q, ``G87``'s I/J/K) carry over to the next cycle block of the same G code. ``G73``/``G83`` peck by
Q and back off by the block's ``D`` or the peck clearance (1 program unit, or 0.05 with an inch
machine: LinuxCNC's defaults). ``G88`` (the operator retracts by hand) is not modelled.

:func:`run_cycle` returns the moves (``(rapid?, end)`` in mm program coordinates) and the
position after the cycle; errors are :class:`CycleError` with LinuxCNC's message.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.geometry.vec import Vec3

__all__ = ["CYCLES", "CycleError", "CycleState", "run_cycle"]

CYCLES = (73.0, 74.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0, 87.0, 88.0, 89.0)
# (first, second, normal) axis of each plane, and the letter LinuxCNC names in messages
_AXES = {"G17": (0, 1, 2, "z", "xy"), "G18": (2, 0, 1, "y", "xz"), "G19": (1, 2, 0, "x", "yz")}
_DWELL = {82.0, 86.0, 88.0, 89.0}
MAX_PECKS = 100_000  # pecks of a G73/G83 block, repeats of a cycle: beyond, an NC-LOOP-LIMIT error


class CycleError(Exception):
    def __init__(self, message: str, code: Code = Code.NC_SYNTAX) -> None:
        super().__init__(message)
        self.message, self.code = message, code


@dataclass(slots=True)
class CycleState:
    """The modal values cycles keep (LinuxCNC's ``cycle_*``; lengths in mm)."""

    motion: float | None = None  # the cycle in force (None: not a cycle)
    r: float = 0.0
    bottom: float = 0.0
    p: float = 0.0
    q: float = 0.0
    ijk: tuple[float, float, float] = (0.0, 0.0, 0.0)
    initial: float | None = None  # the height the cycles started from (G98), kept while they repeat
    retract_old: bool = False  # G98


def _point(axes: tuple[int, int, int], a: float, b: float, c: float) -> Vec3:
    p = [0.0, 0.0, 0.0]
    p[axes[0]], p[axes[1]], p[axes[2]] = a, b, c
    return (p[0], p[1], p[2])


def run_cycle(
    g: float,
    values: Mapping[str, float],
    unit: float,
    absolute: bool,
    plane: str,
    pos: Vec3,
    state: CycleState,
    spindle: int,
    peck_clearance: float,
) -> tuple[list[tuple[bool, Vec3]], Vec3]:
    """The moves of one cycle block (``values``: the block's words, program units; ``unit``: mm
    per program unit; ``spindle`` 1 cw, -1 ccw, 0 stopped)."""
    ia, ib, ic, normal, name = _AXES[plane]
    axes = (ia, ib, ic)
    letters = "XYZ"
    same = state.motion == g
    if "R" in values:
        r_word = values["R"] * unit
    elif same:
        r_word = state.r
    else:
        raise CycleError("R clearance plane unspecified in cycle")
    repeats = values.get("L", 1.0)
    if repeats == 0:
        raise CycleError("Cannot do zero repeats of cycle")
    n = int(round(repeats))
    if not same and letters[ic] not in values:
        raise CycleError(f"{normal.upper()} value unspecified in {name} plane canned cycle")
    cc_word = values[letters[ic]] * unit if letters[ic] in values else state.bottom
    current_cc = pos[ic]
    if state.initial is None:
        state.initial = current_cc
    old_cc = state.initial
    inc_a = inc_b = 0.0
    if absolute:
        r, cc = r_word, cc_word
        aa = values[letters[ia]] * unit if letters[ia] in values else pos[ia]
        bb = values[letters[ib]] * unit if letters[ib] in values else pos[ib]
    else:
        inc_a = values.get(letters[ia], 0.0) * unit
        inc_b = values.get(letters[ib], 0.0) * unit
        r = r_word + old_cc
        cc = r + cc_word
        aa, bb = pos[ia], pos[ib]
    if r < cc:
        raise CycleError(f"R less than {normal} in cycle in {name} plane")
    moves: list[tuple[bool, Vec3]] = []

    def rapid(a: float, b: float, c: float) -> None:
        moves.append((True, _point(axes, a, b, c)))

    def feed(a: float, b: float, c: float) -> None:
        moves.append((False, _point(axes, a, b, c)))

    if old_cc < r:
        rapid(pos[ia], pos[ib], r)
        old_cc = current_cc = r
    clear = r if not state.retract_old else old_cc
    # the modal words of this cycle: checked before any move of the block
    p = state.p
    if g in _DWELL or g in (74.0, 84.0):
        if "P" in values:
            p = values["P"]
        elif not same and g in _DWELL:
            raise CycleError(f"Dwell time p word missing with g{g:g}")
    q = state.q
    if g in (73.0, 83.0):
        if "Q" in values:
            q = values["Q"] * unit
        elif not same:
            raise CycleError(f"Q word missing with g{g:g}")
        if q <= 0.0:
            raise CycleError("Negative or zero q value used")
    ijk = state.ijk
    if g == 87.0:
        if not same:
            for letter in "IJK":
                if letter not in values:
                    raise CycleError(f"{letter} word missing with g87")
        ijk = (
            values["I"] * unit if "I" in values else ijk[0],
            values["J"] * unit if "J" in values else ijk[1],
            values["K"] * unit if "K" in values else ijk[2],
        )
    if g == 88.0:
        raise CycleError(
            "G88 (boring, the operator retracts the spindle by hand) is not supported", Code.NC_UNSUPPORTED
        )
    if g in (74.0, 84.0):
        if spindle == 0:
            raise CycleError(f"Spindle not turning in G{g:g}")
        if g == 84.0 and spindle < 0:
            raise CycleError("Spindle turning counterclockwise in G84")
        if g == 74.0 and spindle > 0:
            raise CycleError("Spindle turning clockwise in G74")
    if g in (86.0, 87.0) and spindle == 0:
        raise CycleError(f"Spindle not turning in g{g:g}")
    back = values["D"] * unit if "D" in values else peck_clearance * unit
    if g in (73.0, 83.0) and (r - cc) / q > MAX_PECKS:
        raise CycleError(f"G{g:g}: more than {MAX_PECKS} pecks of Q; the cycle is taken as endless", Code.NC_LOOP_LIMIT)
    if n > MAX_PECKS:
        raise CycleError(f"G{g:g}: more than {MAX_PECKS} repeats (L)", Code.NC_LOOP_LIMIT)
    for k in range(n):
        aa, bb = aa + inc_a, bb + inc_b
        if k == 0 and current_cc > r:
            rapid(aa, bb, current_cc)
            rapid(aa, bb, r)
        else:
            rapid(aa, bb, clear)
            if clear > r:
                rapid(aa, bb, r)
        if g in (81.0, 82.0, 86.0):
            feed(aa, bb, cc)
            rapid(aa, bb, clear)
        elif g in (73.0, 83.0):
            depth = r - q
            while depth > cc:
                feed(aa, bb, depth)
                if g == 83.0:
                    rapid(aa, bb, r)
                rapid(aa, bb, depth + back)
                depth -= q
            feed(aa, bb, cc)
            rapid(aa, bb, clear)
        elif g in (74.0, 84.0) and plane != "G17":
            # LinuxCNC's tapping in XZ and YZ passes its coordinates in another order than its
            # other cycles: the feed runs along the plane's first axis, reproduced as it moves
            for depth in (cc, clear):
                moves.append((False, (depth, aa, bb) if plane == "G18" else (bb, depth, aa)))
        elif g in (74.0, 84.0, 89.0):
            feed(aa, bb, cc)
            feed(aa, bb, clear)
        elif g == 85.0:
            feed(aa, bb, cc)
            feed(aa, bb, r)
            rapid(aa, bb, clear)
        else:  # G87 back boring: the plane's own centre words offset, the third is the top
            i, j, kk = (ijk[ia], ijk[ib], ijk[ic])
            oa, ob = aa + i, bb + j
            middle = kk if absolute else cc + kk
            rapid(oa, ob, r)
            rapid(oa, ob, cc)
            rapid(aa, bb, cc)
            feed(aa, bb, middle)
            feed(aa, bb, cc)
            rapid(oa, ob, cc)
            rapid(oa, ob, clear)
            rapid(aa, bb, clear)
    state.motion, state.r, state.bottom = g, r_word, cc_word
    state.p, state.q, state.ijk = p, q, ijk
    return moves, _point(axes, aa, bb, clear)
