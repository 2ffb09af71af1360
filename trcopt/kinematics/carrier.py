"""The ``$TC_CARRn[m]`` data block of a SINUMERIK toolholder with orientation capability.

This module owns the data: the :class:`Carrier` value (one data block ``m``), its construction from
``$TC_CARRn[m]=`` assignments (:func:`carrier_from_assignments`) and back
(:meth:`Carrier.to_assignments`), the static checks of a block (kinematic type, undefined
parameters, ignored vectors, open chains) and the toolholder errors (:func:`holder_error`). TOML
carrier files are :mod:`.carrier_toml`; the mathematics lives in :mod:`.forward`, :mod:`.inverse`
and :mod:`.selection`.

Index table (spec ``toolholder.md`` §2; the increment of the Hirth grid is 28/29, its offset 26/27):

======  ===========================================  =======================================
n       meaning                                      unit / type
======  ===========================================  =======================================
1–3     offset vector l1 (x, y, z)                   mm
4–6     offset vector l2                             mm
7–9     direction of rotary axis 1 (v1)              any length; 0 = axis absent
10–12   direction of rotary axis 2 (v2)              any length; 0 = axis absent
13, 14  angles α1, α2 (used by TCOABS)               deg
15–17   offset vector l3                             mm
18–20   offset vector l4                             mm
21, 22  channel axis supplying α1 / α2               axis name, 0 = none
23      kinematic type ``T`` / ``P`` / ``M``         character (case-insensitive)
24, 25  rotary-axis offsets                          deg
26, 27  Hirth grid offsets                           deg
28, 29  Hirth grid increments (grid active if > 0)   deg
30, 31  minimum position of axis 1 / axis 2          deg
32, 33  maximum position of axis 1 / axis 2          deg
34      holder name                                  string
35, 36  user axis names                              string (not used by the kinematics)
37      identifier (user / CYCLE800 coding)          int (not used by the kinematics)
38–40   user position x, y, z                        mm (not used by the kinematics)
41–46   fine offsets of l1, l2 (index k + 40)        mm
55–60   fine offsets of l3, l4 (index k + 40)        mm
64, 65  fine offsets of the rotary-axis offsets      deg
======  ===========================================  =======================================

Indices 47–54 and 61–63 are undefined; using them is an error, as on the control.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan, alarm
from trcopt.geometry.vec import Vec3

__all__ = [
    "KinematicType",
    "Carrier",
    "carrier_from_assignments",
    "holder_error",
    "ALARM_KINEMATIC_TYPE",
    "UNDEFINED_INDICES",
    "LAST_INDEX",
]


#: SINUMERIK alarm for an invalid ``$TC_CARR23`` (kinematic type).
ALARM_KINEMATIC_TYPE = 14153
#: Indices of ``$TC_CARRn`` that do not exist (reading or writing them is an error).
UNDEFINED_INDICES = frozenset(range(47, 55)) | frozenset(range(61, 64))
#: The last index of ``$TC_CARRn``.
LAST_INDEX = 65
_CLOSURE_TOL_MM = 1e-6


class KinematicType(enum.Enum):
    """``$TC_CARR23``: which part rotates.

    ``T`` only the tool (head), ``P`` only the part (table), ``M`` mixed: axis 1 turns the tool,
    axis 2 the table.
    """

    T = "T"
    P = "P"
    M = "M"

    @classmethod
    def parse(cls, value: object) -> KinematicType:
        """Accept an enum member or a one-character string (case-insensitive).

        Raises
        ------
        ValueError
            For anything else; the message lists the valid options.
        """
        if isinstance(value, KinematicType):
            return value
        if isinstance(value, str) and value.strip().upper() in ("T", "P", "M"):
            return cls(value.strip().upper())
        raise ValueError(f"invalid kinematic type {value!r}; valid: 'T', 'P', 'M'")


# index -> (field name, component) ; component None = scalar field
_VECTOR_FIELDS: dict[str, tuple[int, int, int]] = {
    "l1": (1, 2, 3),
    "l2": (4, 5, 6),
    "v1": (7, 8, 9),
    "v2": (10, 11, 12),
    "l3": (15, 16, 17),
    "l4": (18, 19, 20),
    "position": (38, 39, 40),
    "fine_l1": (41, 42, 43),
    "fine_l2": (44, 45, 46),
    "fine_l3": (55, 56, 57),
    "fine_l4": (58, 59, 60),
}
_REAL_SCALARS: dict[int, str] = {
    13: "angle1",
    14: "angle2",
    24: "axis_offset1",
    25: "axis_offset2",
    26: "hirth_offset1",
    27: "hirth_offset2",
    28: "hirth_increment1",
    29: "hirth_increment2",
    30: "min1",
    31: "min2",
    32: "max1",
    33: "max2",
    64: "fine_axis_offset1",
    65: "fine_axis_offset2",
}
_AXIS_REFS: dict[int, str] = {21: "axis_ref1", 22: "axis_ref2"}
_STRINGS: dict[int, str] = {34: "name", 35: "axis_name1", 36: "axis_name2"}
_INDEX_TO_VECTOR: dict[int, tuple[str, int]] = {
    n: (name, i) for name, idx in _VECTOR_FIELDS.items() for i, n in enumerate(idx)
}

_ZERO: Vec3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True, slots=True)
class Carrier:
    """One toolholder data block ``$TC_CARRn[number]`` (spec §2).

    All lengths in mm, all angles in degrees; vectors are ``(x, y, z)`` tuples in machine (basic)
    coordinates. Defaults are the control's defaults (all zero, type ``T``).

    Parameters
    ----------
    number:
        Data block number m (1 … MD18088).
    l1, l2, l3, l4:
        Offset vectors (``$TC_CARR1–6, 15–20``) [mm].
    v1, v2:
        Rotary-axis directions (``$TC_CARR7–12``); length irrelevant, zero = axis absent.
    angle1, angle2:
        ``$TC_CARR13/14`` [deg]: angles used by TCOABS and as specified angles for TCOFR.
    axis_ref1, axis_ref2:
        ``$TC_CARR21/22``: name of the channel axis whose position supplies the angle (``None`` =
        no reference, the stored angle is used).
    kinematic_type:
        ``$TC_CARR23``.
    axis_offset1, axis_offset2:
        ``$TC_CARR24/25`` [deg]: axis position in which the vectors were measured.
    hirth_offset1, hirth_offset2, hirth_increment1, hirth_increment2:
        ``$TC_CARR26–29`` [deg]: grid ``offset + k·increment``, active when the increment is > 0.
    min1, min2, max1, max2:
        ``$TC_CARR30–33`` [deg]: software limits; an axis whose min and max are both 0 is not
        checked.
    fine_offsets_enabled:
        Whether the fine offsets (41–46, 55–60, 64/65) are added (a setting datum on the control;
        default on).
    """

    number: int = 1
    l1: Vec3 = _ZERO
    l2: Vec3 = _ZERO
    v1: Vec3 = _ZERO
    v2: Vec3 = _ZERO
    angle1: float = 0.0
    angle2: float = 0.0
    l3: Vec3 = _ZERO
    l4: Vec3 = _ZERO
    axis_ref1: str | None = None
    axis_ref2: str | None = None
    kinematic_type: KinematicType = KinematicType.T
    axis_offset1: float = 0.0
    axis_offset2: float = 0.0
    hirth_offset1: float = 0.0
    hirth_offset2: float = 0.0
    hirth_increment1: float = 0.0
    hirth_increment2: float = 0.0
    min1: float = 0.0
    min2: float = 0.0
    max1: float = 0.0
    max2: float = 0.0
    name: str = ""
    axis_name1: str = ""
    axis_name2: str = ""
    identifier: int = 0
    position: Vec3 = _ZERO
    fine_l1: Vec3 = _ZERO
    fine_l2: Vec3 = _ZERO
    fine_l3: Vec3 = _ZERO
    fine_l4: Vec3 = _ZERO
    fine_axis_offset1: float = 0.0
    fine_axis_offset2: float = 0.0
    fine_offsets_enabled: bool = True
    span: SourceSpan | None = field(default=None, compare=False)

    # -- effective values (spec R1) -------------------------------------------------------------
    def _eff(self, base: Vec3, fine: Vec3) -> np.ndarray:
        v = np.asarray(base, dtype=float)
        return v + np.asarray(fine, dtype=float) if self.fine_offsets_enabled else v

    @property
    def offsets(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Effective ``l1 … l4`` [mm] (fine offsets added when enabled)."""
        return (
            self._eff(self.l1, self.fine_l1),
            self._eff(self.l2, self.fine_l2),
            self._eff(self.l3, self.fine_l3),
            self._eff(self.l4, self.fine_l4),
        )

    @property
    def axis_offsets(self) -> tuple[float, float]:
        """Effective rotary-axis offsets ``$TC_CARR24/25`` (+ 64/65 when enabled) [deg]."""
        if self.fine_offsets_enabled:
            return (
                self.axis_offset1 + self.fine_axis_offset1,
                self.axis_offset2 + self.fine_axis_offset2,
            )
        return (self.axis_offset1, self.axis_offset2)

    @property
    def has_axis(self) -> tuple[bool, bool]:
        """Whether rotary axis 1 / 2 exists (non-zero direction vector)."""
        return (any(c != 0.0 for c in self.v1), any(c != 0.0 for c in self.v2))

    def limits(self, axis: int) -> tuple[float, float] | None:
        """Software limits ``(min, max)`` [deg] of axis 1 or 2, ``None`` when both are zero."""
        lo, hi = (self.min1, self.max1) if axis == 1 else (self.min2, self.max2)
        return None if lo == 0.0 and hi == 0.0 else (lo, hi)

    def hirth(self, axis: int) -> tuple[float, float] | None:
        """Hirth grid ``(offset, increment)`` [deg] of axis 1 or 2, ``None`` when inactive."""
        off, inc = (
            (self.hirth_offset1, self.hirth_increment1)
            if axis == 1
            else (self.hirth_offset2, self.hirth_increment2)
        )
        return (off, inc) if inc > 0.0 else None

    def to_assignments(self) -> dict[int, float | str]:
        """The block as ``{n: value}`` (non-default entries only), inverse of
        :func:`carrier_from_assignments`."""
        out: dict[int, float | str] = {}
        for name, idx in _VECTOR_FIELDS.items():
            for n, c in zip(idx, getattr(self, name), strict=True):
                if c != 0.0:
                    out[n] = float(c)
        for n, name in _REAL_SCALARS.items():
            if getattr(self, name) != 0.0:
                out[n] = float(getattr(self, name))
        for n, name in _AXIS_REFS.items():
            if getattr(self, name):
                out[n] = getattr(self, name)
        for n, name in _STRINGS.items():
            if getattr(self, name):
                out[n] = getattr(self, name)
        if self.identifier:
            out[37] = float(self.identifier)
        out[23] = self.kinematic_type.value
        return out

    def warnings(self) -> list[Diagnostic]:
        """Static warnings: ignored vectors (l4 for T, l1 for P) and open chains (spec R4, R5)."""
        span = self.span or SourceSpan()
        out: list[Diagnostic] = []
        l1, l2, l3, l4 = self.offsets
        kt = self.kinematic_type
        m = self.number
        if kt is KinematicType.T and np.any(l4 != 0.0):
            out.append(_warn(Code.TH_IGNORED_L4, f"toolholder {m}: l4 is ignored for type T", span))
        if kt is KinematicType.P and np.any(l1 != 0.0):
            out.append(_warn(Code.TH_IGNORED_L1, f"toolholder {m}: l1 is ignored for type P", span))
        sums = {
            KinematicType.T: [("l1+l2+l3", l1 + l2 + l3)],
            KinematicType.P: [("l2+l3+l4", l2 + l3 + l4)],
            KinematicType.M: [("l1+l2", l1 + l2), ("l3+l4", l3 + l4)],
        }[kt]
        for label, s in sums:
            if float(np.linalg.norm(s)) > _CLOSURE_TOL_MM:
                out.append(
                    _warn(
                        Code.TH_CHAIN_OPEN,
                        f"toolholder {m}: chain not closed ({label} = "
                        f"({s[0]:g}, {s[1]:g}, {s[2]:g}) mm); the sum acts as a constant offset",
                        span,
                    )
                )
        return out


def _warn(code: Code, message: str, span: SourceSpan) -> Diagnostic:
    return Diagnostic(Severity.WARNING, code, message, span)


def holder_error(code: Code, message: str, span: SourceSpan | None) -> AlarmError:
    """A toolholder error (project code ``TH-*``) at ``span`` (an empty span when there is none)."""
    return AlarmError(Diagnostic(Severity.ERROR, code, message, span or SourceSpan()))


def _real(value: object, n: int, number: int, span: SourceSpan | None) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise holder_error(
            Code.TH_VALUE,
            f"$TC_CARR{n}[{number}] must be a number, got {value!r}",
            span,
        )
    x = float(value)
    if not math.isfinite(x):
        raise holder_error(Code.TH_VALUE, f"$TC_CARR{n}[{number}] must be finite, got {value!r}", span)
    return x


def _axis_ref(value: object) -> str | None:
    if value is None or isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        return None if value == 0 else str(int(value)) if float(value).is_integer() else str(value)
    text = str(value).strip().strip("\"'")
    return None if text in ("", "0") else text


def carrier_from_assignments(
    values: Mapping[int, object],
    number: int,
    span: SourceSpan | None = None,
    *,
    fine_offsets_enabled: bool = True,
) -> Carrier:
    """Build data block ``number`` from ``$TC_CARRn[number] = value`` assignments.

    Parameters
    ----------
    values:
        ``{n: value}`` for the system-variable index n (1 … 65). Numbers for the REAL entries
        (mm or deg as in the module table), a string for the kinematic type (23) and the names
        (34–36); the axis references (21/22) take an axis name or 0. Missing indices keep their
        defaults (0, type ``T``).
    number:
        The data block number m of ``$TC_CARRn[m]``.
    span:
        Where the block is used or defined; carried into every diagnostic.
    fine_offsets_enabled:
        Add the fine offsets (spec R1, default on).

    Returns
    -------
    Carrier

    Raises
    ------
    AlarmError
        Alarm 14153 for a kinematic type other than T/P/M (the message names the data block);
        ``TH-UNDEFINED-PARAM`` for indices 47–54, 61–63 or outside 1 … 65; ``TH-VALUE`` for a value
        of the wrong type.
    """
    kwargs: dict[str, Any] = {}  # Carrier field name -> its value (of that field's type)
    vectors: dict[str, list[float]] = {}
    kin = KinematicType.T
    for raw_n, value in values.items():
        n = int(raw_n)
        if n < 1 or n > LAST_INDEX or n in UNDEFINED_INDICES:
            raise holder_error(
                Code.TH_UNDEFINED_PARAM,
                f"$TC_CARR{n}[{number}] is not a defined toolholder parameter "
                "(defined: 1-46, 55-60, 64, 65)",
                span,
            )
        if n in _INDEX_TO_VECTOR:
            name, comp = _INDEX_TO_VECTOR[n]
            vec = vectors.setdefault(name, [0.0, 0.0, 0.0])
            vec[comp] = _real(value, n, number, span)
        elif n in _REAL_SCALARS:
            kwargs[_REAL_SCALARS[n]] = _real(value, n, number, span)
        elif n in _AXIS_REFS:
            kwargs[_AXIS_REFS[n]] = _axis_ref(value)
        elif n in _STRINGS:
            kwargs[_STRINGS[n]] = str(value)
        elif n == 37:
            kwargs["identifier"] = int(_real(value, n, number, span))
        elif n == 23:
            try:
                kin = KinematicType.parse(value)
            except ValueError:
                diag = alarm(
                    ALARM_KINEMATIC_TYPE,
                    f"toolholder {number}: invalid kinematic type {value!r} in "
                    f"$TC_CARR23[{number}] (valid: T, P, M)",
                    span or SourceSpan(),
                )
                raise AlarmError(diag) from None
    for name, vec in vectors.items():
        kwargs[name] = (vec[0], vec[1], vec[2])
    return Carrier(
        number=number,
        kinematic_type=kin,
        fine_offsets_enabled=fine_offsets_enabled,
        span=span,
        **kwargs,
    )
