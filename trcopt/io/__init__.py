"""Output writers: plan JSON, tool-centre G-code, SVG preview, interactive HTML preview, DXF
(optional ``trcopt[dxf]``), the feed profile CSV; pictures (paths, speed profile) in :mod:`trcopt.io.plot`.

Importing this package stays cheap: each writer loads on first use (its name is looked up here),
ezdxf and matplotlib inside the functions that need them.
"""

from __future__ import annotations

from trcopt.lazy import lazy_exports

# each writer loads on first use: planning to JSON needs neither the SVG writer (and the XML and
# HTTP modules of the standard library behind its escaping) nor the HTML preview
_LAZY = {
    "OutputError": "trcopt.io.atomic",
    "write_bytes_atomic": "trcopt.io.atomic",
    "write_text_atomic": "trcopt.io.atomic",
    "write_dxf": "trcopt.io.dxf",
    "render_feed_csv": "trcopt.io.feed_csv",
    "write_feed_csv": "trcopt.io.feed_csv",
    "GcodeError": "trcopt.io.gcode",
    "check_gcode_arcs": "trcopt.io.gcode",
    "toolpath_to_gcode": "trcopt.io.gcode",
    "render_html": "trcopt.io.html_preview",
    "write_html": "trcopt.io.html_preview",
    "PLAN_SCHEMA": "trcopt.io.plan_json",
    "PlanJsonError": "trcopt.io.plan_json",
    "dumps_plan": "trcopt.io.plan_json",
    "plan_json": "trcopt.io.plan_json",
    "write_plan_json": "trcopt.io.plan_json",
    "render_svg": "trcopt.io.svg",
}

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

__getattr__, __dir__ = lazy_exports(__name__, _LAZY)
