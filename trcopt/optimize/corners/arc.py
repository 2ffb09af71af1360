"""The ``arc`` corner strategy: the largest same-ε circular blend at every corner between two lines
(and, on a path without compensation, between a line and an arc or two arcs).

The baseline of the optimised transitions, the usual controller smoothing, in closed form
(:mod:`~trcopt.optimize.corners.fillet`): on a compensated path ε bounds the material left on the
cut part (an inside corner's blend has vertex distance ε; an outside corner's blend is the
transition circle, which leaves nothing and gouges nothing); on an uncompensated path (G40 CAM
output) ε bounds the distance of the new path from the programmed one, measured as the job's
tolerance kind says.
"""

from __future__ import annotations

from trcopt.optimize.corners.assemble import TARGET_MARGIN
from trcopt.optimize.corners.curves import joint_turn
from trcopt.optimize.corners.fillet import (
    FilletSpec,
    cut_contour_spec,
    fillet_path,
    line_joints,
)
from trcopt.optimize.corners.records import CornerResult
from trcopt.optimize.corners.strategies import CornerJob
from trcopt.path import Role

__all__ = ["arc_transitions"]


def arc_transitions(job: CornerJob) -> CornerResult:
    """``job``'s path with a circular blend at every corner between two lines, within its tolerance."""
    if job.tolerance_mm <= 0:
        return job.unchanged()
    segs = list(job.toolpath)
    specs: dict[int, FilletSpec] = {}
    for k in line_joints(segs):
        seg = segs[k]
        # a small margin below ε: the closed form meets ε exactly, a sampled check may not
        tol = (1.0 - TARGET_MARGIN) * job.tolerance_at(k)
        if seg.radius > 0.0:
            if seg.role not in (Role.CONTOUR, Role.CORNER) or segs[k + 1].role not in (Role.CONTOUR, Role.CORNER):
                continue  # approach and retraction corners of a compensated path stay exact
            specs[k] = cut_contour_spec(seg, joint_turn(seg.geometry, segs[k + 1].geometry), tol)  # type: ignore[arg-type]
        else:
            specs[k] = FilletSpec(tol, job.kind)
    return fillet_path(segs, specs, job.strategy)
