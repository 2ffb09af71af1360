"""Output writers: plan JSON, tool-centre G-code, SVG preview, interactive HTML preview, DXF
(optional ``trcopt[dxf]``), the feed profile CSV; pictures (paths, speed profile) in :mod:`trcopt.io.plot`.

Importing this package stays cheap: ezdxf and matplotlib load inside the functions that need them.
"""

from __future__ import annotations

from trcopt.io.atomic import OutputError, write_bytes_atomic, write_text_atomic
from trcopt.io.dxf import write_dxf
from trcopt.io.feed_csv import render_feed_csv, write_feed_csv
from trcopt.io.gcode import GcodeError, check_gcode_arcs, toolpath_to_gcode
from trcopt.io.html_preview import render_html, write_html
from trcopt.io.plan_json import PLAN_SCHEMA, PlanJsonError, dumps_plan, plan_json, write_plan_json
from trcopt.io.svg import render_svg

__all__ = [
    "GcodeError",
    "OutputError",
    "PLAN_SCHEMA",
    "PlanJsonError",
    "check_gcode_arcs",
    "dumps_plan",
    "plan_json",
    "render_feed_csv",
    "render_html",
    "render_svg",
    "toolpath_to_gcode",
    "write_bytes_atomic",
    "write_dxf",
    "write_feed_csv",
    "write_html",
    "write_plan_json",
    "write_text_atomic",
]
