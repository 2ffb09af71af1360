"""LinuxCNC (RS274NGC): reader with a ``.tbl`` tool table, LinuxCNC's own compensation rules
(neighbour-only, its error messages), and parenthesised-comment G-code."""

from __future__ import annotations

import re

from trcopt.controllers.base import Controller, deferred
from trcopt.controllers.linuxcnc.corners import TOLERANCE_CONCAVE_CORNER
from trcopt.io.gcode import GcodeFlavor

__all__ = ["CONTROLLER", "GCODE"]

# an RS274 comment: "(" at line start, after blank or after a number (SINUMERIK writes AC(..),
# MSG(..), X=(..): always after a letter, '=' or an operator)
_PAREN_COMMENT = re.compile(r"(?:^|[\s0-9.])\([^)\n]*\)", re.M)
_STRING = re.compile(r'"[^"\n]*"')
_SEMICOLON_COMMENT = re.compile(r";[^\n]*")


def _recognise(text: str) -> bool:
    """Parenthesised comments outside strings and ``;`` comments (``MSG("(…)")`` says nothing)."""
    code = _SEMICOLON_COMMENT.sub("", _STRING.sub('""', text))
    return _PAREN_COMMENT.search(code) is not None


GCODE = GcodeFlavor(
    name="linuxcnc",
    paren_comments=True,
    block_numbers=False,
    decimal_point=True,
    preamble=("G21", "G90", "G94", "G91.1", "G40"),
    end="M2",
    # path blending within the contour tolerance (P): no stop between tangent arcs and lines
    continuous_path=("G64 P{tol} Q0",),
)

CONTROLLER = Controller(
    name="linuxcnc",
    dialect="rs274",
    title="LinuxCNC (RS274NGC)",
    extensions=(".ngc",),
    # loaded with the first LinuxCNC program (a program of another controller never loads them)
    read=deferred("trcopt.controllers.linuxcnc.reader", "read_ngc"),
    compensate=deferred("trcopt.controllers.linuxcnc.compensation", "compensate_linuxcnc"),
    gcode=GCODE,
    recognise=_recognise,
    near_tangent_rad=TOLERANCE_CONCAVE_CORNER,
    stream=deferred("trcopt.controllers.linuxcnc.reader", "stream_ngc"),
    verified_path=deferred("trcopt.controllers.linuxcnc.lathe", "nose_centres"),
)
