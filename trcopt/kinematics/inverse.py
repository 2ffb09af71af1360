"""Inverse problem and solution selection of an orientable toolholder (spec §5–§7).

:func:`inverse_solutions` finds, in closed form, every pair of axis positions (α1, α2) [deg] that
turns a base direction ``e`` into a requested direction ``d`` (two cones sharing a ray, spec §6):
none, one (boundary), two, one with a *free* angle, or infinitely many (parallel axes).
:func:`select_solution` then applies, in this order (spec R9), the 360° shift toward the specified
angles, the Hirth grid, the ordering (first = smaller L1 distance to the specified angles), and the
software limits with ±k·360° retries and fall-back to the second pair (``$P_TCANG`` swapped).
:func:`solve_orientation` (TCOFR/TCOFRZ/Y/X) and :func:`tcoabs_angles` (TCOABS) are the two
entry points a program uses.

Free angles (the rotary axis is parallel to the vector it should turn, or parallel axes where only
the sum of the angles is fixed) take the specified angle, so the axis does not move.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan
from trcopt.kinematics.carrier import Carrier, KinematicType
from trcopt.kinematics.forward import relative_direction, rotation, rpy_matrix

__all__ = [
    "SolutionKind",
    "OrientationWord",
    "AnglePair",
    "InverseResult",
    "Selection",
    "inverse_solutions",
    "select_solution",
    "solve_orientation",
    "tcoabs_angles",
    "reference_angles",
    "shift_toward",
    "hirth_round",
    "fit_limits",
    "frame_matrix",
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
_LIMIT_TOL = 1e-9


class SolutionKind(enum.Enum):
    """What the geometry admits for a requested orientation."""

    NONE = "none"  #: orientation not reachable
    ONE = "one"  #: boundary orientation, one (double) pair
    TWO = "two"  #: the general case
    FREE = "free"  #: one pair in which at least one angle is free (any value works)
    INFINITE = "infinite"  #: parallel axes: only a combination of the angles is fixed


class OrientationWord(enum.Enum):
    """Modal G group 42: where the holder angles come from."""

    TCOABS = "TCOABS"
    TCOFR = "TCOFR"
    TCOFRZ = "TCOFRZ"
    TCOFRY = "TCOFRY"
    TCOFRX = "TCOFRX"

    @classmethod
    def parse(cls, value: object) -> OrientationWord:
        if isinstance(value, OrientationWord):
            return value
        try:
            return cls(str(value).upper())
        except ValueError:
            valid = ", ".join(m.value for m in cls)
            raise ValueError(f"unknown orientation word {value!r}; valid: {valid}") from None

    @property
    def base_axis(self) -> int:
        """Index (x=0, y=1, z=2) of the tool axis that TCOFRx aligns with the same frame axis
        (spec R6); TCOFR = TCOFRZ."""
        return {"TCOFRX": 0, "TCOFRY": 1}.get(self.value, 2)


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


@dataclass(frozen=True, slots=True)
class Selection:
    """The angles a holder activation uses, with the ``$P_TCANG`` bookkeeping of spec §7.

    Attributes
    ----------
    word:
        TCOABS or the TCOFR variant that produced the angles.
    reference:
        Specified angles (ref1, ref2) [deg].
    inverse:
        The exact solutions (``None`` for TCOABS, where nothing is solved).
    ordered:
        Pairs after 360° shift and Hirth rounding, first = closest to the reference.
    chosen:
        Pair actually used, after the limit check [deg].
    p_tcang:
        ``$P_TCANG[1..4]``: used pair, then the other pair (NaN when none) [deg].
    tcang0:
        ``$P_TCANG[0]``: number of geometric solutions.
    tcsol:
        Number of pairs that passed the limit check.
    tcdiff:
        Hirth rounding differences (rounded − exact) in ``$P_TCANG`` slot order [deg].
    swapped:
        The first pair failed the limits and the second is used (``$P_TCANG`` swapped).
    orientation_error_deg:
        Angle between requested and achieved direction (non-zero only with Hirth) [deg].
    reasons:
        Why this pair was chosen, step by step.
    """

    word: OrientationWord
    reference: tuple[float, float]
    inverse: InverseResult | None
    ordered: tuple[AnglePair, ...]
    chosen: tuple[float, float]
    p_tcang: tuple[float, float, float, float]
    tcang0: int
    tcsol: int
    tcdiff: tuple[float, float, float, float]
    swapped: bool
    orientation_error_deg: float
    reasons: tuple[str, ...]

    def to_json(self) -> dict[str, object]:
        """JSON-able summary (degrees; NaN written as ``null``)."""
        return {
            "word": self.word.value,
            "reference": list(self.reference),
            "solutions": [list(p.angles) for p in self.ordered],
            "chosen": list(self.chosen),
            "p_tcang": [_json_float(x) for x in self.p_tcang],
            "p_tcang0": self.tcang0,
            "p_tcsol": self.tcsol,
            "p_tcdiff": [_json_float(x) for x in self.tcdiff],
            "swapped": self.swapped,
            "orientation_error_deg": self.orientation_error_deg,
            "reasons": list(self.reasons),
        }


def _json_float(x: float) -> float | None:
    return None if math.isnan(x) else float(x)


# --------------------------------------------------------------------------------------------
# closed-form geometry
# --------------------------------------------------------------------------------------------


def _unit(v: Sequence[float] | np.ndarray, what: str) -> np.ndarray:
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
        exception here; :func:`solve_orientation` raises).
    """
    d = _unit(direction, "direction")
    e = _unit(base, "base direction")
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
    a = _unit(vecs[ia], "axis") if has[ia] else None
    b = _unit(vecs[ib], "axis") if has[ib] else None
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


# --------------------------------------------------------------------------------------------
# shift, Hirth, order, limits (spec §7)
# --------------------------------------------------------------------------------------------


def shift_toward(angle: float, reference: float) -> float:
    """Add the multiple of 360° that brings ``angle`` nearest to ``reference`` [deg]
    (10 with 750 specified → 730)."""
    return angle + 360.0 * math.floor((reference - angle) / 360.0 + 0.5)


def hirth_round(angle: float, offset: float, increment: float, reference: float) -> float:
    """Nearest grid value ``offset + k·increment`` [deg]; an exact tie goes to the grid value
    nearer to ``reference`` (spec R10). ``increment <= 0`` leaves the angle unchanged."""
    if increment <= 0.0:
        return angle
    k = math.floor((angle - offset) / increment)
    lo = offset + k * increment
    hi = lo + increment
    dlo, dhi = angle - lo, hi - angle
    if abs(dlo - dhi) <= 1e-9:
        return lo if abs(lo - reference) <= abs(hi - reference) else hi
    return lo if dlo < dhi else hi


def fit_limits(angle: float, limits: tuple[float, float] | None, reference: float) -> float | None:
    """The axis position inside ``limits`` [deg]: ``angle`` itself if inside, else the
    ``angle ± k·360`` inside the range nearest to ``reference`` (spec R12); ``None`` if none fits.
    ``limits=None`` (both zero) means no check."""
    if limits is None:
        return angle
    lo, hi = limits
    if lo - _LIMIT_TOL <= angle <= hi + _LIMIT_TOL:
        return angle
    kmin = math.ceil((lo - angle) / 360.0 - 1e-12)
    kmax = math.floor((hi - angle) / 360.0 + 1e-12)
    cands = [angle + 360.0 * k for k in range(kmin, kmax + 1)]
    cands = [c for c in cands if lo - _LIMIT_TOL <= c <= hi + _LIMIT_TOL]
    if not cands:
        return None
    return min(cands, key=lambda c: (abs(c - reference), c))


def reference_angles(
    carrier: Carrier, axis_positions: Mapping[str, float] | None = None
) -> tuple[float, float]:
    """Specified angles [deg]: the position of the axis named in ``$TC_CARR21/22`` when it is
    known (``axis_positions``, at the start of the activating block), else ``$TC_CARR13/14``.
    Mixing per axis is allowed."""
    pos = {k.upper(): float(v) for k, v in (axis_positions or {}).items()}
    out = []
    for ref, stored in ((carrier.axis_ref1, carrier.angle1), (carrier.axis_ref2, carrier.angle2)):
        out.append(pos[ref.upper()] if ref and ref.upper() in pos else stored)
    return (out[0], out[1])


def _fmt(x: float) -> str:
    return "nan" if math.isnan(x) else f"{x:.6g}"


def _pair_text(p: tuple[float, float] | AnglePair) -> str:
    a1, a2 = p.angles if isinstance(p, AnglePair) else p
    return f"({_fmt(a1)}, {_fmt(a2)})"


def _error(code: str, message: str, span: SourceSpan | None) -> AlarmError:
    return AlarmError(Diagnostic(Severity.ERROR, code, message, span or SourceSpan()))


def select_solution(
    carrier: Carrier,
    inverse: InverseResult,
    reference: tuple[float, float],
    *,
    word: OrientationWord = OrientationWord.TCOFR,
    span: SourceSpan | None = None,
) -> Selection:
    """Shift, round, order and limit the exact pairs (spec §7, order R9).

    Raises
    ------
    AlarmError
        ``TH-UNREACHABLE`` when ``inverse`` has no pair; ``TH-NO-VALID-SOLUTION`` when no pair
        fits the software limits (messages name the data block).
    """
    m = carrier.number
    if not inverse.pairs:
        raise _error(
            "TH-UNREACHABLE",
            f"toolholder {m}: orientation not reachable: {inverse.note}",
            span,
        )
    reasons: list[str] = []
    shifted: list[AnglePair] = []
    for p in inverse.pairs:
        a = [p.angle1, p.angle2]
        for i in range(2):
            if not (p.free1, p.free2)[i]:
                s = shift_toward(a[i], reference[i])
                if abs(s - a[i]) > 1e-9:
                    reasons.append(
                        f"axis {i + 1}: {_fmt(a[i])} shifted by {_fmt(s - a[i])} toward the "
                        f"specified {_fmt(reference[i])} -> {_fmt(s)}"
                    )
                a[i] = s
        shifted.append(p.with_angles(a[0], a[1]))
    for p in inverse.pairs:
        for i, free in enumerate((p.free1, p.free2)):
            if free:
                reasons.append(f"axis {i + 1} is free; kept at the specified {_fmt(reference[i])}")
                break
    rounded: list[tuple[AnglePair, tuple[float, float]]] = []
    for p in shifted:
        a = [p.angle1, p.angle2]
        diff = [0.0, 0.0]
        for i in range(2):
            grid = carrier.hirth(i + 1)
            if grid is not None:
                r = hirth_round(a[i], grid[0], grid[1], reference[i])
                diff[i] = r - a[i]
                if abs(diff[i]) > 0:
                    reasons.append(
                        f"axis {i + 1}: Hirth grid {_fmt(grid[0])} + k*{_fmt(grid[1])} rounds "
                        f"{_fmt(a[i])} to {_fmt(r)} (diff {diff[i]:+.4f})"
                    )
                a[i] = r
        rounded.append((p.with_angles(a[0], a[1]), (diff[0], diff[1])))

    def key(item: tuple[AnglePair, tuple[float, float]]) -> tuple[float, float, float, float]:
        p = item[0]
        d1, d2 = abs(p.angle1 - reference[0]), abs(p.angle2 - reference[1])
        return (round(d1 + d2, 9), round(d1, 9), p.angle1, p.angle2)

    rounded.sort(key=key)
    ordered = [p for p, _ in rounded]
    diffs = [d for _, d in rounded]
    if len(ordered) == 2:
        dist = [key(it)[0] for it in rounded]
        reasons.append(
            f"first solution {_pair_text(ordered[0])} is closest to the specified angles "
            f"{_pair_text(reference)} (distance {dist[0]:.6g} deg vs {dist[1]:.6g} deg)"
        )
    lims = (carrier.limits(1), carrier.limits(2))
    fitted: list[tuple[float, float] | None] = []
    for p in ordered:
        f1 = fit_limits(p.angle1, lims[0], reference[0])
        f2 = fit_limits(p.angle2, lims[1], reference[1])
        fitted.append(None if f1 is None or f2 is None else (f1, f2))
        if f1 is None or f2 is None:
            bad = 1 if f1 is None else 2
            lo, hi = lims[bad - 1] or (0.0, 0.0)
            reasons.append(
                f"pair {_pair_text(p)}: axis {bad} outside its limits [{_fmt(lo)}, {_fmt(hi)}] "
                "also after +-k*360 deg"
            )
        elif (f1, f2) != p.angles:
            reasons.append(
                f"pair {_pair_text(p)} brought inside the limits as {_pair_text((f1, f2))}"
            )
    tcsol = sum(f is not None for f in fitted)
    if tcsol == 0:
        raise _error(
            "TH-NO-VALID-SOLUTION",
            f"toolholder {m}: no solution within the software limits $TC_CARR30-33 "
            f"(solutions {', '.join(_pair_text(p) for p in ordered)})",
            span,
        )
    use = 0 if fitted[0] is not None else 1
    swapped = use == 1
    chosen = fitted[use]
    assert chosen is not None
    other = 1 - use
    if other < len(ordered):
        fo = fitted[other]
        other_angles = fo if fo is not None else ordered[other].angles
        other_diff = diffs[other]
    else:
        other_angles = (math.nan, math.nan)
        other_diff = (math.nan, math.nan)
    if swapped:
        reasons.append(
            "first solution discarded by the limits; the second is used and $P_TCANG[1/2] and "
            "[3/4] are swapped"
        )
    e = np.asarray(inverse.base)
    achieved = relative_direction(carrier, chosen[0], chosen[1], e)
    cosang = float(np.clip(achieved @ np.asarray(inverse.direction), -1.0, 1.0))
    err = math.degrees(math.acos(cosang))
    if err < 1e-7:
        err = 0.0
    return Selection(
        word=word,
        reference=(float(reference[0]), float(reference[1])),
        inverse=inverse,
        ordered=tuple(ordered),
        chosen=(float(chosen[0]), float(chosen[1])),
        p_tcang=(chosen[0], chosen[1], other_angles[0], other_angles[1]),
        tcang0=inverse.count,
        tcsol=tcsol,
        tcdiff=(diffs[use][0], diffs[use][1], other_diff[0], other_diff[1]),
        swapped=swapped,
        orientation_error_deg=err,
        reasons=tuple(reasons),
    )


def frame_matrix(frame: Sequence[float] | Sequence[Sequence[float]] | np.ndarray) -> np.ndarray:
    """A frame rotation from ROT-style angles ``(x, y, z)`` [deg] (RPY ``Rz·Ry·Rx``) or a 3×3
    rotation matrix (checked to be orthonormal with determinant +1 to 1e-9)."""
    arr = np.asarray(frame, dtype=float)
    if arr.shape == (3,):
        return rpy_matrix(float(arr[0]), float(arr[1]), float(arr[2]))
    if arr.shape == (3, 3):
        if (
            not np.all(np.isfinite(arr))
            or np.max(np.abs(arr @ arr.T - np.eye(3))) > 1e-9
            or abs(np.linalg.det(arr) - 1.0) > 1e-9
        ):
            raise ValueError("frame matrix must be a rotation (orthonormal, det +1)")
        return arr
    raise ValueError(f"frame must be 3 ROT angles or a 3x3 matrix, got shape {arr.shape}")


def solve_orientation(
    carrier: Carrier,
    *,
    frame: Sequence[float] | Sequence[Sequence[float]] | np.ndarray | None = None,
    direction: Sequence[float] | np.ndarray | None = None,
    word: OrientationWord | str = OrientationWord.TCOFR,
    reference: tuple[float, float] | None = None,
    axis_positions: Mapping[str, float] | None = None,
    span: SourceSpan | None = None,
) -> Selection:
    """Angles for TCOFR/TCOFRZ/Y/X: the tool axis (z/y/x) parallel to the same frame axis.

    Exactly one of ``frame`` (ROT angles [deg] or a rotation matrix) and ``direction`` (the
    requested tool direction, any length) is given; with neither the identity frame is used.
    The result is independent of the plane G17–G19.

    Parameters
    ----------
    reference:
        Specified angles [deg]; default :func:`reference_angles` of the carrier.
    axis_positions:
        Channel axis positions [deg] at the start of the activating block (for ``$TC_CARR21/22``).
    span:
        Source span for diagnostics.

    Raises
    ------
    AlarmError
        ``TH-UNREACHABLE`` or ``TH-NO-VALID-SOLUTION``.
    ValueError
        Both ``frame`` and ``direction`` given, TCOABS as word, or a malformed frame/direction.
    """
    w = OrientationWord.parse(word)
    if w is OrientationWord.TCOABS:
        raise ValueError("TCOABS does not solve an orientation; use tcoabs_angles()")
    if frame is not None and direction is not None:
        raise ValueError("give either a frame or a direction, not both")
    e = np.zeros(3)
    e[w.base_axis] = 1.0
    if direction is not None:
        d = _unit(direction, "direction")
    else:
        rot = np.eye(3) if frame is None else frame_matrix(frame)
        d = rot @ e
    ref = reference if reference is not None else reference_angles(carrier, axis_positions)
    inv = inverse_solutions(carrier, d, e, ref)
    return select_solution(carrier, inv, ref, word=w, span=span)


def tcoabs_angles(
    carrier: Carrier,
    axis_positions: Mapping[str, float] | None = None,
    *,
    span: SourceSpan | None = None,
) -> Selection:
    """Angles for TCOABS (spec §5): referenced axis positions or ``$TC_CARR13/14``, checked
    against the software limits with ±k·360° retries (spec §7.6).

    Raises
    ------
    AlarmError
        ``TH-LIMIT`` when an angle cannot be brought inside its limits.
    """
    ref = reference_angles(carrier, axis_positions)
    fitted = []
    reasons = [f"TCOABS: specified angles {_pair_text(ref)}"]
    for i in range(2):
        lim = carrier.limits(i + 1)
        f = fit_limits(ref[i], lim, ref[i])
        if f is None:
            assert lim is not None
            raise _error(
                "TH-LIMIT",
                f"toolholder {carrier.number}: axis {i + 1} angle {_fmt(ref[i])} deg is outside "
                f"the limits [{_fmt(lim[0])}, {_fmt(lim[1])}] ($TC_CARR{30 + i}/{32 + i}) "
                "also after +-k*360 deg",
                span,
            )
        if f != ref[i]:
            reasons.append(f"axis {i + 1}: {_fmt(ref[i])} brought inside the limits as {_fmt(f)}")
        fitted.append(f)
    pair = AnglePair(fitted[0], fitted[1])
    nan = math.nan
    return Selection(
        word=OrientationWord.TCOABS,
        reference=ref,
        inverse=None,
        ordered=(AnglePair(ref[0], ref[1]),),
        chosen=pair.angles,
        p_tcang=(pair.angle1, pair.angle2, nan, nan),
        tcang0=1,
        tcsol=1,
        tcdiff=(0.0, 0.0, nan, nan),
        swapped=False,
        orientation_error_deg=0.0,
        reasons=tuple(reasons),
    )
