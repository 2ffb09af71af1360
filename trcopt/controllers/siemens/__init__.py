"""SINUMERIK 840D sl: reader (words, tool data ``$TC_DP``, toolholder ``$TC_CARR``), smooth approach
and retraction (SAR, G147…G348) as a pass before compensation, the shared TRC engine with its
SINUMERIK rules, and ``;``-commented, block-numbered G-code."""

from __future__ import annotations

from trcopt.compensation.engine import compensate
from trcopt.controllers.base import Controller
from trcopt.controllers.siemens.reader import read_siemens, stream_siemens
from trcopt.controllers.siemens.sar import expand_sar
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

CONTROLLER = Controller(
    name="siemens",
    dialect="siemens",
    title="SINUMERIK 840D sl",
    extensions=(".mpf", ".spf"),
    read=read_siemens,
    compensate=compensate,
    gcode=GCODE,
    leads=expand_sar,
    stream=stream_siemens,
)
