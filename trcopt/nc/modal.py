"""Dialect-neutral modal machinery of the NC front end, and :func:`read_program`.

A dialect (``dialects/siemens.py``, …) turns each block's words into changes of a
:class:`ModalState` and asks this module for the geometry it must not get wrong: the end radius
check of an arc, the closed-form centre of a radius-programmed arc (``CR=``), and the modal
:class:`~trcopt.nc.model.CompState` snapshot (cached: most blocks share one).

Conventions: absolute workpiece coordinates in mm, feeds in mm/s, arcs in the (u, v) frame of the
active plane with ``ccw`` seen from +applicate (G3 = True in every plane).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.config import Tolerances
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec2
from trcopt.modes import (
    ApproachMode,
    ApproachStrategy,
    CollisionMode,
    CornerMode,
    LeadSegmentation,
    LeadSide,
    Side,
    ToolUnit,
)
from trcopt.nc.model import CompState, MoveKind
from trcopt.nc.tools import ToolEdge, ToolTable

__all__ = [
    "ModalState",
    "ReadOptions",
    "arc_centre_from_radius",
    "arc_radius_mismatch",
    "fail",
    "DEFAULT_EDGE",
]

DEFAULT_EDGE = 1  # edge activated by a tool change without D (MD20270 CUTTING_EDGE_DEFAULT)


def fail(code: Code, message: str, span: SourceSpan, alarm: int | None = None) -> AlarmError:
    """An error-severity diagnostic wrapped for raising inside a block reader."""
    return AlarmError(Diagnostic(Severity.ERROR, code, message, span, alarm))


@dataclass(frozen=True, slots=True)
class ReadOptions:
    """Options of :func:`read_program` passed to the dialect reader.

    Parameters
    ----------
    file:
        Name used in source spans.
    tolerances:
        Geometric tolerances (arc end radius check, coincidence).
    max_disc:
        Upper limit of DISC (MD20220 CUTCOM_MAX_DISC); larger values are clamped with a warning.
    tools:
        Preset tool edges ``{(t, d): ToolEdge | {"type":…, "radius": mm, "wear": mm}}``.
    tool_table:
        A tool-table file in the controller's own format (``None``: the controller looks beside
        the program where it has a table format, or uses the program's tool data).
    tool_unit:
        Length unit of ``tool_table`` where the format does not state it (LinuxCNC ``.tbl``).
    appr_radius:
        Heidenhain APPR/DEP CT/LCT radius reading: ``"centre"`` (the tool-centre arc's radius, the
        default) or ``"contour"`` (spec heidenhain_trc.md R9).
    zero_offsets:
        A TOML file of settable zero offsets (SINUMERIK G54…; ``None``: the one beside the program).
    """

    file: str = "<program>"
    tolerances: Tolerances = field(default_factory=Tolerances)
    max_disc: int = 50
    tools: Mapping[tuple[int, int], ToolEdge | Mapping[str, object]] | None = None
    tool_table: str | os.PathLike[str] | None = None
    tool_unit: ToolUnit = ToolUnit.PROGRAM
    appr_radius: str = "centre"
    zero_offsets: str | os.PathLike[str] | None = None


class ModalState:
    """The modal state of the control while a program is read (mutable, one per read)."""

    __slots__ = (
        "position",
        "plane",
        "motion",
        "feed_mm_s",
        "side",
        "corner",
        "disc",
        "approach",
        "collision",
        "strategy",
        "offn",
        "tools",
        "tool",
        "edge",
        "sar_side",
        "sar_segmentation",
        "_comp_cache",
    )

    def __init__(self, tools: ToolTable) -> None:
        self.position: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self.plane = Plane.G17
        self.motion = MoveKind.LINE  # G1 at program start (MD20150 default)
        self.feed_mm_s: float | None = None
        self.side = Side.OFF
        self.corner = CornerMode.TRANSITION_CIRCLE
        self.disc = 0
        self.approach = ApproachMode.NORM
        self.collision = CollisionMode.CDOF
        self.strategy = ApproachStrategy.G460
        self.offn = 0.0
        self.tools = tools
        self.tool: int | None = None
        self.edge: int | None = None
        self.sar_side = LeadSide.FROM_COMPENSATION
        self.sar_segmentation = LeadSegmentation.SPATIAL
        self._comp_cache: dict[tuple[object, ...], CompState] = {}

    def active_edge(self) -> ToolEdge | None:
        """Data of the selected (T, D), or None (no tool, no edge, D0, or no data)."""
        if self.tool is None or not self.edge:
            return None
        return self.tools.get(self.tool, self.edge)

    def tool_state(self) -> tuple[bool, float]:
        """(tool_active, effective compensation value R = DP6 + DP15 + OFFN in mm).

        D0 (with a tool or not) counts as an active tool with radius 0; an edge without data is
        not active (radius 0).
        """
        if self.edge == 0:
            return True, 0.0
        edge = self.active_edge()
        if edge is None:
            return False, 0.0
        return True, edge.compensation + self.offn

    def comp_state(self, side_programmed: bool = False) -> CompState:
        """The CompState snapshot in force (shared instances for equal states)."""
        # enum members are singletons: their ids make a cheap key (Enum.__hash__ is Python code)
        key = (
            id(self.side),
            self.tool,
            self.edge,
            self.offn,
            self.tools.version,
            id(self.corner),
            self.disc,
            id(self.approach),
            id(self.collision),
            id(self.strategy),
            side_programmed,
        )
        comp = self._comp_cache.get(key)
        if comp is None:
            active, radius = self.tool_state()
            comp = CompState(
                side=self.side,
                radius=radius,
                tool_active=active,
                corner=self.corner,
                disc=self.disc,
                approach=self.approach,
                collision=self.collision,
                strategy=self.strategy,
                side_programmed=side_programmed,
            )
            self._comp_cache[key] = comp
        return comp


def arc_centre_from_radius(
    start: Vec2, end: Vec2, radius: float, ccw: bool, tol: float, coincidence: float = 1e-3
) -> Vec2:
    """Centre of the arc from ``start`` to ``end`` (plane u, v in mm) with signed radius ``CR``.

    ``radius > 0`` selects the arc of at most 180°, ``radius < 0`` the one of more than 180°
    (SINUMERIK ``CR=``). A chord longer than the diameter by at most ``tol`` is accepted as a
    half circle; end points closer than ``coincidence`` (mm) are a full circle, which ``CR=``
    cannot describe. Raises ``ValueError`` (with the reason) when no such arc exists.
    """
    du, dv = end[0] - start[0], end[1] - start[1]
    chord = math.hypot(du, dv)
    r = abs(radius)
    if r == 0.0:
        raise ValueError("CR=0 does not define a circle")
    if chord <= coincidence:
        raise ValueError("CR= cannot describe a full circle (end point equals start point)")
    half = chord / 2.0
    if half > r:
        if half - r > tol:
            raise ValueError(
                f"radius {r:.4f} mm is smaller than half the chord {half:.4f} mm (no such arc)"
            )
        h = 0.0
    else:
        h = math.sqrt(r * r - half * half)
    # the centre of a CCW arc of at most 180° lies left of the chord start → end
    sign = (1.0 if ccw else -1.0) * (1.0 if radius > 0 else -1.0)
    nu, nv = -dv / chord, du / chord
    return (start[0] + du / 2.0 + sign * h * nu, start[1] + dv / 2.0 + sign * h * nv)


def arc_radius_mismatch(
    start: Vec2, end: Vec2, centre: Vec2, tol: float
) -> tuple[float, float] | None:
    """(start radius, end radius) when they differ by more than ``tol`` (mm), else None."""
    rs = math.hypot(start[0] - centre[0], start[1] - centre[1])
    re_ = math.hypot(end[0] - centre[0], end[1] - centre[1])
    if abs(rs - re_) > tol:
        return rs, re_
    return None


