"""Controller profiles: a controller's compensation semantics as data over the shared engine.

The engine (:mod:`trcopt.compensation.engine`) implements the SINUMERIK rules. A
:class:`ControllerProfile` overrides some of its settings and says how the engine's alarms read in
the controller's words; the controller's reader sets the per-move modes (``CompState``) itself.
:func:`compensate_with_profile` runs the engine under a profile. Each controller that uses one
defines it in its own folder (``trcopt.controllers.heidenhain.profile``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.compensation.engine import compensate
from trcopt.config import TrcSettings
from trcopt.errors import Diagnostic, Severity
from trcopt.nc.model import Move
from trcopt.path import Segment

__all__ = ["ControllerProfile", "map_diagnostic", "mapped_stream", "compensate_with_profile"]


@dataclass(frozen=True, slots=True)
class ControllerProfile:
    """How one controller's compensation maps onto the engine.

    Parameters
    ----------
    name:
        Controller name.
    settings:
        Engine settings overridden by the profile (``TrcSettings`` field → value).
    alarms:
        Engine alarm number or code → (controller code, message, severity) for the controller.
    """

    name: str
    settings: Mapping[str, object] = field(default_factory=dict)
    alarms: Mapping[str, tuple[Code, str, Severity]] = field(default_factory=dict)

    def engine_settings(self, base: TrcSettings | None = None) -> TrcSettings:
        """``base`` (default settings when omitted) with the profile's overrides."""
        return (base or TrcSettings()).with_(**self.settings)


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
    engine = compensate(moves, profile.engine_settings(settings), raw, complete=complete)
    yield from mapped_stream(engine, raw, out, lambda d: map_diagnostic(profile, d))


def mapped_stream(
    segments: Iterable[Segment],
    raw: list[Diagnostic],
    out: list[Diagnostic],
    mapper: Callable[[Diagnostic], Diagnostic],
) -> Iterator[Segment]:
    """``segments`` (an engine's stream) while the diagnostics the engine appends to ``raw`` move
    to ``out`` through ``mapper``, in order; the stream stops at the first mapped error."""
    for seg in segments:
        while raw:
            mapped = mapper(raw.pop(0))
            out.append(mapped)
            if mapped.severity is Severity.ERROR:
                return
        yield seg
    out.extend(mapper(d) for d in raw)
