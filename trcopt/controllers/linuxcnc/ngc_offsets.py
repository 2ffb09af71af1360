"""Coordinate systems and offsets as LinuxCNC's interpreter keeps them.

LinuxCNC holds the tool's *program* position (the controlled point in the active work system)
and three offsets that map it onto the machine: the work offset of the active system ``G54`` …
``G59.3`` (parameters ``#5221 + 20·(n−1)`` …), the ``G92`` axis offset (``#5211``…``#5213``,
``#5210`` = applied) and the tool length offset (``G43``/``G43.1``/``G43.2``)::

    machine = program + G92 offset + work offset + tool length offset

Every change of an offset changes the program position so that the machine does not move
(``G92 X0`` makes the current point X0). ``G53`` moves, ``G28``/``G30`` (reference points
``#5161``… / ``#5181``…, in machine coordinates) and ``G28.1``/``G30.1`` go through the same
relation. Parameter values are in the *machine unit* (LinuxCNC's ``USER`` unit: the tool-table
unit, see :class:`Offsets`), positions here in mm.

The moves trcopt outputs are the program position expressed in one fixed frame: the G54 system
as it stands when the program starts (:meth:`Offsets.fixed`) — the same numbers as ``rs274``
prints while G54 is active without G92, and a continuous path when the program changes system.
XY rotation (``G10 L2 R``) is not modelled: it stops the read with ``NC-UNSUPPORTED``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_expr import Parameters
from trcopt.geometry.vec import Vec3

__all__ = ["Offsets", "OffsetError", "SYSTEM_WORDS", "origin_param"]

SYSTEM_WORDS = {54.0: 1, 55.0: 2, 56.0: 3, 57.0: 4, 58.0: 5, 59.0: 6, 59.1: 7, 59.2: 8, 59.3: 9}
G92_APPLIED, G92_FIRST = 5210, 5211
HOME_FIRST = {28: 5161, 30: 5181}
TOOL_OFFSET_PARAMS = 5081  # #5081… : the tool length offset in force
POSITION_PARAMS = 5420  # #5420… : the current program position


def origin_param(system: int, axis: int = 0) -> int:
    """Parameter number of a work offset: system 1 (G54) … 9 (G59.3), axis 0 X … 2 Z."""
    return 5201 + 20 * system + axis


class OffsetError(Exception):
    def __init__(self, code: Code, message: str) -> None:
        super().__init__(message)
        self.code, self.message = code, message


def _add(a: Vec3, b: Vec3, k: float = 1.0) -> Vec3:
    return (a[0] + k * b[0], a[1] + k * b[1], a[2] + k * b[2])


@dataclass(slots=True)
class Offsets:
    """The offsets in force (mm) and the parameters that store them (machine units).

    ``machine_mm`` answers the mm per machine unit (asked only when a parameter is read or
    written, so that a reader whose machine unit is the program's can decide it late).
    """

    params: Parameters
    machine_mm: Callable[[], float]
    index: int = 1
    origin: Vec3 = (0.0, 0.0, 0.0)
    axis: Vec3 = (0.0, 0.0, 0.0)
    tool: Vec3 = (0.0, 0.0, 0.0)
    base: Vec3 | None = None  # the G54 origin at the start: the output frame
    loaded: bool = field(default=False)

    # -- parameters -------------------------------------------------------------------------
    def _get(self, number: int) -> float:
        value = self.params.numbered[number]
        return value * self.machine_mm() if value else 0.0  # a zero decides no unit

    def _set(self, number: int, mm: float) -> None:
        self.params.numbered[number] = mm / self.machine_mm() if mm else 0.0

    def _origin_of(self, system: int) -> Vec3:
        return (
            self._get(origin_param(system, 0)),
            self._get(origin_param(system, 1)),
            self._get(origin_param(system, 2)),
        )

    def start(self) -> None:
        """Read the active system from ``#5220`` and the offsets from their parameters (once,
        before the first block uses them)."""
        if self.loaded:
            return
        self.loaded = True
        p = self.params.numbered
        index = int(p[5220]) if 1 <= p[5220] <= 9 else 1
        p[5220] = float(index)
        self._check_rotation(index)
        self.index = index
        self.origin = self._origin_of(index)
        self.base = self._origin_of(1)
        if p[G92_APPLIED]:
            self.axis = (self._get(G92_FIRST), self._get(G92_FIRST + 1), self._get(G92_FIRST + 2))

    def _check_rotation(self, system: int) -> None:
        if self.params.numbered[origin_param(system, 9)] != 0.0:
            raise OffsetError(Code.NC_UNSUPPORTED, "a rotated coordinate system (G10 L2 R, #5210+20n) is not supported")

    # -- the output frame ---------------------------------------------------------------------
    def fixed(self, pos: Vec3) -> Vec3:
        """A program position in the output frame (G54 at the start)."""
        self.start()
        base = self.base or (0.0, 0.0, 0.0)
        return _add(_add(pos, self.origin), _add(self.axis, base, -1.0))

    def machine(self, pos: Vec3) -> Vec3:
        """LinuxCNC's absolute position (``#<_abs_x>``…): program + all offsets."""
        self.start()
        return _add(_add(pos, self.axis), _add(self.origin, self.tool))

    # -- G54 … G59.3 --------------------------------------------------------------------------
    def select(self, system: int, pos: Vec3) -> Vec3:
        """``convert_coordinate_system``: the program position in the newly active system."""
        self.start()
        if system == self.index:
            return pos
        self._check_rotation(system)
        new = self._origin_of(system)
        pos = _add(_add(pos, self.origin), new, -1.0)
        self.index, self.origin = system, new
        self.params.numbered[5220] = float(system)
        return pos

    # -- G10 L2 / L20 -------------------------------------------------------------------------
    def set_origin(self, system: int, values: dict[int, float], l20: bool, pos: Vec3) -> Vec3:
        """``G10 L2`` (the values are the offsets) or ``G10 L20`` (the values are where the
        current point shall be in that system; P0 = the active one). Returns the new program
        position (it changes when the system is the active one)."""
        self.start()
        if system == 0:
            system = self.index
        self._check_rotation(system)
        old = list(self._origin_of(system))
        if l20:
            # the current point seen in that system (LinuxCNC's find_current_in_system)
            cur = _add(_add(pos, self.origin), self._origin_of(system), -1.0)
            if not self.params.numbered[G92_APPLIED]:
                cur = _add(cur, self.axis)
            for axis, value in values.items():
                old[axis] = cur[axis] + old[axis] - value
        else:
            for axis, value in values.items():
                old[axis] = value
        for axis in range(3):
            self._set(origin_param(system, axis), old[axis])
        if system != self.index:
            return pos
        new: Vec3 = (old[0], old[1], old[2])
        pos = _add(_add(pos, self.origin), new, -1.0)
        self.origin = new
        return pos

    # -- G92 family ---------------------------------------------------------------------------
    def g92(self, values: dict[int, float], pos: Vec3) -> Vec3:
        """``G92``: the current point gets the given coordinates."""
        self.start()
        p, axis = list(pos), list(self.axis)
        for i, value in values.items():
            axis[i] = p[i] + axis[i] - value
            p[i] = value
        self.axis = (axis[0], axis[1], axis[2])
        self.params.numbered[G92_APPLIED] = 1.0
        for i in range(3):
            self._set(G92_FIRST + i, axis[i])
        return (p[0], p[1], p[2])

    def g52(self, values: dict[int, float], pos: Vec3) -> Vec3:
        """``G52``: a local offset (the same store as G92)."""
        self.start()
        p, axis = list(pos), list(self.axis)
        for i, value in values.items():
            p[i] += axis[i] - value
            axis[i] = value
        self.axis = (axis[0], axis[1], axis[2])
        self.params.numbered[G92_APPLIED] = 1.0
        for i in range(3):
            self._set(G92_FIRST + i, axis[i])
        return (p[0], p[1], p[2])

    def g92_cancel(self, keep_parameters: bool, pos: Vec3) -> Vec3:
        """``G92.1`` (parameters zeroed) and ``G92.2`` (parameters kept)."""
        self.start()
        pos = _add(pos, self.axis)
        self.axis = (0.0, 0.0, 0.0)
        self.params.numbered[G92_APPLIED] = 0.0
        if not keep_parameters:
            for i in range(3):
                self.params.numbered[G92_FIRST + i] = 0.0
        return pos

    def g92_restore(self, pos: Vec3) -> Vec3:
        """``G92.3``: the offsets from the parameters again."""
        self.start()
        new = (self._get(G92_FIRST), self._get(G92_FIRST + 1), self._get(G92_FIRST + 2))
        pos = _add(_add(pos, self.axis), new, -1.0)
        self.axis = new
        self.params.numbered[G92_APPLIED] = 1.0
        return pos

    # -- G53, G28/G30 -------------------------------------------------------------------------
    def machine_end(self, values: dict[int, float], pos: Vec3) -> Vec3:
        """The end of a ``G53`` move: the given axes are machine coordinates."""
        self.start()
        end = list(pos)
        for i, value in values.items():
            end[i] = value - self.origin[i] - self.axis[i] - self.tool[i]
        return (end[0], end[1], end[2])

    def reference(self, which: int) -> Vec3:
        """The ``G28``/``G30`` reference point in program coordinates."""
        self.start()
        first = HOME_FIRST[which]
        home = (self._get(first), self._get(first + 1), self._get(first + 2))
        return _add(_add(home, self.origin, -1.0), _add(self.axis, self.tool), -1.0)

    def save_reference(self, which: int, pos: Vec3) -> None:
        """``G28.1``/``G30.1``: the current point, in machine coordinates."""
        here = self.machine(pos)
        for i in range(3):
            self._set(HOME_FIRST[which] + i, here[i])

    # -- tool length offset ---------------------------------------------------------------------
    def set_tool(self, tool: Vec3, pos: Vec3) -> Vec3:
        """A new tool length offset (``G43``, ``G43.1``, ``G43.2``, ``G49``); the machine stays."""
        self.start()
        pos = _add(_add(pos, self.tool), tool, -1.0)
        self.tool = tool
        for i in range(3):
            self._set(TOOL_OFFSET_PARAMS + i, tool[i])
        return pos
