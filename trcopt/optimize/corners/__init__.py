"""Feed-optimised corner transitions within a contour tolerance.

* :mod:`.strategies` — the registry of corner strategies (``program``, ``exact``, ``arc``,
  ``optimal``), each a module of its own (:mod:`.program`, :mod:`.exact`, :mod:`.arc`, :mod:`.optimal`);
* :mod:`.apply` — the pipeline's corner stage: the program's path-control mode or a strategy;
* :mod:`.fillet` (with :mod:`.fillet_spec`, :mod:`.fillet_elements`, :mod:`.tangent_circle`,
  :mod:`.bspline_corner`) — circular and G2 B-spline blends in closed form, on every path;
* :mod:`.blend` — :func:`blend_corners`, the entry point: runs a strategy by name;
* :mod:`.records` — what a strategy returns (:class:`CornerResult`, :class:`CornerRecord`);
* :mod:`.sites` — the corners of a tool path and what constrains them (:func:`find_corner_sites`);
* :mod:`.boundary` — the exact cut boundary and the material a path leaves;
* :mod:`.deviation` — the largest material a new path leaves beyond the exact cut (:func:`cut_deviation`);
* :mod:`.centres` — the new path's disc centres for that measurement, sampled on demand;
* :mod:`.samples` — sample points and boxes of elements and paths for that measurement;
* :mod:`.qp` — one corner as a G2 quintic problem (SQP of convex QPs);
* :mod:`.chain` (with :mod:`.chain_geometry`, :mod:`.chain_spline`, :mod:`.chain_qp`) — one G2 cubic
  spline across a run of small CAM corners or a curvature jump;
* :mod:`.circular` — the largest same-ε circular blend at one corner;
* :mod:`.assemble` — the new path from the transitions, fitted to the tolerance;
* :mod:`.selection` — the fastest of G2, circular and a per-corner mix;
* :mod:`.curves` — curvature, turning angle and the quintic basis shared by the above.

The names below load on first use (PEP 562), so the registry — and with it ``trcopt plan``'s
argument parser — imports no numerical library.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from trcopt.lazy import lazy_exports

if TYPE_CHECKING:
    from trcopt.optimize.corners.blend import blend_corners, optimize_corners
    from trcopt.optimize.corners.deviation import cut_deviation
    from trcopt.optimize.corners.qp import CornerBlendProblem
    from trcopt.optimize.corners.records import JUMP_SMOOTHED, CornerRecord, CornerResult
    from trcopt.optimize.corners.sites import CornerSite, find_corner_sites
    from trcopt.optimize.corners.strategies import CornerJob, CornerStrategy

_LAZY = {
    "blend_corners": "trcopt.optimize.corners.blend",
    "optimize_corners": "trcopt.optimize.corners.blend",
    "cut_deviation": "trcopt.optimize.corners.deviation",
    "CornerBlendProblem": "trcopt.optimize.corners.qp",
    "JUMP_SMOOTHED": "trcopt.optimize.corners.records",
    "CornerRecord": "trcopt.optimize.corners.records",
    "CornerResult": "trcopt.optimize.corners.records",
    "CornerSite": "trcopt.optimize.corners.sites",
    "find_corner_sites": "trcopt.optimize.corners.sites",
    "CornerJob": "trcopt.optimize.corners.strategies",
    "CornerStrategy": "trcopt.optimize.corners.strategies",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


__all__ = [
    "JUMP_SMOOTHED",
    "CornerBlendProblem",
    "CornerJob",
    "CornerRecord",
    "CornerResult",
    "CornerSite",
    "CornerStrategy",
    "blend_corners",
    "cut_deviation",
    "find_corner_sites",
    "optimize_corners",
]
