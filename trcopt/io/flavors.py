"""Output-only G-code flavours: controllers trcopt writes for but does not read."""

from __future__ import annotations

from trcopt.io.gcode import GcodeFlavor

__all__ = ["GRBL", "OUTPUT_FLAVORS"]

#: plain ISO G-code for grbl-style controllers (grbl 1.1 and compatible hobby controllers): no
#: block numbers, parenthesised comments, incremental arc centres (grbl's only mode, so no G91.1),
#: no path-control words (grbl has no G64), no tool changer (grbl rejects M6: a tool change is
#: ``M5 M0``, spindle and program stop, with a comment naming the tool), the spindle, coolant and
#: program stop/end M functions, S and the work offsets G54–G59 kept
GRBL = GcodeFlavor(
    name="grbl",
    paren_comments=True,
    block_numbers=False,
    decimal_point=True,
    preamble=("G21", "G90", "G94", "G40"),
    end="M2",
    portable_words=r"^(M0*[0-5789]|M30|S\d+(\.\d*)?|G5[4-9])$",
    manual_tool_change="M5 M0",
)

#: output-only flavours (no controller reads them), by name
OUTPUT_FLAVORS = {GRBL.name: GRBL}
