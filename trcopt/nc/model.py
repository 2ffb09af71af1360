"""The canonical move: the dialect-neutral output of the NC front end.

From here on nothing is dialect-specific. Coordinates are absolute workpiece coordinates in mm,
feeds in mm/s (``None`` = rapid traverse). Every move carries the modal snapshot compensation
needs and its source span.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from ..errors import Diagnostic, SourceSpan
from ..geometry.plane import Plane

Vec3 = tuple[float, float, float]

__all__ = [
    "MoveKind",
    "Side",
    "CornerMode",
    "ApproachMode",
    "CollisionMode",
    "ApproachStrategy",
    "SarContour",
    "SarSide",
    "SarSegmentation",
    "SarSpec",
    "CompState",
    "Move",
    "NcProgram",
    "parse_enum",
]


def parse_enum(cls: type[enum.Enum], value: object) -> enum.Enum:
    """Accept an enum member, its name or its value (case-insensitive); reject with the options."""
    if isinstance(value, cls):
        return value
    text = str(value).strip()
    for member in cls:
        if text.upper() in (member.name.upper(), str(member.value).upper()):
            return member
    options = ", ".join(str(m.value) for m in cls)
    raise ValueError(f"invalid {cls.__name__} {value!r}; valid: {options}")


class MoveKind(enum.Enum):
    RAPID = "rapid"  # G0
    LINE = "line"  # G1
    ARC = "arc"  # G2/G3 (helix when the applicate changes)
    NONE = "none"  # a block without axis motion (M functions, tool data, ...)


class Side(enum.Enum):
    """Compensation side: OFF = G40/R0, LEFT = G41/RL (tool left of travel), RIGHT = G42/RR."""

    OFF = "off"
    LEFT = "left"
    RIGHT = "right"

    @property
    def sign(self) -> int:
        return _SIDE_SIGN[self.value]


_SIDE_SIGN = {"off": 0, "left": 1, "right": -1}


class CornerMode(enum.Enum):
    TRANSITION_CIRCLE = "G450"
    INTERSECTION = "G451"


class ApproachMode(enum.Enum):
    NORM = "NORM"
    KONT = "KONT"
    KONTT = "KONTT"
    KONTC = "KONTC"


class CollisionMode(enum.Enum):
    CDOF = "CDOF"
    CDON = "CDON"
    CDOF2 = "CDOF2"


class ApproachStrategy(enum.Enum):
    G460 = "G460"
    G461 = "G461"
    G462 = "G462"


class SarContour(enum.Enum):
    G147 = "G147"  # approach, straight line
    G148 = "G148"  # retract, straight line
    G247 = "G247"  # approach, quadrant
    G248 = "G248"  # retract, quadrant
    G347 = "G347"  # approach, semicircle
    G348 = "G348"  # retract, semicircle

    @property
    def is_approach(self) -> bool:
        return self.value.endswith("7")


class SarSide(enum.Enum):
    G140 = "G140"
    G141 = "G141"
    G142 = "G142"
    G143 = "G143"


class SarSegmentation(enum.Enum):
    G340 = "G340"
    G341 = "G341"


@dataclass(frozen=True, slots=True)
class SarSpec:
    """Smooth approach/retraction words of one block (non-modal ones plus the modal side/segmentation).

    ``discl``/``disrp`` are ``(value, absolute)``; ``fad`` is ``(value_mm_s, mode)`` with mode
    ``"PM"``, ``"PR"`` or ``""`` (active feed type).
    """

    contour: SarContour
    side: SarSide = SarSide.G140
    segmentation: SarSegmentation = SarSegmentation.G340
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
