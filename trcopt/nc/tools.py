"""Tool-edge data as the NC front end sees it: ``$TC_DP1`` (type), ``$TC_DP6`` (radius) and
``$TC_DP15`` (wear radius) per tool T and edge D.

A :class:`ToolTable` starts from an optional preset (``{(t, d): ToolEdge | mapping}``) and is
updated by the program's ``$TC_DP`` assignments. The effective compensation value of an edge is
``radius + wear`` (mm); the interpreter adds OFFN.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

__all__ = ["ToolEdge", "ToolTable", "tool_kind"]

# $TC_DPn parameter number -> ToolEdge field
_DP_FIELDS = {1: "type", 6: "radius", 15: "wear"}


def tool_kind(tool_type: int) -> str:
    """Family of a SINUMERIK tool type number: milling (1xx), drill (2xx), grinding (4xx),
    turning (5xx), slotting/special (7xx), or unspecified (0)."""
    family = int(tool_type) // 100
    return {
        0: "unspecified",
        1: "milling",
        2: "drill",
        4: "grinding",
        5: "turning",
        7: "special",
    }.get(family, "other")


@dataclass(frozen=True, slots=True)
class ToolEdge:
    """One cutting edge (T, D).

    Parameters
    ----------
    type:
        ``$TC_DP1`` tool type (120 = end mill; 0 = not given).
    radius:
        ``$TC_DP6`` geometry radius, mm.
    wear:
        ``$TC_DP15`` wear radius, mm (signed, added to the radius).
    """

    type: int = 0
    radius: float = 0.0
    wear: float = 0.0

    @property
    def compensation(self) -> float:
        """Radius + wear (mm), the tool's part of the effective compensation value."""
        return self.radius + self.wear

    @property
    def kind(self) -> str:
        return tool_kind(self.type)

    @property
    def supports_trc(self) -> bool:
        """False for drills (2xx) and turning/grinding tools (4xx/5xx): not for 2D TRC."""
        return self.kind not in ("drill", "grinding", "turning")

    @classmethod
    def from_value(cls, value: ToolEdge | Mapping[str, Any]) -> ToolEdge:
        """Accept a ToolEdge or a mapping with keys ``type``, ``radius``, ``wear`` only (values as
        ``int()`` / ``float()`` read them: numbers or numeric strings; radius and wear in mm)."""
        if isinstance(value, ToolEdge):
            return value
        if not isinstance(value, Mapping):
            raise TypeError(
                f"tool edge must be a ToolEdge or a mapping, got {type(value).__name__}"
            )
        unknown = set(value) - {"type", "radius", "wear"}
        if unknown:
            raise ValueError(
                f"unknown tool edge key {sorted(unknown)[0]!r}; valid: type, radius, wear"
            )
        return cls(
            type=int(value.get("type", 0)),
            radius=float(value.get("radius", 0.0)),
            wear=float(value.get("wear", 0.0)),
        )


class ToolTable:
    """Mutable per-program tool-edge store keyed by (T, D)."""

    __slots__ = ("_edges", "version")

    def __init__(
        self, preset: Mapping[tuple[int, int], ToolEdge | Mapping[str, object]] | None = None
    ) -> None:
        self._edges: dict[tuple[int, int], ToolEdge] = {}
        self.version = 0  # incremented by every assignment (lets readers cache derived values)
        for key, value in (preset or {}).items():
            t, d = key
            self._edges[(int(t), int(d))] = ToolEdge.from_value(value)

    def get(self, tool: int, edge: int) -> ToolEdge | None:
        """The edge's data, or None when nothing is known about (tool, edge)."""
        return self._edges.get((tool, edge))

    def assign(self, parameter: int, tool: int, edge: int, value: float) -> bool:
        """Apply ``$TC_DP<parameter>[tool, edge] = value``; False for a parameter not modelled."""
        name = _DP_FIELDS.get(parameter)
        if name is None:
            return False
        self.version += 1
        current = self._edges.get((tool, edge), ToolEdge())
        if name == "type":
            updated = replace(current, type=int(value))
        elif name == "radius":
            updated = replace(current, radius=float(value))
        else:
            updated = replace(current, wear=float(value))
        self._edges[(tool, edge)] = updated
        return True

    def as_dict(self) -> dict[tuple[int, int], ToolEdge]:
        return dict(self._edges)

    def __contains__(self, key: object) -> bool:
        return key in self._edges

    def __len__(self) -> int:
        return len(self._edges)
