"""Heidenhain TNC conversational (Klartext): reader with contour elements, APPR/DEP and a TOML tool
table, the shared TRC engine under the Heidenhain profile (with the M120 LA look-ahead limit of
:mod:`~trcopt.controllers.heidenhain.m120`), and block-numbered G-code."""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING

from trcopt.controllers.base import Controller, deferred
from trcopt.io.gcode import GcodeFlavor

if TYPE_CHECKING:
    from trcopt.compensation.profiles import ControllerProfile
    from trcopt.config import TrcSettings
    from trcopt.errors import Diagnostic
    from trcopt.nc.model import Move
    from trcopt.path import Segment

__all__ = ["CONTROLLER", "HEIDENHAIN"]

_BEGIN_PGM = re.compile(r"^\s*\d*\s*BEGIN\s+PGM\b", re.I | re.M)


# the reader and the compensation are imported when a Heidenhain program is planned, not when the
# registry is (a program of another controller never loads them)


def __getattr__(name: str) -> ControllerProfile:
    if name == "HEIDENHAIN":
        from trcopt.controllers.heidenhain.profile import HEIDENHAIN

        return HEIDENHAIN
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _compensate(
    moves: Iterable[Move], settings: TrcSettings, diagnostics: list[Diagnostic], complete: bool = True
) -> Iterator[Segment]:
    from trcopt.controllers.heidenhain.m120 import compensate_heidenhain
    from trcopt.controllers.heidenhain.profile import HEIDENHAIN

    return compensate_heidenhain(moves, HEIDENHAIN, settings, diagnostics, complete=complete)


CONTROLLER = Controller(
    name="heidenhain",
    dialect="heidenhain",
    title="Heidenhain TNC (Klartext)",
    extensions=(".h",),
    read=deferred("trcopt.controllers.heidenhain.reader", "read_klartext"),
    compensate=_compensate,
    # plain tool-centre output for ISO-programmable TNCs: the SINUMERIK-style ISO subset
    gcode=GcodeFlavor(
        name="heidenhain",
        paren_comments=False,
        block_numbers=True,
        decimal_point=False,
        preamble=("G71", "G90", "G94", "G40"),
        end="M30",
    ),
    recognise=lambda text: _BEGIN_PGM.search(text) is not None,
    stream=deferred("trcopt.controllers.heidenhain.reader", "stream_klartext"),
)
