"""What a corner strategy returns: the new tool-centre path and one record per corner.

* :class:`CornerRecord` — what happened at one tangent discontinuity (or curvature jump);
* :class:`CornerResult` — the new path, the records, the measured deviation, the strategy's name;
* :data:`JUMP_SMOOTHED` — the reason of a record whose curvature jump got a G2 spline.

Importing this module loads no numerical library, so the strategy registry can name it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from trcopt.modes import CornerObjective, TransitionKind
from trcopt.path import Segment

if TYPE_CHECKING:
    from trcopt.optimize.corners.qp import CornerSolution

__all__ = ["JUMP_SMOOTHED", "CornerRecord", "CornerResult"]

JUMP_SMOOTHED = "curvature jump smoothed"  # reason of a record whose curvature jump got a G2 spline


@dataclass(frozen=True)
class CornerRecord:
    """What happened at one tangent discontinuity (joint between toolpath[index] and [index+1]).

    Attributes
    ----------
    index:
        The joint: between ``toolpath[index]`` and ``toolpath[index + 1]``.
    turn_deg:
        Signed turning angle of the exact path there, degrees (positive = left).
    inside:
        True when the material lies on the outer side of the turn (pocket-like corner).
    blended:
        True when a transition replaced the corner.
    tolerance_mm:
        Contour tolerance the transition was built for, mm (tightened below the requested one
        where the measured deviation needed it).
    max_curvature:
        Peak curvature of the transition, 1/mm.
    span_mm:
        Length of the exact path the transition replaced, ``sa + sb``, mm.
    solution:
        The G2 quintic problem's solution, also when a circular blend was used instead.
    reason:
        Why the corner was not blended, or why it got the transition it got ("" when nothing is
        to say).
    transition:
        The curve that replaced the corner; None when not blended.
    vertex_mm, contour_mm:
        Distance of the transition from the corner point, and the largest distance of the new path
        from the exact one (tool-centre paths), mm; None when not measured.
    radius_mm:
        Radius of a circular blend, mm.
    """

    index: int
    turn_deg: float
    inside: bool
    blended: bool
    tolerance_mm: float
    max_curvature: float | None = None
    span_mm: float | None = None
    solution: CornerSolution | None = None
    reason: str = ""
    transition: TransitionKind | None = None
    vertex_mm: float | None = None
    contour_mm: float | None = None
    radius_mm: float | None = None


@dataclass
class CornerResult:
    """New tool-centre path and per-corner records.

    Attributes
    ----------
    segments:
        The new tool-centre path.
    corners:
        One record per corner site, by joint index.
    max_deviation_mm:
        Largest material left beyond the exact path's cut, mm (measured by
        :func:`~trcopt.optimize.corners.deviation.cut_deviation`).
    mode:
        Name of the strategy that made it (:mod:`trcopt.optimize.corners.strategies`).
    objective:
        What the transitions minimise; None when the strategy
        optimises nothing.
    """

    segments: list[Segment]
    corners: list[CornerRecord] = field(default_factory=list)
    max_deviation_mm: float = 0.0
    mode: str = "optimal"
    objective: CornerObjective | None = None
    origin: list[int] | None = None  # per new segment, the exact segment it comes from (when known)

    @property
    def blended(self) -> int:
        """Number of corners given a transition."""
        return sum(c.blended for c in self.corners)

    def count(self, transition: TransitionKind) -> int:
        """Corners blended with ``transition``."""
        return sum(c.blended and c.transition is transition for c in self.corners)

    @property
    def curvature_jumps(self) -> int:
        """Curvature jumps (tangent-continuous joints) replaced by G2 splines."""
        return sum(c.blended and c.reason == JUMP_SMOOTHED for c in self.corners)
