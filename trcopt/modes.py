"""Every mode of the project in one place, and the one parser that turns strings into modes.

Modes are enums; strings are accepted only at the boundary (command line, TOML, public keyword
arguments) through :func:`parse_enum`, which rejects an unknown value listing the valid options.

Conventions: positive offset = left of travel = G41 = RL (``Side.LEFT``).
"""

from __future__ import annotations

import enum
from typing import TypeVar

__all__ = [
    "parse_enum",
    "Side",
    "CornerMode",
    "ApproachMode",
    "CollisionMode",
    "ApproachStrategy",
    "SarContour",
    "LeadShape",
    "LeadSide",
    "LeadSegmentation",
    "RetractEnd",
    "TransitionKind",
    "ToolUnit",
    "CornerObjective",
    "LeadObjective",
    "ToolFamily",
    "WearMode",
    "OrientationWord",
    "ApprRadius",
    "FeedReference",
    "TimingEngine",
    "PathMode",
    "ToleranceKind",
]

E = TypeVar("E", bound=enum.Enum)


def parse_enum(cls: type[E], value: object, what: str | None = None) -> E:
    """The member of ``cls`` named by ``value``: a member, its name or its value (case-insensitive).

    Anything else raises :class:`ValueError` naming ``what`` (default: the enum's name) and listing
    the valid values.
    """
    if isinstance(value, cls):
        return value
    text = str(value).strip().upper()
    for member in cls:
        if text in (member.name.upper(), str(member.value).upper()):
            return member
    options = ", ".join(str(m.value) for m in cls)
    raise ValueError(f"invalid {what or cls.__name__} {value!r}; valid: {options}")


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


class LeadShape(enum.Enum):
    """Shape of the lead contour P3 → P4."""

    LINE = "line"  # G147 / G148
    QUADRANT = "quadrant"  # G247 / G248
    SEMICIRCLE = "semicircle"  # G347 / G348


class LeadSide(enum.Enum):
    """Side the lead circle lies on, relative to the tangent at P4."""

    FROM_COMPENSATION = "G140"  # side of G41/G42; AUTOMATIC when compensation is off
    LEFT = "G141"
    RIGHT = "G142"
    AUTOMATIC = "G143"  # the side of the start (approach) or end (retraction) point


class LeadSegmentation(enum.Enum):
    """How the applicate infeed is split (spec R41)."""

    SPATIAL = "G340"  # infeed to the DISCL level, then a slanted line or a helix to P4
    PLANAR = "G341"  # infeed down to the machining plane, then the contour in the plane


class RetractEnd(enum.Enum):
    """Which coordinates of the retraction end point P0 the block programs (spec R45)."""

    PROGRAMMED = "programmed"  # at least one plane axis: P0 is the block end point
    APPLICATE_ONLY = "applicate"  # only the applicate: the lead ends in P1 (= P0)
    NONE = "none"  # no geometry axis: the lead ends in P2 (= P1 = P0)


class TransitionKind(enum.Enum):
    """The curve that replaced one corner of the tool path (the corner strategies are named in
    :mod:`trcopt.optimize.corners.strategies`, not here)."""

    QUINTIC = "quintic"  # G2 quintic Hermite curve of one corner
    SPLINE = "spline"  # G2 spline across a run of small corners or a curvature jump
    ARC = "arc"  # circular blend (G1)


class PathMode(enum.Enum):
    """What the path does at the end of a block (the program's path-control mode)."""

    EXACT_PATH = "exact_path"  # stop at every tangent discontinuity (LinuxCNC G61; no mode programmed)
    EXACT_STOP = "exact_stop"  # stop at every block end, tangent or not (G61.1, G60, G9)
    BLEND = "blend"  # round the corner within a tolerance (G64 P, G641, G642, G645, CYCL DEF 32)


class ToleranceKind(enum.Enum):
    """How a corner tolerance is measured."""

    CONTOUR = "contour"  # largest distance of the new path from the programmed path (Hausdorff)
    VERTEX = "vertex"  # distance of the transition from the programmed corner point
    DISTANCE = "distance"  # the transition starts and ends this far from the corner (SINUMERIK ADIS)


class ToolUnit(enum.Enum):
    """Length unit of a tool-table file (``program``: the unit the program sets with G20/G21)."""

    PROGRAM = "program"
    INCH = "inch"
    MM = "mm"

    @property
    def mm(self) -> float:
        """Millimetres per unit (``program``: 1, the values are kept as written until the
        program's unit is known)."""
        return 25.4 if self is ToolUnit.INCH else 1.0


class CornerObjective(enum.Enum):
    """What optimised corner transitions minimise."""

    CURVATURE = "curvature"  # the peak curvature: the speed limit under acceleration limits
    JERK = "jerk"  # the larger of the curvature and the curvature rate scaled by the jerk limit


class LeadObjective(enum.Enum):
    """What an optimal lead-in was ranked by."""

    TIME = "time"  # the traverse time of the timing stage, s
    SURROGATE = "surrogate"  # length + 2·ρmin·∫κ² ds, mm (when the timing stage is unavailable)


class ToolFamily(enum.Enum):
    """Which length-to-axis table applies (spec §3.4): milling/drilling (types 100–299) or
    turning/grinding (types 400–599)."""

    MILLING = "milling"
    TURNING = "turning"


class WearMode(enum.Enum):
    """Group-56 wear handling (spec §3.8): ``TOWSTD`` wear is rotated with the tool length,
    ``TOWMCS`` wear is added unrotated in machine coordinates."""

    TOWSTD = "TOWSTD"
    TOWMCS = "TOWMCS"


class OrientationWord(enum.Enum):
    """Modal G group 42: where the holder angles come from."""

    TCOABS = "TCOABS"
    TCOFR = "TCOFR"
    TCOFRZ = "TCOFRZ"
    TCOFRY = "TCOFRY"
    TCOFRX = "TCOFRX"

    @property
    def base_axis(self) -> int:
        """Index (x=0, y=1, z=2) of the tool axis that TCOFRx aligns with the same frame axis
        (spec R6); TCOFR = TCOFRZ."""
        return {"TCOFRX": 0, "TCOFRY": 1}.get(self.value, 2)


class ApprRadius(enum.Enum):
    """Heidenhain APPR/DEP CT and LCT: what the programmed radius R measures (spec R9)."""

    CONTOUR = "contour"  # the contour-level arc radius (the tool centre runs on R + r)
    CENTRE = "centre"  # the tool-centre arc radius (the reading of the manual's example programs)


class FeedReference(enum.Enum):
    """Where the programmed feed holds (machine file ``feed_reference``)."""

    CENTRE = "centre"  # on the tool centre (CFTCP), the default
    CONTOUR = "contour"  # on the contour (CFC-like): compensated arcs are scaled


class TimingEngine(enum.Enum):
    """Which solver times a section of the acceleration-limited feed."""

    AUTO = "auto"  # the own reachability solver on lines and arcs, toppra on polynomial sections
    OWN = "own"  # the own solver everywhere it applies
    TOPPRA = "toppra"  # toppra on every section
