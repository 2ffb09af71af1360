"""SINUMERIK 840D sl: reader (words, tool data ``$TC_DP``, toolholder ``$TC_CARR``), smooth approach
and retraction (SAR, G147…G348) as a pass before compensation, the shared TRC engine with its
SINUMERIK rules, and ``;``-commented, block-numbered G-code."""

from __future__ import annotations

from trcopt.controllers.base import Controller, deferred
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
    # loaded with the first SINUMERIK program (a program of another controller never loads them)
    read=deferred("trcopt.controllers.siemens.reader", "read_siemens"),
    compensate=deferred("trcopt.compensation.engine", "compensate"),
    gcode=GCODE,
    leads=deferred("trcopt.controllers.siemens.sar", "expand_sar"),
    stream=deferred("trcopt.controllers.siemens.reader", "stream_siemens"),
)
