"""Coordinate transformation cycles of the Klartext reader: ``CYCL DEF 7`` datum shift, ``8``
mirror image, ``10`` rotation, ``11`` scaling and ``26`` axis-specific scaling.

A programmed point p (program coordinates) is at ``D + M·R·S(p)`` in the preset (work) system, in
the order the TNC manuals give for combined transformations (datum shift, mirror, rotation,
scaling), whatever order the cycles were programmed in:

* D — datum shift (``7.1 X… Y… Z…``; ``IX…`` adds to the active shift; not entered axes keep
  theirs; ``X+0 Y+0 Z+0`` resets it);
* M — mirror image of the entered plane axes (``8.1 X Y``; ``8.1`` without an axis resets it);
  mirroring the tool axis is not modelled (``HH-NOT-MODELLED``);
* R — rotation about the tool axis by ``ROT`` degrees, counter-clockwise from the reference axis
  of the working plane (``10.1 ROT+35``; ``IROT`` adds; ``ROT+0`` resets it);
* S — scaling of the three main axes by ``SCL`` (``11.1 SCL 0.75``; ``SCL 1`` resets it) times the
  axis-specific factors of cycle 26 about its centre (``26.1 X1.4 Y0.6 CCX+15 CCY+20``).

A scale factor of 0 (or below) makes the plane degenerate: ``HH-FRAME``. Compensation works in the
transformed frame as the controller's does: the reader transforms each programmed point and
compensates the transformed contour with the physical tool radius; a mirror with one plane axis
reverses the compensation side and the direction of arcs (the tool path is the mirror image).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.controllers.heidenhain.lexer import Word
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3

__all__ = ["Frame", "FrameError", "apply_cycle", "FRAME_CYCLES"]

FRAME_CYCLES = ("7", "8", "10", "11", "26")
_AXES = {"X": 0, "Y": 1, "Z": 2}
Mat = tuple[Vec3, Vec3, Vec3]


class FrameError(Exception):
    def __init__(self, code: Code, message: str, column: int | None = None) -> None:
        super().__init__(message)
        self.code, self.message, self.column = code, message, column


def _mul(a: Mat, p: Vec3) -> Vec3:
    return (
        a[0][0] * p[0] + a[0][1] * p[1] + a[0][2] * p[2],
        a[1][0] * p[0] + a[1][1] * p[1] + a[1][2] * p[2],
        a[2][0] * p[0] + a[2][1] * p[1] + a[2][2] * p[2],
    )


def _inverse(a: Mat) -> Mat:
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    c00, c01, c02 = a11 * a22 - a12 * a21, a12 * a20 - a10 * a22, a10 * a21 - a11 * a20
    det = a00 * c00 + a01 * c01 + a02 * c02
    inv = 1.0 / det
    return (
        (c00 * inv, (a02 * a21 - a01 * a22) * inv, (a01 * a12 - a02 * a11) * inv),
        (c01 * inv, (a00 * a22 - a02 * a20) * inv, (a02 * a10 - a00 * a12) * inv),
        (c02 * inv, (a01 * a20 - a00 * a21) * inv, (a00 * a11 - a01 * a10) * inv),
    )


@dataclass(slots=True)
class Frame:
    """The active transformation cycles (see the module docstring)."""

    shift: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    mirror: set[int] = field(default_factory=set)
    rotation: float = 0.0
    scale: float = 1.0
    axis_scale: list[float] = field(default_factory=lambda: [1.0, 1.0, 1.0])
    axis_centre: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])

    def identity(self) -> bool:
        return (
            self.shift == [0.0, 0.0, 0.0]
            and not self.mirror
            and self.rotation % 360.0 == 0.0
            and self.scale == 1.0
            and self.axis_scale == [1.0, 1.0, 1.0]
        )

    def _linear(self, plane: Plane, p: Vec3) -> Vec3:
        return self._rotate_mirror(plane, [self.scale * self.axis_scale[i] * p[i] for i in range(3)])

    def _rotate_mirror(self, plane: Plane, q: list[float]) -> Vec3:
        u, v, _ = plane.axes
        c, s = math.cos(math.radians(self.rotation)), math.sin(math.radians(self.rotation))
        if self.rotation % 360.0 != 0.0:
            q[u], q[v] = c * q[u] - s * q[v], s * q[u] + c * q[v]
        for i in self.mirror:
            q[i] = -q[i]
        return (q[0], q[1], q[2])

    def matrix(self, plane: Plane) -> tuple[Mat, Vec3]:
        """``(A, d)`` with ``work = A·p + d``."""
        cols = [self._linear(plane, e) for e in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))]
        a: Mat = tuple((cols[0][r], cols[1][r], cols[2][r]) for r in range(3))  # type: ignore[assignment]
        c = self.axis_centre
        off = self._rotate_mirror(plane, [self.scale * c[i] * (1.0 - self.axis_scale[i]) for i in range(3)])
        return a, (self.shift[0] + off[0], self.shift[1] + off[1], self.shift[2] + off[2])

    def to_work(self, p: Vec3, plane: Plane) -> Vec3:
        if self.identity():
            return p
        a, d = self.matrix(plane)
        q = _mul(a, p)
        return (q[0] + d[0], q[1] + d[1], q[2] + d[2])

    def to_prog(self, p: Vec3, plane: Plane) -> Vec3:
        if self.identity():
            return p
        a, d = self.matrix(plane)
        return _mul(_inverse(a), (p[0] - d[0], p[1] - d[1], p[2] - d[2]))

    def mirrored(self, plane: Plane) -> bool:
        """Whether the working plane is mirrored (an odd number of its axes): sides and arc
        directions reverse."""
        u, v, _ = plane.axes
        return (u in self.mirror) != (v in self.mirror)

    def plane_scale(self, plane: Plane) -> float | None:
        """The length factor in the working plane, or None where the plane is scaled unevenly
        (cycle 26 with different factors: circles would become ellipses)."""
        u, v, _ = plane.axes
        if abs(self.axis_scale[u] - self.axis_scale[v]) > 1e-12:
            return None
        return self.scale * self.axis_scale[u]

    def rigid_axes(self, plane: Plane) -> bool:
        """No rotation and no scaling in the plane: the program axes are the machine axes."""
        return self.rotation % 360.0 == 0.0 and self.plane_scale(plane) == 1.0


def _factor(value: float, what: str, column: int) -> float:
    if value <= 0.0:
        raise FrameError(
            Code.HH_FRAME,
            f"{what} {value:g}: a scale factor must be > 0 (0 makes the working plane degenerate)",
            column,
        )
    return value


def apply_cycle(frame: Frame, number: str, words: tuple[Word, ...], unit: float, plane: Plane, column: int) -> None:
    """Apply one block ``CYCL DEF <number> <words>`` of a transformation cycle to ``frame``."""
    cycle, _, sub = number.partition(".")
    if sub in ("", "0"):
        return  # the cycle's title block (7.0 DATUM SHIFT …)
    if cycle == "7":
        for w in words:
            if w.value is None or w.address not in ("X", "Y", "Z", "IX", "IY", "IZ"):
                what = "a datum table (#)" if w.text.startswith("#") else repr(w.text)
                raise FrameError(Code.HH_NOT_MODELLED, f"CYCL DEF {number}: {what} is not modelled", w.column)
            i = _AXES[w.address[-1]]
            v = w.value * unit
            frame.shift[i] = frame.shift[i] + v if w.address.startswith("I") else v
    elif cycle == "8":
        axes = set()
        for w in words:
            name = w.text.upper()
            if w.address != "" or name not in _AXES:
                raise FrameError(
                    Code.HH_SYNTAX, f"CYCL DEF {number}: mirror axis X, Y or Z expected, not {w.text!r}", w.column
                )
            if _AXES[name] == plane.axes[2]:
                raise FrameError(
                    Code.HH_NOT_MODELLED, f"CYCL DEF {number}: mirroring the tool axis {name} is not modelled", w.column
                )
            axes.add(_AXES[name])
        frame.mirror = axes
    elif cycle == "10":
        if len(words) != 1 or words[0].address not in ("ROT", "IROT"):
            raise FrameError(
                Code.HH_SYNTAX, f"CYCL DEF {number}: expected ROT… or IROT…", words[0].column if words else column
            )
        w = words[0]
        assert w.value is not None
        frame.rotation = frame.rotation + w.value if w.address == "IROT" else w.value
    elif cycle == "11":
        if len(words) != 1 or words[0].address != "SCL":
            raise FrameError(Code.HH_SYNTAX, f"CYCL DEF {number}: expected SCL…", words[0].column if words else column)
        assert words[0].value is not None
        frame.scale = _factor(words[0].value, "SCL", words[0].column)
    elif cycle == "26":
        factors, centre = [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]
        for w in words:
            if w.value is not None and w.address in _AXES:
                factors[_AXES[w.address]] = _factor(w.value, w.address, w.column)
            elif w.value is not None and w.address in ("CCX", "CCY", "CCZ"):
                centre[_AXES[w.address[-1]]] = w.value * unit
            else:
                raise FrameError(
                    Code.HH_SYNTAX,
                    f"CYCL DEF {number}: expected X/Y/Z factors and CCX/CCY/CCZ, not {w.text!r}",
                    w.column,
                )
        frame.axis_scale, frame.axis_centre = factors, centre
    else:  # pragma: no cover - the caller dispatches FRAME_CYCLES only
        raise FrameError(Code.HH_NOT_MODELLED, f"CYCL DEF {number} is not modelled", column)
