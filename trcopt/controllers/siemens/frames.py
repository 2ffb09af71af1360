"""SINUMERIK frames: the programmable frame (TRANS/ATRANS, ROT/AROT, SCALE/ASCALE, MIRROR/AMIRROR),
the settable zero offsets (G54…G57, G505…G599, G500) and the block-wise suppression (G53, G153, SUPA).

Coordinates. A block's axis words are in the workpiece coordinate system (WCS). trcopt's plan is
in the *settable zero system* (SZS) of the settable zero offset in force at the program's first
motion (the *reference*, usually G54): ``P_szs = F(P_wcs)`` with ``F`` the programmable frame.
The settable offset itself is not added (the plan is what a G54 workpiece drawing shows). When the
program selects another settable offset after its first motion, the difference of the two
offsets (from the zero-offset file) is added so that the path stays in the reference system; a
block under G53/G153/SUPA is in machine coordinates: ``P_szs = P_mcs - offset(reference)``.

Frame composition as the Programming Manual (Fundamentals, "Frames") describes it: the
substitutional instructions ``TRANS``, ``ROT``, ``SCALE``, ``MIRROR`` replace the whole programmable
frame (alone in their block they delete it); the additive ones ``ATRANS``, ``AROT``, ``ASCALE``,
``AMIRROR`` act in the current WCS, ``F_new = F_old ∘ component`` (an ``ATRANS`` after a ``SCALE``
is scaled). ``ROT X… Y… Z…`` turns about Z, then Y, then X (RPY, MD10600 = 1); ``RPL=`` turns in the
active plane. ``MIRROR X0`` reverses the X axis (the value is not used).

Zero-offset file (TOML, mm in machine coordinates)::

    [G54]
    X = -250.0      # translation (mm)
    Y = -120.0
    Z = -310.0
    ROT_Z = 30.0    # optional: rotation about Z (degrees, counter-clockwise seen from +Z)
    SCALE = 1.0     # optional: scale factor of all three axes (≠ 0)

A settable frame is composed as a SINUMERIK frame is (translation, then rotation, then scale):
``P_mcs = T + R(ROT_Z)·SCALE·P_szs``; the programmable frame acts inside it,
``P_mcs = S(F(P_wcs))``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

from trcopt.config import file_beside, read_toml
from trcopt.errors import ConfigError
from trcopt.geometry.plane import Plane
from trcopt.nc.limits import MAX_COORDINATE_MM

__all__ = [
    "Frame",
    "IDENTITY",
    "translation",
    "rotation",
    "scaling",
    "mirroring",
    "ZeroOffsets",
    "load_zero_offsets",
    "find_zero_offsets",
    "SETTABLE_G",
    "FRAME_WORDS",
]

Vec = tuple[float, float, float]
Mat = tuple[Vec, Vec, Vec]

#: G codes of the settable zero offsets (group 8): G500, G54…G57, G505…G599
SETTABLE_G = frozenset([500, 54, 55, 56, 57, *range(505, 600)])
#: the frame instructions (each alone in its block, with its axis values)
FRAME_WORDS = frozenset(["TRANS", "ATRANS", "ROT", "AROT", "SCALE", "ASCALE", "MIRROR", "AMIRROR"])
_EPS = 1e-12


@dataclass(frozen=True, slots=True)
class Frame:
    """An affine map ``p ↦ m·p + t`` (WCS → SZS)."""

    m: Mat = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    t: Vec = (0.0, 0.0, 0.0)

    @property
    def identity(self) -> bool:
        return self == IDENTITY

    def apply(self, p: Vec) -> Vec:
        m, t = self.m, self.t
        return (
            m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2] + t[0],
            m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2] + t[1],
            m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2] + t[2],
        )

    def invert(self, p: Vec) -> Vec:
        """The WCS point whose image is ``p``."""
        q = (p[0] - self.t[0], p[1] - self.t[1], p[2] - self.t[2])
        inv = _inverse(self.m)
        return tuple(inv[i][0] * q[0] + inv[i][1] * q[1] + inv[i][2] * q[2] for i in range(3))  # type: ignore[return-value]

    def inverse(self) -> Frame:
        """The map back: ``inverse().apply(apply(p)) == p``."""
        inv = _inverse(self.m)
        t = tuple(-sum(inv[i][k] * self.t[k] for k in range(3)) for i in range(3))
        return Frame(inv, t)  # type: ignore[arg-type]

    def then(self, inner: Frame) -> Frame:
        """``self ∘ inner``: first ``inner``, then ``self``."""
        a, b = self.m, inner.m
        m = tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))
        t = tuple(sum(a[i][k] * inner.t[k] for k in range(3)) + self.t[i] for i in range(3))
        return Frame(m, t)  # type: ignore[arg-type]

    def plane_problem(self, plane: Plane, arc: bool) -> str | None:
        """Why the frame cannot be planned in ``plane`` (None: it can): the frame must keep the
        working plane (turn only about its applicate) and, for an arc, scale it uniformly."""
        u, v, w = plane.axes
        m = self.m
        if max(abs(m[w][u]), abs(m[w][v]), abs(m[u][w]), abs(m[v][w])) > _EPS:
            return (
                f"the frame turns the working plane {plane.value} out of itself "
                "(a rotation about another axis than its applicate)"
            )
        if arc:
            a, b, c, d = m[u][u], m[u][v], m[v][u], m[v][v]
            # a similarity: the columns are orthogonal and of equal length
            if abs(a * b + c * d) > 1e-9 or abs(math.hypot(a, c) - math.hypot(b, d)) > 1e-9 * max(
                1.0, math.hypot(a, c)
            ):
                return "the frame scales the working plane differently along its axes: a circle would become an ellipse"
        return None

    def mirrored(self, plane: Plane) -> bool:
        """Whether the frame reverses the sense of rotation in ``plane`` (G2↔G3, G41↔G42)."""
        u, v, _ = plane.axes
        m = self.m
        return m[u][u] * m[v][v] - m[u][v] * m[v][u] < 0.0


IDENTITY = Frame()


def _inverse(m: Mat) -> Mat:
    a, b, c = m
    det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
    if abs(det) < 1e-300:
        raise ArithmeticError("the frame is singular")
    if m == IDENTITY.m:
        return m  # exact: a pure translation maps back without rounding
    return (
        ((b[1] * c[2] - b[2] * c[1]) / det, (a[2] * c[1] - a[1] * c[2]) / det, (a[1] * b[2] - a[2] * b[1]) / det),
        ((b[2] * c[0] - b[0] * c[2]) / det, (a[0] * c[2] - a[2] * c[0]) / det, (a[2] * b[0] - a[0] * b[2]) / det),
        ((b[0] * c[1] - b[1] * c[0]) / det, (a[1] * c[0] - a[0] * c[1]) / det, (a[0] * b[1] - a[1] * b[0]) / det),
    )


def translation(v: Vec) -> Frame:
    return Frame(IDENTITY.m, v)


def _cos_sin(deg: float) -> tuple[float, float]:
    """cos and sin of an angle in degrees, exact at multiples of 90°."""
    q = deg / 90.0
    if q == round(q):
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(round(q)) % 4]
    r = math.radians(deg)
    return math.cos(r), math.sin(r)


def rotation(axis: int, deg: float) -> Frame:
    """Right-handed rotation by ``deg`` degrees about axis 0 (X), 1 (Y) or 2 (Z)."""
    c, s = _cos_sin(deg)
    if axis == 2:
        m = ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))
    elif axis == 1:
        m = ((c, 0.0, s), (0.0, 1.0, 0.0), (-s, 0.0, c))
    else:
        m = ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))
    return Frame(m, (0.0, 0.0, 0.0))


def scaling(factors: Vec) -> Frame:
    x, y, z = factors
    return Frame(((x, 0.0, 0.0), (0.0, y, 0.0), (0.0, 0.0, z)), (0.0, 0.0, 0.0))


def mirroring(axes: tuple[bool, bool, bool]) -> Frame:
    return scaling(tuple(-1.0 if a else 1.0 for a in axes))  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------- zero offsets
@dataclass(frozen=True, slots=True)
class ZeroOffsets:
    """Settable frames by G number: each maps its settable zero system to machine coordinates (mm)."""

    source: str
    offsets: dict[int, Frame]

    def get(self, g: int) -> Frame | None:
        if g == 500 and g not in self.offsets:
            return IDENTITY  # G500: the settable frame is normally empty
        return self.offsets.get(g)


_OFFSET_KEYS = ("X", "Y", "Z", "ROT_Z", "SCALE")


def _number(source: str, key: str, name: str, value: object, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{source}: [{key}].{name} must be a number ({unit})")
    if not (math.isfinite(value) and abs(value) <= MAX_COORDINATE_MM):
        raise ConfigError(f"{source}: [{key}].{name} = {value!r} is not a finite value within ±{MAX_COORDINATE_MM:g}")
    return float(value)


def zero_offsets_from_dict(data: dict[str, object], source: str) -> ZeroOffsets:
    offsets: dict[int, Frame] = {}
    for key, row in data.items():
        g_text = key.upper()
        g = int(g_text[1:]) if g_text.startswith("G") and g_text[1:].isdigit() else -1
        if g not in SETTABLE_G:
            raise ConfigError(f"{source}: {key!r} is not a settable zero offset (G500, G54…G57, G505…G599)")
        if not isinstance(row, dict):
            raise ConfigError(f"{source}: [{key}] must be a table with X, Y, Z (and ROT_Z, SCALE)")
        bad = set(row) - set(_OFFSET_KEYS)
        if bad:
            raise ConfigError(
                f"{source}: [{key}]: unknown key {sorted(bad)[0]!r}; valid: X, Y, Z (translation, mm), "
                "ROT_Z (rotation about Z, degrees), SCALE (factor)"
            )
        t = tuple(_number(source, key, axis, row.get(axis, 0.0), "mm") for axis in "XYZ")
        rot = _number(source, key, "ROT_Z", row.get("ROT_Z", 0.0), "degrees")
        scale = _number(source, key, "SCALE", row.get("SCALE", 1.0), "factor")
        if scale == 0.0:
            raise ConfigError(f"{source}: [{key}].SCALE = 0 makes the plane degenerate")
        frame = translation(t)  # type: ignore[arg-type]
        if rot != 0.0:
            frame = frame.then(rotation(2, rot))
        if scale != 1.0:
            frame = frame.then(scaling((scale, scale, scale)))
        offsets[g] = frame
    return ZeroOffsets(source, offsets)


def load_zero_offsets(path: str | os.PathLike[str]) -> ZeroOffsets:
    """Read a zero-offset file (see the module docstring); problems raise :class:`ConfigError`."""
    return zero_offsets_from_dict(read_toml(Path(path), "zero-offset file"), str(path))


def find_zero_offsets(program: str) -> Path | None:
    """``<stem>.offsets.toml`` beside the program file, else ``offsets.toml`` in its folder."""
    return file_beside(program, ".offsets.toml", "offsets.toml")
