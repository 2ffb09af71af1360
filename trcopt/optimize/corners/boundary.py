"""The cut boundary of the exact tool path and the material a new path leaves beyond it.

The cut-part deviation is measured on the physics, not on the tool-centre path: the exact path's
cut boundary is probed along its normals (:func:`boundary_probes`) and the new path's swept discs
must reach every probe (:func:`material_left`); :func:`~.deviation.cut_deviation` is the largest
thickness left over a whole path.

* :func:`blendable` — a segment whose corners may be replaced (compensated plane feed motion);
* :func:`material_sign` — on which side of a compensated segment the material lies;
* :func:`envelope`, :func:`joint_fans` — the candidate points of the exact cut boundary;
* :func:`element_samples` — points and tangents of a line or arc (:mod:`.samples`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.optimize.corners.chain_geometry import Elements
from trcopt.optimize.corners.samples import FAN, element_samples, elements_samples, fans
from trcopt.path import Role, Segment

__all__ = [
    "blendable",
    "boundary_probes",
    "element_samples",
    "envelope",
    "joint_fans",
    "material_left",
    "material_sign",
]


def blendable(seg: Segment) -> bool:
    """True for a compensated plane feed line or arc of the contour (or a corner element)."""
    g = seg.geometry
    return (
        not seg.is_rapid
        and seg.role in (Role.CONTOUR, Role.CORNER)
        and seg.radius > 0
        and isinstance(g, Line | Arc)
        and g.plane_length > 1e-9
        and abs(g.start[2] - g.end[2]) <= 1e-12
    )


def material_sign(seg: Segment) -> float:
    """+1 when the material lies left of the tool's travel (G42), −1 when right (G41)."""
    # G41 (LEFT): tool left of the contour, so the material is right of travel (−1)
    return -1.0 if seg.side.value == "left" else 1.0


def _normal(t: np.ndarray, sign: float) -> np.ndarray:
    return sign * np.array([-t[..., 1], t[..., 0]]).T if t.ndim > 1 else sign * np.array([-t[1], t[0]])


def boundary_probes(
    exact: Sequence[Line | Arc],
    programmed: Sequence[Line | Arc],
    radius: float,
    sign: float,
    step: float,
    near: np.ndarray | None = None,
    reach: float = math.inf,
    others: Sequence[Line | Arc] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Points of the exact cut boundary (n×2, mm) and unit directions away from the material (n×2).

    Candidates (:func:`_candidates`) kept where they lie on the boundary of the exact swept region
    (:func:`_on_boundary`; the path is ``exact`` and ``others``, every element that comes within
    ``radius`` of the candidates) and, with ``near``, within ``reach`` mm of it.
    """
    P, D = _candidates(exact, programmed, radius, sign, step)
    if near is not None:
        keep = np.hypot(*(P - near[None, :]).T) <= reach
        P, D = P[keep], D[keep]
    keep = _on_boundary(Elements([*exact, *(others or ())]), P, radius)
    return P[keep], D[keep]


def _candidates(
    exact: Sequence[Line | Arc], programmed: Sequence[Line | Arc], radius: float, sign: float, step: float
) -> tuple[np.ndarray, np.ndarray]:
    """Candidate points of the exact cut boundary and their directions away from the material: the
    envelope points of the exact centre elements every ``step`` mm (:func:`envelope`), disc fans
    at their joints, the programmed vertices with their normal fans (:func:`joint_fans`)."""
    P, D = envelope(exact, radius, sign, step)
    Pf, Df = joint_fans(exact, programmed, radius, sign)
    return np.vstack((P, Pf)), np.vstack((D, Df))


def envelope(exact: Sequence[Line | Arc], radius: float, sign: float, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The envelope points of the exact centre elements every ``step`` mm and their directions
    away from the material."""
    if not exact:
        return np.zeros((0, 2)), np.zeros((0, 2))
    p, t = elements_samples(exact, step)
    n = _normal(t, sign)
    return p + radius * n, -n


def joint_fans(
    exact: Sequence[Line | Arc], programmed: Sequence[Line | Arc], radius: float, sign: float
) -> tuple[np.ndarray, np.ndarray]:
    """The candidates of the exact cut boundary at joints: disc fans at the joints of the exact
    centre elements, the programmed vertices with their normal fans (points, directions away
    from the material)."""
    pts, dirs = [np.zeros((0, 2))], [np.zeros((0, 2))]
    ends = [(e1, e2) for e1, e2 in zip(exact[:-1], exact[1:], strict=False) if math.dist(e1.end, e2.start) <= 1e-9]
    if ends:
        fan = fans([(_normal(np.array(e1.end_tangent()), sign), _normal(np.array(e2.start_tangent()), sign))
                    for e1, e2 in ends])  # fmt: skip
        pts.append(np.repeat(np.array([e1.point2(1.0) for e1, _ in ends]), FAN, axis=0) + radius * fan)
        dirs.append(-fan)
    ends = [
        (e1, e2) for e1, e2 in zip(programmed[:-1], programmed[1:], strict=False)
        if math.dist(e1.end[:2], e2.start[:2]) <= 1e-9
    ]  # fmt: skip
    if ends:
        fan = fans([(-_normal(np.array(e1.end_tangent()), sign), -_normal(np.array(e2.start_tangent()), sign))
                    for e1, e2 in ends])  # fmt: skip
        pts.append(np.repeat(np.array([e1.point2(1.0) for e1, _ in ends]), FAN, axis=0))
        dirs.append(fan)
    return np.vstack(pts), np.vstack(dirs)


def _on_boundary(path: Elements, P: np.ndarray, radius: float) -> np.ndarray:
    """Which of the points ``P`` lie on the boundary of the region swept by discs of ``radius``
    along ``path``: their distance to it is ``radius`` (to a relative 1e-7); only elements within
    that distance of a point matter."""
    tol = 1e-7 * max(radius, 1.0)
    m, _, d = path.near_distances(P, radius + tol, ordered=False)
    dmin = np.full(len(P), np.inf)
    np.minimum.at(dmin, m, d)
    return np.abs(dmin - radius) <= tol


def material_left(probes: np.ndarray, dirs: np.ndarray, centres: np.ndarray, radius: float) -> np.ndarray:
    """Thickness of material left along each probe ray (mm, ≥ 0).

    A probe is a point of the exact cut boundary with the unit direction pointing away from the
    material; the new tool sweeps discs of ``radius`` around ``centres``. The result is the
    distance along the ray to the first disc (0 when the probe itself is swept). Sampled centres
    sweep a subset of the true region, so the value is an upper bound. ``centres`` is m×2 (the
    same for every probe) or n×m×2 (its own centres per probe).
    """
    rel = (centres if centres.ndim == 3 else centres[None, :, :]) - probes[:, None, :]  # n×m×2
    return _left_along(rel, dirs, radius)[0]


def _left_along(rel: np.ndarray, dirs: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`material_left` from the centres relative to the probes (n×m×2), and the squared
    distances of the centres from the probes (n×m)."""
    along = np.einsum("nmk,nk->nm", rel, dirs)
    dist2 = np.einsum("nmk,nmk->nm", rel, rel)
    perp2 = dist2 - along * along
    inside = perp2 <= radius * radius
    root = np.sqrt(np.maximum(radius * radius - perp2, 0.0))
    entry = np.where(inside, along - root, np.inf)
    exit_ = np.where(inside, along + root, -np.inf)
    # a disc that contains the probe (entry ≤ 0 ≤ exit) sweeps it: thickness 0
    covered = np.any((entry <= 0.0) & (exit_ >= 0.0), axis=1)
    ahead = np.where(entry > 0.0, entry, np.inf).min(axis=1)
    out = np.where(covered, 0.0, ahead)
    return np.minimum(out, 10.0 * radius + 1.0), dist2
