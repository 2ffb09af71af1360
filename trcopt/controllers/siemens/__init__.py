"""SINUMERIK 840D sl: reader (words, tool data ``$TC_DP``, toolholder ``$TC_CARR``), smooth approach
and retraction (SAR, G147…G348) as a pass before compensation, the shared TRC engine with its
SINUMERIK rules, and ``;``-commented, block-numbered G-code."""

from __future__ import annotations

from typing import Any

from trcopt.controllers.base import Controller
from trcopt.io.gcode import GcodeFlavor

__all__ = ["CONTROLLER", "GCODE"]

GCODE = GcodeFlavor(
    name="siemens",
    paren_comments=False,
    block_numbers=True,
    decimal_point=False,
    preamble=("G71", "G90", "G94", "G40"),
    end="M30",
    # contour tolerance, then continuous-path mode with smoothing within it
    continuous_path=("CTOL={tol}", "G642"),
)

# the reader, the SAR pass and the compensation are imported when a SINUMERIK program is planned,
# not when the registry is (a program of another controller never loads them)


def _read(*args: Any, **kwargs: Any) -> Any:
    from trcopt.controllers.siemens.reader import read_siemens

    return read_siemens(*args, **kwargs)


def _stream(*args: Any, **kwargs: Any) -> Any:
    from trcopt.controllers.siemens.reader import stream_siemens

    return stream_siemens(*args, **kwargs)


def _leads(*args: Any, **kwargs: Any) -> Any:
    from trcopt.controllers.siemens.sar import expand_sar

    return expand_sar(*args, **kwargs)


def _compensate(*args: Any, **kwargs: Any) -> Any:
    from trcopt.compensation.engine import compensate

    return compensate(*args, **kwargs)


CONTROLLER = Controller(
    name="siemens",
    dialect="siemens",
    title="SINUMERIK 840D sl",
    extensions=(".mpf", ".spf"),
    read=_read,
    compensate=_compensate,
    gcode=GCODE,
    leads=_leads,
    stream=_stream,
)
