"""Which pair of angles a toolholder activation uses, and its ``$P_TCANG`` bookkeeping (spec §7).

:func:`select_solution` applies to the exact pairs of :func:`~.inverse.inverse_solutions`, in this
order (spec R9): the 360° shift toward the specified angles (:func:`shift_toward`), the Hirth grid
(:func:`hirth_round`), the ordering (first = smaller L1 distance to the specified angles), and the
software limits with ±k·360° retries (:func:`fit_limits`) and fall-back to the second pair
(``$P_TCANG`` swapped). The result is a :class:`Selection`, also for TCOABS
(:func:`~.orientation.tcoabs_angles`); :class:`OrientationWord` says which word produced it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from trcopt.codes import Code
from trcopt.errors import SourceSpan
from trcopt.kinematics.carrier import Carrier, holder_error
from trcopt.kinematics.forward import relative_direction
from trcopt.kinematics.inverse import AnglePair, InverseResult
from trcopt.modes import OrientationWord

__all__ = [
    "Selection",
    "select_solution",
    "shift_toward",
    "hirth_round",
    "fit_limits",
    "format_angle",
    "format_pair",
]

_LIMIT_TOL = 1e-9


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


def format_angle(x: float) -> str:
    """An angle [deg] as the messages and reasons write it (``nan`` for a missing one)."""
    return "nan" if math.isnan(x) else f"{x:.6g}"


def format_pair(p: tuple[float, float] | AnglePair) -> str:
    """A pair of angles [deg] as the messages and reasons write it: ``(a1, a2)``."""
    a1, a2 = p.angles if isinstance(p, AnglePair) else p
    return f"({format_angle(a1)}, {format_angle(a2)})"


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
        raise holder_error(
            Code.TH_UNREACHABLE,
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
                        f"axis {i + 1}: {format_angle(a[i])} shifted by {format_angle(s - a[i])} toward the "
                        f"specified {format_angle(reference[i])} -> {format_angle(s)}"
                    )
                a[i] = s
        shifted.append(p.with_angles(a[0], a[1]))
    for p in inverse.pairs:
        for i, free in enumerate((p.free1, p.free2)):
            if free:
                reasons.append(f"axis {i + 1} is free; kept at the specified {format_angle(reference[i])}")
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
                        f"axis {i + 1}: Hirth grid {format_angle(grid[0])} + k*{format_angle(grid[1])} rounds "
                        f"{format_angle(a[i])} to {format_angle(r)} (diff {diff[i]:+.4f})"
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
            f"first solution {format_pair(ordered[0])} is closest to the specified angles "
            f"{format_pair(reference)} (distance {dist[0]:.6g} deg vs {dist[1]:.6g} deg)"
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
                f"pair {format_pair(p)}: axis {bad} outside its limits [{format_angle(lo)}, {format_angle(hi)}] "
                "also after +-k*360 deg"
            )
        elif (f1, f2) != p.angles:
            reasons.append(
                f"pair {format_pair(p)} brought inside the limits as {format_pair((f1, f2))}"
            )
    tcsol = sum(f is not None for f in fitted)
    if tcsol == 0:
        raise holder_error(
            Code.TH_NO_VALID_SOLUTION,
            f"toolholder {m}: no solution within the software limits $TC_CARR30-33 "
            f"(solutions {', '.join(format_pair(p) for p in ordered)})",
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
