"""The ``arc`` corner strategy: the largest same-ε circular blend at every corner (G1).

The baseline of the optimised transitions, the usual controller smoothing: each tangent
discontinuity between two lines gets the largest circle tangent to both that leaves at most ε of
material on the cut part and does not gouge (:func:`~trcopt.optimize.corners.circular.circular_blend`);
where the measured deviation of the whole path exceeds ε, the corner nearest the worst probe is
tightened and the path rebuilt.
"""

from __future__ import annotations

from trcopt.optimize.corners.assemble import TARGET_MARGIN, TransitionPlan, fit_tolerance
from trcopt.optimize.corners.records import CornerResult
from trcopt.optimize.corners.sites import find_corner_sites
from trcopt.optimize.corners.strategies import CornerJob

__all__ = ["arc_transitions"]


def arc_transitions(job: CornerJob) -> CornerResult:
    """``job``'s path with a circular blend at every corner between two lines, within its tolerance."""
    if job.tolerance_mm <= 0:
        return job.unchanged()
    segs = list(job.toolpath)
    sites = find_corner_sites(segs, job.programmed, tolerance_mm=job.tolerance_mm)
    # a small margin for the difference between the per-corner and the global sampling
    eps = {k: (1.0 - TARGET_MARGIN) * job.tolerance_mm for k, _ in sites}
    return fit_tolerance(TransitionPlan(segs, sites, eps), job.programmed, job.tolerance_mm, job.strategy)
