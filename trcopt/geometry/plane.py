"""Working planes G17/G18/G19 and the mapping between workpiece (x, y, z) and plane (u, v, w).

G17: u=X, v=Y, w=Z. G18: u=Z, v=X, w=Y. G19: u=Y, v=Z, w=X. Each basis is right-handed, so a
counter-clockwise sweep in (u, v) seen from +w is G3 in every plane.
"""

from __future__ import annotations

import enum
import functools

from trcopt.geometry.vec import Vec3


class Plane(enum.Enum):
    """Working plane; the value is the G-code name."""

    G17 = "G17"
    G18 = "G18"
    G19 = "G19"

    @functools.cached_property
    def axes(self) -> tuple[int, int, int]:
        """Indices into (x, y, z) of the abscissa, ordinate and applicate."""
        return _AXES[self]

    @property
    def axis_names(self) -> tuple[str, str, str]:
        u, v, w = self.axes
        return ("XYZ"[u], "XYZ"[v], "XYZ"[w])

    def to_uvw(self, xyz: Vec3) -> Vec3:
        u, v, w = self.axes
        return (xyz[u], xyz[v], xyz[w])

    def to_xyz(self, uvw: Vec3) -> Vec3:
        out = [0.0, 0.0, 0.0]
        u, v, w = self.axes
        out[u], out[v], out[w] = uvw
        return (out[0], out[1], out[2])

    @classmethod
    def parse(cls, value: str | Plane) -> Plane:
        if isinstance(value, Plane):
            return value
        try:
            return cls(str(value).upper())
        except ValueError:
            raise ValueError(f"unknown plane {value!r}; valid: G17, G18, G19") from None


_AXES = {Plane.G17: (0, 1, 2), Plane.G18: (2, 0, 1), Plane.G19: (1, 2, 0)}
