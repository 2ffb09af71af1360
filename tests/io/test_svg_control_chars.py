"""The SVG stays well-formed XML when a title or diagnostic quotes characters XML forbids (a
control byte from a damaged program, found by the fuzz run)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.io.svg import render_svg
from trcopt.pipeline import PlanOptions, plan


def test_control_characters_become_replacement_characters() -> None:
    r = plan("N10 G1 X10 Y0 F100\nN20 X20\nM30\n", file="p.mpf", options=PlanOptions(timing=False))
    bad = Diagnostic(Severity.ERROR, Code.NC_SYNTAX, "got [1\x17,1] \x00\x1b", SourceSpan("p.mpf", 2, 1, "N20"))
    text = render_svg(r.programmed, r.toolpath, [*r.diagnostics, bad], title="prog\x01.mpf")
    ET.fromstring(text)  # well-formed
    assert "\ufffd" in text and "\x17" not in text and "\x01" not in text
