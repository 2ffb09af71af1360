"""The orientation words of a program: the holder angles for TCOABS and TCOFR/TCOFRZ/Y/X (spec §5).

* :func:`solve_orientation` — TCOFR and its variants: the tool axis parallel to the same axis of a
  frame (ROT angles or a rotation matrix, :func:`frame_matrix`) or to a requested direction, by
  the closed-form inverse (:mod:`trcopt.kinematics.inverse`) and the selection rules
  (:mod:`trcopt.kinematics.selection`);
* :func:`tcoabs_angles` — TCOABS: the specified angles themselves, brought inside the limits;
* :func:`reference_angles` — the specified angles: the referenced channel axes or ``$TC_CARR13/14``.

Angles in degrees.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from trcopt.codes import Code
from trcopt.errors import SourceSpan
from trcopt.kinematics.carrier import Carrier, holder_error
from trcopt.kinematics.forward import rpy_matrix
from trcopt.kinematics.inverse import AnglePair, inverse_solutions, unit_vector
from trcopt.kinematics.selection import Selection, fit_limits, format_angle, format_pair, select_solution
from trcopt.modes import OrientationWord, parse_enum

__all__ = ["solve_orientation", "tcoabs_angles", "reference_angles", "frame_matrix"]


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
    w = parse_enum(OrientationWord, word)
    if w is OrientationWord.TCOABS:
        raise ValueError("TCOABS does not solve an orientation; use tcoabs_angles()")
    if frame is not None and direction is not None:
        raise ValueError("give either a frame or a direction, not both")
    e = np.zeros(3)
    e[w.base_axis] = 1.0
    if direction is not None:
        d = unit_vector(direction, "direction")
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
    reasons = [f"TCOABS: specified angles {format_pair(ref)}"]
    for i in range(2):
        lim = carrier.limits(i + 1)
        f = fit_limits(ref[i], lim, ref[i])
        if f is None:
            assert lim is not None
            raise holder_error(
                Code.TH_LIMIT,
                f"toolholder {carrier.number}: axis {i + 1} angle {format_angle(ref[i])} deg is outside "
                f"the limits [{format_angle(lim[0])}, {format_angle(lim[1])}] ($TC_CARR{30 + i}/{32 + i}) "
                "also after +-k*360 deg",
                span,
            )
        if f != ref[i]:
            reasons.append(f"axis {i + 1}: {format_angle(ref[i])} brought inside the limits as {format_angle(f)}")
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
