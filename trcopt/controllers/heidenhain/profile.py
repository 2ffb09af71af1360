"""The Heidenhain TNC compensation profile: Klartext semantics over the shared engine.

========================  ===================================================================
Klartext                  engine
========================  ===================================================================
RL / RR / R0              ``Side.LEFT`` / ``Side.RIGHT`` / ``Side.OFF``; r = R + DR_TAB + DR_CALL
switch on (L/LP RL)       selection block, ``ApproachMode.NORM`` (ends perpendicular to the
                          next element, spec R3)
switch off (L R0, DEP)    deselection block (starts perpendicular to the last element)
outside corner            ``CornerMode.TRANSITION_CIRCLE`` at every deflection (no curve-insert
                          limit: ``cutcom_curve_insert_limit_deg = 0``)
M97                       ``CornerMode.INTERSECTION`` on the block after the M97 block (the engine
                          takes the corner mode from the block that starts at the corner), at any
                          deflection (``cutcom_corner_limit_deg = 180``)
inside corner             intersection (engine default)
collision checking        ``CollisionMode.CDOF``; no block omission: a bottleneck is an error
M120 LA n                 ``CollisionMode.CDON`` with the search limit LA instead of MD20240
                          (:mod:`.m120`): pieces the tool would damage are not machined; the
                          omission of a block under M120 is warning 10763, not an error
"Tool radius too large"   engine alarms 10751, 10758, 10763 and the CDOF contour-violation
                          warning all mean the offset path cannot exist → ``HH-TOOL-RADIUS-TOO-LARGE``
R+ / R−                   not TRC: the front end lengthens/shortens the paraxial move itself
APPR / DEP                lead geometry from ``appr_dep``; the front end hands the
                          engine contour-level lead arcs and tool-centre lead lines (``origin``)
========================  ===================================================================

The reader also checks "tool radius too large" on the contour itself, so a program stops at that
block whatever settings the pipeline passes.
"""

from __future__ import annotations

from types import MappingProxyType

from trcopt.codes import Code
from trcopt.compensation.profiles import ControllerProfile
from trcopt.controllers.heidenhain.contour import TOOL_RADIUS_TOO_LARGE
from trcopt.errors import Severity

__all__ = ["HEIDENHAIN"]

_E = Severity.ERROR
_TOO_LARGE = (Code.HH_TOOL_RADIUS_TOO_LARGE, TOOL_RADIUS_TOO_LARGE, Severity.ERROR)

HEIDENHAIN = ControllerProfile(
    "heidenhain",
    settings=MappingProxyType(
        {"cutcom_curve_insert_limit_deg": 0.0, "cutcom_corner_limit_deg": 180.0, "strict": True}
    ),
    alarms=MappingProxyType(
        {
            Code.ALARM_10751: _TOO_LARGE,
            Code.ALARM_10758: _TOO_LARGE,
            Code.ALARM_10763: _TOO_LARGE,
            Code.TRC_CONTOUR_VIOLATION: _TOO_LARGE,
            Code.TRC_SIDE_CHANGE: (Code.HH_TRC_SIDE_SWITCH, "RL↔RR changed without an R0 block", Severity.ERROR),
            Code.ALARM_10753: (Code.HH_TRC_IN_CIRCLE, "radius compensation switched on in a circle block", _E),
            Code.ALARM_10754: (Code.HH_TRC_IN_CIRCLE, "radius compensation switched off in a circle block", _E),
        }
    ),
)
