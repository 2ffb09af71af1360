"""Feed-optimised corner transitions within a contour tolerance.

* :mod:`.blend` — finds the tangent discontinuities of a tool path and replaces them
  (:func:`blend_corners`), measures the material left (:func:`cut_deviation`);
* :mod:`.qp` — one corner as a G2 quintic problem (SQP of OSQP QPs);
* :mod:`.chain` — one G2 cubic spline across a run of small CAM corners or a curvature jump;
* :mod:`.strategies` — the registry of transition strategies (``exact``, ``arc``, ``optimal``).
"""

from __future__ import annotations

from trcopt.optimize.corners.blend import (
    CornerRecord,
    CornerResult,
    blend_corners,
    cut_deviation,
    find_corner_sites,
    optimize_corners,
)

__all__ = [
    "CornerRecord",
    "CornerResult",
    "blend_corners",
    "cut_deviation",
    "find_corner_sites",
    "optimize_corners",
]
