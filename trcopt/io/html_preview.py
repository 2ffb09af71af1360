"""Interactive preview of a plan: one self-contained HTML file (``trcopt plan PROG --html F``).

The page needs no network: the script and the style sheet (``html_preview.js``/``.css``, package
data beside this module) are inlined, the plan is embedded as JSON (``<script type=
"application/json" id="plan-data">``, see :func:`preview_data`). It draws the programmed contour,
the tool-centre path (one ``<path class="seg">`` per segment, coloured by the planned speed or by
role; rapids dashed), the tool at the junctions, direction arrows, the start, axes with a mm scale,
in the XY, XZ, YZ or an isometric view, with pan (drag) and zoom (wheel); hovering a segment shows
its block, source line and feed; alarms and omitted blocks are marked and listed with links to
their place; the speed-over-time plot is linked to the path both ways.

numpy is imported inside the functions (only a timed plan needs it), so importing this module
stays cheap.
"""

from __future__ import annotations

import html
import json
import math
import os
from collections.abc import Iterable, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

from trcopt.errors import Diagnostic, Severity
from trcopt.geometry.primitives import Arc, Line
from trcopt.io.atomic import write_text_atomic
from trcopt.io.marks import locate_diagnostics
from trcopt.path import Role, Segment
from trcopt.trajectory import Trajectory
from trcopt.units import mm_s_to_mm_min

__all__ = ["preview_data", "render_html", "write_html", "MAX_TOOL_CIRCLES", "MAX_PLOT_SAMPLES", "PREVIEW_SCHEMA"]

PREVIEW_SCHEMA = "trcopt.preview/1"
MAX_TOOL_CIRCLES = 400
MAX_PLOT_SAMPLES = 2000  # samples of the speed-over-time plot (and of the speed colouring)
MAX_SPEED_POINTS_PER_SEGMENT = 400
ARC_STEP_RAD = math.pi / 36  # the drawn arcs are polylines with a point every 5°
_DIGITS = 4  # 0.1 µm, 0.1 ms


def _r(x: float, digits: int = _DIGITS) -> float | None:
    x = float(x)
    return round(x, digits) + 0.0 if math.isfinite(x) else None


def _xyz(p: Sequence[float]) -> list[float | None]:
    return [_r(c) for c in p]


def _shape_s(seg: Segment) -> list[float]:
    """Arc lengths (from the segment start, mm) of the points that draw the segment."""
    g = seg.geometry
    length = g.length
    if isinstance(g, Line) or length <= 0.0:
        return [0.0, length]
    if isinstance(g, Arc):
        n = max(4, math.ceil(abs(g.sweep) / ARC_STEP_RAD))
        return [length * k / n for k in range(n + 1)]
    return list(g.cum)


def _shape(seg: Segment) -> list[list[float | None]]:
    g = seg.geometry
    if not isinstance(g, (Line, Arc)):
        return [_xyz(seg.plane.to_xyz(p)) for p in g.points]
    return [_xyz(seg.plane.to_xyz(g.point(s))) for s in _shape_s(seg)]


def _seg_json(seg: Segment) -> dict[str, Any]:
    u = seg.plane.to_xyz((1.0, 0.0, 0.0))
    v = seg.plane.to_xyz((0.0, 1.0, 0.0))
    return {
        "p": _shape(seg),
        "role": seg.role.value,
        "rapid": seg.is_rapid or seg.role in (Role.RAPID, Role.POSITIONING),
        "line": seg.span.line,
        "block": seg.span.block,
        "feed": None if seg.feed_mm_s is None else _r(mm_s_to_mm_min(seg.feed_mm_s), 3),
        "r": _r(seg.radius),
        "plane": seg.plane.value,
        "uv": [list(u), list(v)],
    }


def _tools(toolpath: Sequence[Segment]) -> list[dict[str, Any]]:
    """The tool at every junction of the tool path where its radius is > 0 (at most 400)."""
    out: list[dict[str, Any]] = []
    for i, seg in enumerate(toolpath):
        if seg.radius <= 0.0:
            continue
        u, v = seg.plane.to_xyz((1.0, 0.0, 0.0)), seg.plane.to_xyz((0.0, 1.0, 0.0))
        ends = [seg.start_xyz, seg.end_xyz] if i == 0 else [seg.end_xyz]
        out += [{"c": _xyz(p), "r": _r(seg.radius), "u": list(u), "v": list(v), "seg": i} for p in ends]
    if len(out) > MAX_TOOL_CIRCLES:
        step = (len(out) - 1) / (MAX_TOOL_CIRCLES - 1)
        out = [out[round(k * step)] for k in range(MAX_TOOL_CIRCLES)]
    return out


def _timing(trajectory: Trajectory, toolpath: Sequence[Segment]) -> dict[str, Any] | None:
    """Speed plot samples, segment times and the speed along every segment (mm/min)."""
    import numpy as np

    segs = list(trajectory.segments)
    if not segs or len(segs) != len(toolpath) or not trajectory.duration > 0.0:
        return None
    smp = trajectory.sample(max(trajectory.duration / (MAX_PLOT_SAMPLES - 1), 1e-4))
    speed = np.asarray(smp.speed, dtype=float) * 60.0
    s_all = np.asarray(smp.s, dtype=float)
    seg_of = np.asarray(smp.segment, dtype=int)
    feeds = np.asarray(trajectory.feeds, dtype=float) * 60.0
    timed = trajectory.segments_with_times()
    offsets = np.concatenate(([0.0], np.cumsum([s.geometry.length for s in segs])))
    along: list[list[list[float | None]]] = []
    for i, seg in enumerate(segs):
        inside = (s_all - offsets[i])[(seg_of == i)]
        inside = inside[(inside > 0.0) & (inside < seg.geometry.length)]
        if len(inside) > MAX_SPEED_POINTS_PER_SEGMENT:
            inside = inside[:: math.ceil(len(inside) / MAX_SPEED_POINTS_PER_SEGMENT)]
        s_rel = np.unique(np.concatenate((_shape_s(seg), inside)))
        v = np.interp(offsets[i] + s_rel, s_all, speed)
        point = seg.geometry.point
        along.append(
            [[*_xyz(seg.plane.to_xyz(point(float(s)))), _r(float(w), 2)] for s, w in zip(s_rel, v, strict=True)]
        )
    cutting = [float(speed[k]) for k in range(len(speed)) if not segs[int(seg_of[k])].is_rapid]
    return {
        "duration_s": _r(trajectory.duration),
        "jerk_limited": bool(trajectory.jerk_limited),
        "machine": trajectory.machine.name,
        "t": [_r(t) for t in smp.t],
        "v": [_r(w, 2) for w in speed],
        "seg": [int(k) for k in seg_of],
        "feed": [_r(w, 2) for w in feeds[seg_of]],
        "xyz": [_xyz(p) for p in np.asarray(smp.xyz)],
        "t0": [_r(s.t_start_s or 0.0) for s in timed],
        "t1": [_r(s.t_end_s or 0.0) for s in timed],
        "along": along,
        # the colour scale spans the cutting moves: rapids (drawn grey) would squash it
        "vmax": _r(max(cutting) if cutting else float(speed.max(initial=0.0)), 2),
    }


def _diag_json(mark: Any) -> dict[str, Any]:
    d: Diagnostic = mark.diagnostic
    return {
        "severity": d.severity.value,
        "code": str(d.code),
        "alarm": d.alarm,
        "message": d.message,
        "line": d.span.line,
        "block": d.span.block,
        "text": d.format(),
        "kind": mark.kind,
        "path": mark.path,
        "index": mark.index,
        "at": None if mark.point is None else _xyz(mark.point),
    }


def preview_data(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    diagnostics: Iterable[Diagnostic] = (),
    trajectory: Trajectory | None = None,
    *,
    title: str | None = None,
    source: str | None = None,
    summary: str | None = None,
) -> dict[str, Any]:
    """The JSON the page embeds (schema ``trcopt.preview/1``; lengths mm, times s, speeds mm/min).

    Keys: ``programmed``/``toolpath`` (per segment: points ``p`` [x, y, z] that draw it, ``role``,
    ``rapid``, source ``line`` and ``block``, programmed ``feed`` in mm/min or None for rapids, tool
    radius ``r``, ``plane``), ``tools`` (the tool at the junctions), ``diagnostics`` (errors and
    warnings with their place, :func:`trcopt.io.marks.locate_diagnostics`), ``timing`` (None
    without a feed profile; else the plot samples ``t``/``v``/``seg``/``feed``/``xyz``, segment
    times ``t0``/``t1``, the speed along every segment ``along`` [x, y, z, v], the colour scale's
    ``vmax``), ``lines`` (the source text of the lines the segments name).
    """
    programmed, toolpath = list(programmed), list(toolpath)
    diagnostics = list(diagnostics)
    marks = locate_diagnostics(programmed, toolpath, diagnostics)
    text_lines = (source or "").splitlines()
    wanted = {s.span.line for s in (*programmed, *toolpath)} | {m.diagnostic.span.line for m in marks}
    lines = {str(n): text_lines[n - 1].strip()[:200] for n in sorted(wanted) if 0 < n <= len(text_lines)}
    timing = None
    if trajectory is not None:
        timing = _timing(trajectory, toolpath)
    return {
        "schema": PREVIEW_SCHEMA,
        "title": title if title is not None else "trcopt plan",
        "units": "mm",
        "summary": summary or "",
        "ok": not any(d.severity is Severity.ERROR for d in diagnostics),
        "programmed": [_seg_json(s) for s in programmed],
        "toolpath": [_seg_json(s) for s in toolpath],
        "tools": _tools(toolpath),
        "diagnostics": [_diag_json(m) for m in marks],
        "timing": timing,
        "lines": lines,
    }


def _asset(name: str) -> str:
    return resources.files("trcopt.io").joinpath(name).read_text(encoding="utf-8")


def _embed_json(data: dict[str, Any]) -> str:
    text = json.dumps(data, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
    # "<" only occurs inside JSON strings, where \u003c means the same: no "</script>" can end the block
    return text.replace("<", "\\u003c").replace("\u2028", "\\u2028").replace("\u2029", "\\u2029")


def render_html(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    diagnostics: Iterable[Diagnostic] = (),
    trajectory: Trajectory | None = None,
    *,
    title: str | None = None,
    source: str | None = None,
    summary: str | None = None,
) -> str:
    """The preview page of a plan (module docstring), as one self-contained HTML document.

    Parameters
    ----------
    programmed, toolpath:
        The programmed contour and the tool-centre path, mm.
    diagnostics:
        The plan's diagnostics; errors and warnings are marked and listed.
    trajectory:
        The timed tool path (either kind): colours the path by the planned speed and gives the
        speed-over-time plot. Without it the path is coloured by role and there is no plot.
    title:
        Heading and page title (default ``"trcopt plan"``).
    source:
        The program text: hovering a segment shows its source line.
    summary:
        A few lines shown under the heading (e.g. ``PlanResult.summary()``).
    """
    data = preview_data(
        programmed, toolpath, diagnostics, trajectory, title=title, source=source, summary=summary
    )
    heading = html.escape(data["title"])
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        "<meta name=\"generator\" content=\"trcopt\">\n"
        "<link rel=\"icon\" href=\"data:,\">\n"
        f"<title>{heading} — trcopt preview</title>\n<style>\n{_asset('html_preview.css')}</style>\n</head>\n"
        f"<body>\n<header><h1>{heading}</h1><pre id=\"summary\"></pre></header>\n"
        f"{_asset('html_preview_body.html')}"
        f"<script type=\"application/json\" id=\"plan-data\">{_embed_json(data)}</script>\n"
        f"<script>\n{_asset('html_preview.js')}</script>\n</body>\n</html>\n"
    )


def write_html(path: str | os.PathLike[str], *args: Any, **kwargs: Any) -> Path:
    """Render with :func:`render_html` (same arguments) and write the page atomically
    (:class:`~trcopt.io.atomic.OutputError` on an I/O failure)."""
    return write_text_atomic(path, render_html(*args, **kwargs))
