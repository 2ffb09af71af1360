"""Controller profiles: how a dialect's compensation semantics map onto the shared engine.

The engine (:mod:`.engine`) implements the SINUMERIK rules. A profile says, as data, which of its
modes a controller uses and how the engine's alarms read in that controller's words; the front end
of the dialect sets the per-move modes (``CompState``) accordingly.

Heidenhain Klartext (spec ``heidenhain_trc.md``):

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
"Tool radius too large"   engine alarms 10751, 10758, 10763 and the CDOF contour-violation
                          warning all mean the offset path cannot exist → ``E_TOOL_RADIUS_TOO_LARGE``
R+ / R−                   not TRC: the front end lengthens/shortens the paraxial move itself
APPR / DEP                lead geometry from :mod:`trcopt.sar.heidenhain`; the front end hands the
                          engine contour-level lead arcs and tool-centre lead lines (``origin``)
========================  ===================================================================

The Heidenhain front end also checks "tool radius too large" on the contour itself, so a program
stops at that block whatever settings the pipeline passes. :func:`compensate_with_profile` is the
profile-aware entry point for callers that know the dialect (see the module's ``profile_for``).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

from ..config import TrcSettings
from ..errors import Diagnostic, Severity
from ..nc.model import ApproachMode, CollisionMode, CornerMode, Move
from ..path import Segment
from .engine import compensate

__all__ = [
    "ControllerProfile",
    "SIEMENS",
    "HEIDENHAIN",
    "PROFILES",
    "profile_for",
    "map_diagnostic",
    "compensate_with_profile",
    "TOOL_RADIUS_TOO_LARGE",
]

TOOL_RADIUS_TOO_LARGE = "Tool radius too large"


@dataclass(frozen=True, slots=True)
class ControllerProfile:
    """How one controller's compensation maps onto the engine.

    Parameters
    ----------
    name:
        Dialect name.
    outside_corner, m97_corner:
        Corner mode of an ordinary outside corner and of one whose block carries M97.
    approach, collision:
        Approach mode of the selection block and collision mode in force.
    settings:
        Engine settings overridden by the profile (``TrcSettings`` field → value).
    alarms:
        Engine alarm number or code → (controller code, message, severity) for the controller.
    appr_radius:
        APPR/DEP CT/LCT radius reading (Heidenhain spec R9): ``"contour"`` or ``"centre"``.
    """

    name: str
    outside_corner: CornerMode = CornerMode.TRANSITION_CIRCLE
    m97_corner: CornerMode | None = None
    approach: ApproachMode = ApproachMode.NORM
    collision: CollisionMode = CollisionMode.CDOF
    settings: Mapping[str, object] = field(default_factory=dict)
    alarms: Mapping[str, tuple[str, str, Severity]] = field(default_factory=dict)
    appr_radius: str = "contour"

    def engine_settings(self, base: TrcSettings | None = None) -> TrcSettings:
        """``base`` (default settings when omitted) with the profile's overrides."""
        return replace(base or TrcSettings(), **dict(self.settings))


_TOO_LARGE = ("E_TOOL_RADIUS_TOO_LARGE", TOOL_RADIUS_TOO_LARGE, Severity.ERROR)

SIEMENS = ControllerProfile("siemens")
HEIDENHAIN = ControllerProfile(
    "heidenhain",
    m97_corner=CornerMode.INTERSECTION,
    settings=MappingProxyType(
        {"cutcom_curve_insert_limit_deg": 0.0, "cutcom_corner_limit_deg": 180.0, "strict": True}
    ),
    alarms=MappingProxyType(
        {
            "10751": _TOO_LARGE,
            "10758": _TOO_LARGE,
            "10763": _TOO_LARGE,
            "TRC-CONTOUR-VIOLATION": _TOO_LARGE,
            "TRC-SIDE-CHANGE": (
                "E_TRC_SIDE_SWITCH",
                "RL↔RR changed without an R0 block",
                Severity.ERROR,
            ),
            "10753": (
                "E_TRC_IN_CIRCLE",
                "radius compensation switched on in a circle block",
                Severity.ERROR,
            ),
            "10754": (
                "E_TRC_IN_CIRCLE",
                "radius compensation switched off in a circle block",
                Severity.ERROR,
            ),
        }
    ),
)
PROFILES: Mapping[str, ControllerProfile] = MappingProxyType(
    {"siemens": SIEMENS, "heidenhain": HEIDENHAIN}
)


def profile_for(dialect: str) -> ControllerProfile:
    """The profile of a dialect (``siemens``, ``heidenhain``); unknown names are rejected."""
    try:
        return PROFILES[dialect]
    except KeyError:
        raise ValueError(
            f"no compensation profile for {dialect!r}; valid: {', '.join(PROFILES)}"
        ) from None


def map_diagnostic(profile: ControllerProfile, diag: Diagnostic) -> Diagnostic:
    """An engine diagnostic in the controller's words (unchanged when the profile has no entry)."""
    key = str(diag.alarm) if diag.alarm is not None else diag.code
    entry = profile.alarms.get(key)
    if entry is None:
        return diag
    code, message, severity = entry
    return Diagnostic(severity, code, f"{message} (engine {key}: {diag.message})", diag.span, None)


def compensate_with_profile(
    moves: Iterable[Move],
    profile: ControllerProfile,
    settings: TrcSettings | None = None,
    diagnostics: list[Diagnostic] | None = None,
    complete: bool = True,
) -> Iterator[Segment]:
    """:func:`~.engine.compensate` with the profile's settings; diagnostics mapped by the profile.

    A warning the profile maps to an error (Heidenhain: a contour violation) stops the stream.
    """
    out = diagnostics if diagnostics is not None else []
    raw: list[Diagnostic] = []
    for seg in compensate(moves, profile.engine_settings(settings), raw, complete=complete):
        while raw:
            mapped = map_diagnostic(profile, raw.pop(0))
            out.append(mapped)
            if mapped.severity is Severity.ERROR:
                return
        yield seg
    out.extend(map_diagnostic(profile, d) for d in raw)
