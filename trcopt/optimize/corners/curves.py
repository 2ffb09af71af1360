"""Plane-curve measures shared by the corner modules.

* :func:`signed_curvature`, :func:`joint_turn` — of the tool-centre elements at a joint;
* :func:`frame_back`, :func:`frame_forward` — point, tangent and curvature at an arc length from
  an element's end or start (where a transition meets its neighbours);
* :func:`quintic_basis`, :func:`quintic_third_basis` — the quintic Hermite basis of the G2 corner
  transitions and its derivatives.
"""

from __future__ import annotations

import math

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.geometry.poly import quintic_hermite_basis, quintic_hermite_third

__all__ = [
    "Element",
    "frame_back",
    "frame_forward",
    "joint_turn",
    "quintic_basis",
    "quintic_third_basis",
    "rot90",
    "signed_curvature",
]

Element = Line | Arc


def quintic_basis(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic Hermite basis and its first two derivatives at ``u`` (K×6 each), coefficient order
    (P0, D0, A0, A1, D1, P1) as in :func:`trcopt.geometry.hermite_curve`."""
    u = np.asarray(u, float)
    h0, h1, h2 = quintic_hermite_basis(u)
    b0, b1, b2 = (np.stack(np.broadcast_arrays(*h), axis=1) for h in (h0, h1, h2))
    return b0, b1, b2


def quintic_third_basis(u: np.ndarray) -> np.ndarray:
    """Third derivatives of the quintic Hermite basis at ``u`` (K×6)."""
    u = np.asarray(u, float)
    return np.stack(np.broadcast_arrays(*quintic_hermite_third(u)), axis=1)


def frame_back(el: Element, s_back: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Point (mm), unit tangent and signed curvature (1/mm) of ``el`` at plane arc length
    ``s_back`` (mm) before its end."""
    return _frame(el, 1.0 - s_back / el.plane_length)


def frame_forward(el: Element, s_forward: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Point (mm), unit tangent and signed curvature (1/mm) of ``el`` at plane arc length
    ``s_forward`` (mm) after its start."""
    return _frame(el, s_forward / el.plane_length)


def _frame(el: Element, lam: float) -> tuple[np.ndarray, np.ndarray, float]:
    p = np.array(el.point2(lam), float)
    if isinstance(el, Line):
        return p, np.array(el.direction2(), float), 0.0
    return p, np.array(el.tangent2(lam), float), signed_curvature(el)


def signed_curvature(el: Element) -> float:
    """Signed plane curvature of a line (0) or arc (positive = turning left), 1/mm."""
    return 0.0 if isinstance(el, Line) else el.sense / el.radius


def joint_turn(a: Element, b: Element) -> float:
    """Signed turning angle from the end of ``a`` to the start of ``b``, rad (positive = left)."""
    ta, tb = a.end_tangent(), b.start_tangent()
    return math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])


def rot90(v: np.ndarray) -> np.ndarray:
    """Plane vectors (…×2) turned by +90°."""
    return np.stack((-v[..., 1], v[..., 0]), axis=-1)
