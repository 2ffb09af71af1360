"""Optimal lead-out: the time-optimal retraction from the end of the compensated contour.

A lead-out is the lead-in of the mirrored problem: walking the contour backwards from its end,
the end point of the retraction becomes the start point and the compensation side swaps (left of
travel becomes right). :func:`optimal_lead_out` solves that problem with :func:`optimal_lead` —
same constraint model: tangency at the contour end, curvature ≤ 1/ρmin, clearance ≥ R + safety
from the whole contour, no reversal of the infeed axis, optional allowed region — and reverses
the result, so the elements run from the contour end's tool-centre point to the end point.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.geometry import Plane
from trcopt.geometry.vec import Vec2
from trcopt.modes import LeadObjective, Side, parse_enum
from trcopt.optimize.leads.leadin import optimal_lead
from trcopt.optimize.leads.records import Element, LeadResult, lead_segments
from trcopt.path import Role, Segment

__all__ = ["LeadOutResult", "optimal_lead_out"]


@dataclass(frozen=True, slots=True)
class LeadOutResult:
    """The optimal lead-out; ``mirrored`` is the lead-in of the reversed problem it came from."""

    mirrored: LeadResult

    @property
    def elements(self) -> tuple[Element, ...]:
        """Tool-centre elements from the contour end (P4c) to the end point."""
        return tuple(e.reversed() for e in reversed(self.mirrored.elements))

    @property
    def kind(self) -> str:
        return self.mirrored.kind

    @property
    def length(self) -> float:
        return self.mirrored.length

    @property
    def time_s(self) -> float:
        return self.mirrored.time_s

    @property
    def objective(self) -> LeadObjective:
        return self.mirrored.objective

    @property
    def side(self) -> Side:
        """The compensation side of the contour (not of the mirrored problem)."""
        return Side.RIGHT if self.mirrored.side is Side.LEFT else Side.LEFT

    @property
    def segments(self) -> list[Segment]:
        m = self.mirrored
        return [
            replace(s, role=Role.RETRACT)
            for s in lead_segments(self.elements, m.plane, m.feed_mm_s, self.side, m.radius)
        ]

    def to_json(self) -> dict[str, Any]:
        out = self.mirrored.to_json()
        out["direction"] = "out"
        out["side"] = self.side.value
        out["segments"] = [s.to_json() for s in self.segments]
        return out


def optimal_lead_out(
    end: Sequence[float],
    contour: Sequence[Element | Segment],
    radius: float,
    side: Side | str,
    *,
    rho_min: float = 2.0,
    safety: float = 1.0,
    region: Sequence[Vec2] | None = None,
    machine: Machine = DEFAULT_MACHINE,
    feed_mm_s: float = 10.0,
    plane: Plane = Plane.G17,
) -> LeadOutResult:
    """The time-optimal tool-centre lead from the end of ``contour`` to ``end``.

    Parameters are those of :func:`~trcopt.optimize.leads.optimal_lead` with ``end`` (mm, plane
    coordinates) in place of the start point; ``contour`` is in program order and ends where
    the lead-out begins. Raises :class:`~trcopt.errors.SolverError` naming the binding
    constraint when no lead fits.
    """
    side_e = parse_enum(Side, side)
    mirrored_side = Side.RIGHT if side_e is Side.LEFT else Side.LEFT if side_e is Side.RIGHT else side_e
    backwards = [(c.geometry if isinstance(c, Segment) else c).reversed() for c in reversed(contour)]
    lead = optimal_lead(
        end,
        backwards,
        radius,
        mirrored_side,
        rho_min=rho_min,
        safety=safety,
        region=region,
        machine=machine,
        feed_mm_s=feed_mm_s,
        plane=plane,
    )
    return LeadOutResult(lead)
