"""What an optimal lead is: the SAR words it matches, the solved candidates, the chosen lead.

* :class:`LeadResult` — the optimal lead and every candidate it was chosen from (JSON via
  :meth:`LeadResult.to_json`);
* :class:`LeadCandidate` — one solved member of a lead family;
* :class:`SarShape` — the lead as SINUMERIK SAR words, when it has a SAR shape;
* :func:`lead_segments` — lead elements as approach segments.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane, Poly
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import LeadObjective, Side
from trcopt.path import Role, Segment
from trcopt.solution import Solution

__all__ = ["Element", "LeadCandidate", "LeadResult", "SarShape", "lead_segments"]

Element = Line | Arc | Poly


@dataclass(frozen=True, slots=True)
class SarShape:
    """The lead expressed as SINUMERIK SAR words (when it has a SAR shape)."""

    contour: str  # G147 / G247 / G347
    disr: float
    discl: float  # incremental, mm (G340)
    side: str  # G141 / G142


@dataclass(frozen=True, slots=True)
class LeadCandidate:
    """One solved lead family member."""

    kind: str
    elements: tuple[Element, ...]
    length: float
    time_s: float
    min_clearance: float  # exact, to the contour elements not meeting P4, mm
    contact_clearance: float  # exact, to the elements meeting at P4, mm
    solution: Solution[Any]
    rho: float | None = None
    sweep: float | None = None


@dataclass(frozen=True, slots=True)
class LeadResult:
    """The optimal lead and everything it was chosen from.

    ``elements`` are tool-centre elements in plane coordinates from P0 to P4c; ``segments``
    the same as approach :class:`~trcopt.path.Segment` values (absolute coordinates via
    ``plane``); ``time_s`` is the objective value (traverse time over lead + first contour
    element, s, or the surrogate in mm when ``objective`` is ``LeadObjective.SURROGATE``).
    """

    best: LeadCandidate
    candidates: tuple[LeadCandidate, ...]
    objective: LeadObjective
    p0: Vec3
    p4: Vec3
    p4c: Vec3
    tangent: Vec2
    radius: float
    side: Side
    plane: Plane
    feed_mm_s: float
    sar: SarShape | None
    first_contour: Element
    solve_time_s: float = 0.0
    rho_min: float = 2.0
    safety: float = 1.0
    notes: list[str] = field(default_factory=list)

    @property
    def kind(self) -> str:
        return self.best.kind

    @property
    def elements(self) -> tuple[Element, ...]:
        return self.best.elements

    @property
    def length(self) -> float:
        return self.best.length

    @property
    def time_s(self) -> float:
        return self.best.time_s

    @property
    def segments(self) -> list[Segment]:
        return lead_segments(self.elements, self.plane, self.feed_mm_s, self.side, self.radius)

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "objective": self.objective.value,
            "time_s": self.time_s,
            "length_mm": self.length,
            "min_clearance_mm": self.best.min_clearance,
            "contact_clearance_mm": self.best.contact_clearance,
            "radius": self.radius,
            "side": self.side.value,
            "rho": self.best.rho,
            "sweep_deg": None if self.best.sweep is None else math.degrees(self.best.sweep),
            "sar": None
            if self.sar is None
            else {"contour": self.sar.contour, "disr": self.sar.disr, "discl": self.sar.discl, "side": self.sar.side},
            "segments": [s.to_json() for s in self.segments],
            "candidates": [
                {
                    "kind": c.kind,
                    "time_s": c.time_s,
                    "length_mm": c.length,
                    "rho": c.rho,
                    "status": c.solution.status.value,
                    "iterations": c.solution.iterations,
                }
                for c in self.candidates
            ],
        }


def lead_segments(elements: Sequence[Element], plane: Plane, feed: float, side: Side, radius: float) -> list[Segment]:
    """``elements`` as approach segments of block ``LEAD`` at ``feed`` (mm/s), compensation ``side``
    and ``radius`` (mm)."""
    span = SourceSpan(file="<lead>", block="LEAD")
    return [Segment(e, plane, Role.APPROACH, span, feed, side, radius) for e in elements]
