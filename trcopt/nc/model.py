"""The canonical move: the dialect-neutral output of the NC front end.

From here on nothing is dialect-specific. Coordinates are absolute workpiece coordinates in mm,
feeds in mm/s (``None`` = rapid traverse). Every move carries the modal snapshot compensation
needs and its source span.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import Any

from trcopt.errors import Diagnostic, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3
from trcopt.modes import (
    ApproachMode,
    ApproachStrategy,
    CollisionMode,
    CornerMode,
    LeadSegmentation,
    LeadSide,
    PathMode,
    SarContour,
    Side,
    ToleranceKind,
)

__all__ = ["MoveKind", "SarSpec", "CompState", "PathControl", "EXACT_PATH", "Move", "new_move", "NcProgram"]


class MoveKind(enum.Enum):
    RAPID = "rapid"  # G0
    LINE = "line"  # G1
    ARC = "arc"  # G2/G3 (helix when the applicate changes)
    NONE = "none"  # a block without axis motion (M functions, tool data, ...)


@dataclass(frozen=True, slots=True)
class SarSpec:
    """Smooth approach/retraction words of one block (non-modal ones plus the modal side/segmentation).

    ``discl``/``disrp`` are ``(value, absolute)``; ``fad`` is ``(value_mm_s, mode)`` with mode
    ``"PM"``, ``"PR"`` or ``""`` (active feed type).
    """

    contour: SarContour
    side: LeadSide = LeadSide.FROM_COMPENSATION
    segmentation: LeadSegmentation = LeadSegmentation.SPATIAL
    disr: float | None = None
    discl: tuple[float, bool] | None = None
    disrp: tuple[float, bool] | None = None
    fad: tuple[float, str] | None = None
    end_programmed: tuple[bool, bool, bool] = (False, False, False)  # X, Y, Z written in the block


@dataclass(frozen=True, slots=True)
class CompState:
    """Modal compensation state in force for a block (the snapshot TRC needs).

    ``radius`` is the effective compensation value R = $TC_DP6 + $TC_DP15 + OFFN (mm, signed; a
    negative value swaps the side). ``tool_active`` is False when no tool/edge is selected (T/D
    missing); D0 gives ``tool_active=True`` with radius 0.
    """

    side: Side = Side.OFF
    radius: float = 0.0
    tool_active: bool = False
    corner: CornerMode = CornerMode.TRANSITION_CIRCLE
    disc: int = 0
    approach: ApproachMode = ApproachMode.NORM
    collision: CollisionMode = CollisionMode.CDOF
    strategy: ApproachStrategy = ApproachStrategy.G460
    side_programmed: bool = False  # G40/G41/G42 written in this very block
    inch: bool = False  # the program's length unit is inch here (LinuxCNC's unit-dependent tolerances)
    # LinuxCNC lathe tool orientation 1–8 (G18): the moves are of the imaginary tool tip, the
    # compensated nose centre is shifted by the radius towards it (0, 9: the centre itself)
    orientation: int = 0

    @property
    def effective_side(self) -> Side:
        """Side after the sign normalisation: a negative radius swaps G41 and G42."""
        if self.side is Side.OFF or self.radius >= 0.0:
            return self.side
        return Side.RIGHT if self.side is Side.LEFT else Side.LEFT

    @property
    def effective_radius(self) -> float:
        return abs(self.radius)


@dataclass(frozen=True, slots=True)
class PathControl:
    """The path-control mode in force at the end of a block (what the controller does at the
    corner between this block and the next).

    Attributes
    ----------
    mode:
        Exact path (stop at tangent discontinuities), exact stop (stop at the block end), or blend.
    tolerance_mm:
        Blend: the bound of the rounding, mm, measured as ``kind`` says; None for no bound (the
        largest blend the neighbouring blocks allow: LinuxCNC ``G64`` without ``P``).
    kind:
        How ``tolerance_mm`` is measured.
    word:
        The program's words that set the mode, as written (``"G64 P0.01"``, ``"G642 CTOL=0.01"``).
    length_share:
        The tolerance is at most this share of the shorter of the two moves at the corner
        (LinuxCNC: a quarter); None for no such bound.
    merge_mm:
        Consecutive straight feed moves whose points all lie within this distance of one line are
        merged into that line before blending (LinuxCNC's naive-CAM detector, ``G64 Q``).
    """

    mode: PathMode = PathMode.EXACT_PATH
    tolerance_mm: float | None = None
    kind: ToleranceKind = ToleranceKind.CONTOUR
    word: str = ""
    length_share: float | None = None
    merge_mm: float | None = None

    @property
    def blends(self) -> bool:
        return self.mode is PathMode.BLEND


EXACT_PATH = PathControl()  # no mode programmed: stop at tangent discontinuities (the default)


@dataclass(frozen=True, slots=True)
class Move:
    """One block's motion (or a block without motion, kind NONE), in absolute workpiece mm.

    ``center`` (arcs) lies at the start's applicate; ``ccw`` is the sense seen from +applicate in
    the plane frame (G3 = True); ``turns`` counts extra full turns. ``feed_mm_s`` is None for a
    rapid. ``actions`` lists the block's other content (``"M3"``, ``"F600"``, ``"T1"``, ...),
    executed where the block's plane motion would start (or at the intersection when omitted).
    """

    kind: MoveKind
    start: Vec3
    end: Vec3
    plane: Plane
    span: SourceSpan
    comp: CompState = field(default_factory=CompState)
    feed_mm_s: float | None = None
    center: Vec3 | None = None
    ccw: bool | None = None
    turns: int = 0
    actions: tuple[str, ...] = ()
    sar: SarSpec | None = None
    plane_programmed: bool = True  # the block wrote at least one plane axis (R3.4, R45)
    origin: str = ""  # "approach"/"retract" for generated lead sub-moves (SAR, APPR/DEP); "" otherwise
    control: PathControl = EXACT_PATH  # path-control mode in force at the end of the block

    def moves_in_plane(self, tol: float) -> bool:
        """Whether the block travels in its working plane: every arc, and a line or rapid whose
        plane projection is longer than ``tol`` (mm); never a block without motion."""
        kind = self.kind
        if kind is MoveKind.NONE:
            return False
        if kind is MoveKind.ARC:
            return True
        iu, iv, _ = self.plane.axes
        a, b = self.start, self.end
        return math.hypot(b[iu] - a[iu], b[iv] - a[iv]) > tol


class _MoveSlots:
    """The slots of :class:`Move` (the same layout) without its frozen ``__setattr__``."""

    __slots__ = Move.__slots__


def new_move(
    kind: MoveKind,
    start: Vec3,
    end: Vec3,
    plane: Plane,
    span: SourceSpan,
    comp: CompState,
    feed_mm_s: float | None = None,
    center: Vec3 | None = None,
    ccw: bool | None = None,
    turns: int = 0,
    actions: tuple[str, ...] = (),
    sar: SarSpec | None = None,
    plane_programmed: bool = True,
    origin: str = "",
    control: PathControl = EXACT_PATH,
) -> Move:
    """``Move(...)`` (the same arguments, an equal move) at a third of the cost, for a reader's
    loop over the blocks: the fields are set on a :class:`_MoveSlots`, which then becomes a
    :class:`Move` (the dataclass constructor sets each field through ``object.__setattr__``)."""
    m: Any = _MoveSlots()
    m.kind, m.start, m.end, m.plane, m.span, m.comp, m.feed_mm_s = kind, start, end, plane, span, comp, feed_mm_s
    m.center, m.ccw, m.turns, m.actions, m.sar = center, ccw, turns, actions, sar
    m.plane_programmed, m.origin, m.control = plane_programmed, origin, control
    m.__class__ = Move
    return m


@dataclass(frozen=True, slots=True)
class NcProgram:
    """An interpreted program: moves in program order plus front-end diagnostics.

    When an error-severity diagnostic is present the moves stop before the offending block.
    """

    file: str
    dialect: str
    moves: tuple[Move, ...]
    diagnostics: tuple[Diagnostic, ...] = ()
    blocks: int = 0
    extras: dict[str, object] = field(default_factory=dict)
