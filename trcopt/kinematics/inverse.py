"""Closed-form inverse of an orientable toolholder (spec §6).

:func:`inverse_solutions` finds every pair of axis positions (α1, α2) [deg] that turns a base
direction ``e`` into a requested direction ``d`` (two cones sharing a ray): none, one (boundary),
two, one with a *free* angle, or infinitely many (parallel axes). Free angles (the rotary axis is
parallel to the vector it should turn, or parallel axes where only the sum of the angles is fixed)
take the specified angle, so the axis does not move. Which pair a holder activation uses is
:mod:`trcopt.kinematics.selection`; the orientation words of a program are
:mod:`trcopt.kinematics.orientation`.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.kinematics.carrier import Carrier, KinematicType
from trcopt.kinematics.forward import relative_direction, rotation

__all__ = [
    "SolutionKind",
    "AnglePair",
    "InverseResult",
    "inverse_solutions",
    "unit_vector",
    "CONE_EPS",
    "DOUBLE_EPS",
    "FREE_EPS",
]

#: Tolerance of the cone equations (spec REQ-TH-08): how far a requested direction may miss the
#: reachable set and still count as the boundary (one double solution).
CONE_EPS = 1e-9
#: Below this ``γ²·|a×b|²`` the two solutions coincide to rounding and are reported as one.
DOUBLE_EPS = 1e-15
#: Below this length the component of a vector normal to a rotary axis is zero: the angle is free.
FREE_EPS = 1e-9
_PARALLEL_EPS = 1e-12
_CONDITION_EPS = 1e-9


class SolutionKind(enum.Enum):
    """What the geometry admits for a requested orientation."""

    NONE = "none"  #: orientation not reachable
    ONE = "one"  #: boundary orientation, one (double) pair
    TWO = "two"  #: the general case
    FREE = "free"  #: one pair in which at least one angle is free (any value works)
    INFINITE = "infinite"  #: parallel axes: only a combination of the angles is fixed


@dataclass(frozen=True, slots=True)
class AnglePair:
    """Axis positions (α1, α2) [deg]; ``free1``/``free2`` mark angles the geometry leaves free
    (they were set to the specified angle)."""

    angle1: float
    angle2: float
    free1: bool = False
    free2: bool = False

    @property
    def angles(self) -> tuple[float, float]:
        return (self.angle1, self.angle2)

    def with_angles(self, a1: float, a2: float) -> AnglePair:
        return AnglePair(a1, a2, self.free1, self.free2)


@dataclass(frozen=True, slots=True)
class InverseResult:
    """Exact solutions of ``d_rel(α1, α2) = d`` (spec §6), angles in (−180°, 180°] + offset.

    Attributes
    ----------
    kind:
        :class:`SolutionKind`.
    pairs:
        0, 1 or 2 pairs (free angles already at the specified angle).
    gamma2:
        γ² of the cone intersection (NaN when not applicable: parallel or absent axes).
    base, direction:
        e and d (unit vectors).
    residuals:
        ``|d_rel(pair) − d|`` of every pair (forward verification, spec REQ-TH-08).
    note:
        Human-readable explanation of the case.
    """

    kind: SolutionKind
    pairs: tuple[AnglePair, ...]
    gamma2: float
    base: tuple[float, float, float]
    direction: tuple[float, float, float]
    residuals: tuple[float, ...]
    note: str

    @property
    def count(self) -> int:
        """``$P_TCANG[0]``: geometric solutions before limits (free/infinite count as 1)."""
        return len(self.pairs)


def unit_vector(v: Sequence[float] | np.ndarray, what: str) -> np.ndarray:
    """``v`` normalised; ``what`` names it in the error for a zero or non-finite vector."""
    a = np.asarray(v, dtype=float).reshape(3)
    n = float(np.linalg.norm(a))
    if not math.isfinite(n) or n < 1e-12:
        raise ValueError(f"{what} must be a finite non-zero 3-vector, got {list(a)}")
    return a / n


def _signed_angle(a: np.ndarray, u: np.ndarray, x: np.ndarray) -> float | None:
    """Angle [deg] in (−180, 180] turning ``u`` into ``x`` about unit ``a``; ``None`` if free."""
    up = u - (a @ u) * a
    xp = x - (a @ x) * a
    if float(np.linalg.norm(up)) < FREE_EPS:
        return None
    t = math.degrees(math.atan2(float(a @ np.cross(up, xp)), float(up @ xp)))
    return 180.0 if t <= -180.0 else t


def _cone_intersection(
    a: np.ndarray, ca: float, b: np.ndarray, cb: float
) -> tuple[list[np.ndarray], float]:
    """Unit vectors x with ``a·x = ca`` and ``b·x = cb`` for non-parallel unit a, b (§6.2).

    The tolerances act on ``h = γ²·|a×b|² = 1 − |αa + βb|²``: ``h < −CONE_EPS`` → no solution
    (the cones miss by more than the cone-equation tolerance); ``h ≤ DOUBLE_EPS`` → one double
    solution (the normalised base point, which satisfies both cone equations to rounding); else
    two. A tiny positive threshold keeps nearly coincident but distinct solutions apart: collapsing
    them would violate the cone equations of narrow cones.
    """
    k = float(a @ b)
    s2 = 1.0 - k * k
    al = (ca - cb * k) / s2
    be = (cb - ca * k) / s2
    n = np.cross(a, b)
    nn = float(n @ n)
    base = al * a + be * b
    h = 1.0 - float(base @ base)
    g2 = h / nn
    if h < -CONE_EPS:
        return [], g2
    if h <= DOUBLE_EPS:
        return [base / np.linalg.norm(base)], g2
    g = math.sqrt(g2)
    return [base + g * n, base - g * n], g2


def inverse_solutions(
    carrier: Carrier,
    direction: Sequence[float] | np.ndarray,
    base: Sequence[float] | np.ndarray = (0.0, 0.0, 1.0),
    reference: tuple[float, float] = (0.0, 0.0),
) -> InverseResult:
    """All exact axis positions that turn ``base`` into ``direction`` (spec §6, closed form).

    Parameters
    ----------
    carrier:
        The holder.
    direction:
        Requested direction d relative to the workpiece (normalised here).
    base:
        Tool direction e at zero angles for the TCOFR variant (z for TCOFR/TCOFRZ).
    reference:
        Specified angles [deg]; free angles take these values.

    Returns
    -------
    InverseResult
        ``kind`` is :attr:`SolutionKind.NONE` when the orientation is not reachable (no
        exception here; :func:`~.orientation.solve_orientation` raises).
    """
    d = unit_vector(direction, "direction")
    e = unit_vector(base, "base direction")
    has1, has2 = carrier.has_axis
    off = carrier.axis_offsets
    kt = carrier.kinematic_type
    # canonical form x = R(a, θa)·u = R(b, θb)·w  (spec §6.1); (axis index, sign) per side
    if kt is KinematicType.T:
        u, w, ia, sa, ib, sb = e, d, 2, 1.0, 1, -1.0
    elif kt is KinematicType.P:
        u, w, ia, sa, ib, sb = d, e, 2, 1.0, 1, -1.0
    else:
        u, w, ia, sa, ib, sb = e, d, 1, 1.0, 2, 1.0
    vecs = {1: carrier.v1, 2: carrier.v2}
    has = {1: has1, 2: has2}

    def theta_ref(i: int) -> float:
        return reference[i - 1] - off[i - 1]

    def to_pair(ta: float | None, tb: float | None) -> AnglePair:
        th: dict[int, float | None] = {ia: None if ta is None else sa * ta}
        th[ib] = None if tb is None else sb * tb
        ang = {}
        for i in (1, 2):
            t = th[i]
            if t is not None and t <= -180.0:
                t += 360.0  # keep θ in (−180°, 180°] after the sign of §6.1
            ang[i] = float(reference[i - 1]) if t is None else t + off[i - 1]
        return AnglePair(ang[1], ang[2], th[1] is None, th[2] is None)

    pairs: list[AnglePair] = []
    gamma2 = float("nan")
    kind = SolutionKind.NONE
    note = ""
    a = unit_vector(vecs[ia], "axis") if has[ia] else None
    b = unit_vector(vecs[ib], "axis") if has[ib] else None
    if a is None and b is None:
        if float(np.linalg.norm(d - e)) <= _CONDITION_EPS:
            pairs, kind, note = [to_pair(None, None)], SolutionKind.FREE, "no rotary axis; d = e"
        else:
            note = "no rotary axis: the orientation is fixed"
    elif b is None or a is None:
        # one axis: x = w (b absent) or x = u (a absent); the cone condition must hold exactly
        ax, src, dst = (a, u, w) if b is None else (b, w, u)
        assert ax is not None
        if abs(float(ax @ src) - float(ax @ dst)) > _CONDITION_EPS:
            note = (
                "one rotary axis: the requested direction is not on the cone of reachable "
                f"directions (axis·e = {float(ax @ src):.6f}, axis·d = {float(ax @ dst):.6f})"
            )
        else:
            t = _signed_angle(ax, src, dst)
            pair = to_pair(t, None) if b is None else to_pair(None, t)
            pairs = [pair]
            kind = SolutionKind.ONE if t is not None else SolutionKind.FREE
            note = "one rotary axis" + ("" if t is not None else "; its angle is free")
    else:
        ca, cb = float(a @ u), float(b @ w)
        k = float(a @ b)
        if 1.0 - k * k <= _PARALLEL_EPS:
            if abs(ca - (cb if k > 0 else -cb)) <= _CONDITION_EPS:
                tb = sb * theta_ref(ib)
                x = rotation(b, tb) @ w
                ta = _signed_angle(a, u, x)
                # θb kept at the specified angle, so axis ib is reported free
                pair = to_pair(ta, None)
                pairs, kind = [pair], SolutionKind.INFINITE
                note = (
                    f"parallel rotary axes: infinitely many pairs; axis {ib} kept at "
                    f"{reference[ib - 1]:g} deg"
                )
            else:
                note = "parallel rotary axes: the requested direction is not reachable"
        else:
            xs, gamma2 = _cone_intersection(a, ca, b, cb)
            for x in xs:
                pairs.append(to_pair(_signed_angle(a, u, x), _signed_angle(b, w, x)))
            if not xs:
                note = f"the cones of the two axes do not meet (gamma^2 = {gamma2:.3e} < 0)"
            elif any(p.free1 or p.free2 for p in pairs):
                kind = SolutionKind.FREE
                note = "a rotary axis is parallel to the direction it turns"
            elif len(xs) == 1:
                kind, note = SolutionKind.ONE, "boundary orientation: one double solution"
            else:
                kind, note = SolutionKind.TWO, "two solutions"
            if len(pairs) == 2 and kind is SolutionKind.FREE:
                pairs = pairs[:1]
    residuals = tuple(
        float(np.linalg.norm(relative_direction(carrier, p.angle1, p.angle2, e) - d)) for p in pairs
    )
    return InverseResult(
        kind,
        tuple(pairs),
        gamma2,
        (float(e[0]), float(e[1]), float(e[2])),
        (float(d[0]), float(d[1]), float(d[2])),
        residuals,
        note,
    )
