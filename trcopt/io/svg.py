"""Self-contained SVG preview of a plan: programmed contour, tool-centre path, tool, alarms.

Drawn in the plane of the first segment (u, v; the applicate is ignored), +v up. Lines are
``L`` commands, arcs exact ``A`` commands (split so no piece reaches 180°), polys polylines; each
segment is one ``<path>`` carrying ``data-role``/``data-line``/``data-block`` attributes.
Segments in another plane are projected onto the drawing plane (arcs then as sampled polylines).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from xml.sax.saxutils import escape as _xml_escape
from xml.sax.saxutils import quoteattr as _xml_quoteattr

from trcopt.errors import Diagnostic, Severity
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.path import Role, Segment

# characters XML 1.0 does not allow (C0 controls other than tab, LF, CR; lone surrogates; U+FFFE/F):
# a program's comment or a diagnostic quoting a binary byte must not make the picture unreadable
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def escape(text: str) -> str:
    """``text`` as XML character data: markup escaped, characters XML forbids as U+FFFD."""
    return _xml_escape(_NOT_XML.sub("\ufffd", text))


def quoteattr(text: str) -> str:
    """``text`` as a quoted XML attribute value (characters XML forbids as U+FFFD)."""
    return _xml_quoteattr(_NOT_XML.sub("\ufffd", text))


__all__ = ["render_svg", "ROLE_COLOURS", "MAX_TOOL_CIRCLES"]


MAX_TOOL_CIRCLES = 400
PROGRAMMED_COLOUR = "#000000"
ROLE_COLOURS = {
    Role.CONTOUR: "#1f5fd6",
    Role.CORNER: "#f28c00",
    Role.APPROACH: "#1a9e3a",
    Role.RETRACT: "#1a9e3a",
    Role.RAPID: "#8c8c8c",
    Role.POSITIONING: "#8c8c8c",
}
MARKER_COLOUR = "#d62020"
TOOL_COLOUR = "#1f5fd6"

_TITLE_PX = 28.0
_LEGEND_LINE_PX = 16.0
_PAD_PX = 8.0


def _n(x: float) -> str:
    """Compact number for SVG attributes (6 significant decimals, no -0)."""
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


class _Projector:
    """Maps a segment's plane coordinates to drawing (u, v) and SVG (x, y = −v)."""

    def __init__(self, plane: Plane) -> None:
        self.plane = plane

    def uv(self, seg_plane: Plane, p: Sequence[float]) -> Vec2:
        if seg_plane is self.plane:
            return (p[0], p[1])
        q = self.plane.to_uvw(seg_plane.to_xyz((p[0], p[1], p[2] if len(p) > 2 else 0.0)))
        return (q[0], q[1])


def _arc_samples(arc: Arc, n: int = 0) -> list[tuple[float, float, float]]:
    n = n or max(8, int(abs(arc.sweep) / (math.pi / 64)) + 1)
    out = []
    for k in range(n + 1):
        lam = k / n
        p = arc.point2(lam)
        out.append((p[0], p[1], arc.w0 + lam * (arc.w1 - arc.w0)))
    return out


def _arc_extreme_points(arc: Arc) -> list[Vec2]:
    """Start, end and the axis extremes of the circle that lie within the sweep."""
    pts = [arc.point2(0.0), arc.point2(1.0)]
    lo, hi = sorted((arc.a0, arc.a0 + arc.sweep))
    for k in range(math.floor(lo / (math.pi / 2)), math.ceil(hi / (math.pi / 2)) + 1):
        a = k * math.pi / 2
        if lo <= a <= hi:
            pts.append(
                (arc.center[0] + arc.radius * math.cos(a), arc.center[1] + arc.radius * math.sin(a))
            )
    return pts


def _segment_points(proj: _Projector, seg: Segment) -> list[Vec2]:
    """Points that bound the drawn segment (for the view box)."""
    g = seg.geometry
    if isinstance(g, Line):
        return [proj.uv(seg.plane, g.start), proj.uv(seg.plane, g.end)]
    if isinstance(g, Arc):
        if seg.plane is proj.plane:
            return _arc_extreme_points(g)
        return [proj.uv(seg.plane, p) for p in _arc_samples(g)]
    return [proj.uv(seg.plane, p) for p in g.points]


def _path_d(proj: _Projector, seg: Segment) -> str:
    g = seg.geometry

    def xy(p: Vec2) -> str:
        return f"{_n(p[0])} {_n(-p[1])}"

    if isinstance(g, Line):
        return f"M {xy(proj.uv(seg.plane, g.start))} L {xy(proj.uv(seg.plane, g.end))}"
    if isinstance(g, Arc) and seg.plane is proj.plane:
        pieces = max(1, math.ceil(abs(g.sweep) / (math.pi - 1e-6)))
        parts = [f"M {xy(g.point2(0.0))}"]
        # y is flipped, so a counter-clockwise arc is drawn with SVG sweep-flag 0
        flag = 0 if g.sweep > 0 else 1
        r = _n(g.radius)
        for k in range(1, pieces + 1):
            parts.append(f"A {r} {r} 0 0 {flag} {xy(g.point2(k / pieces))}")
        return " ".join(parts)
    pts = _arc_samples(g) if isinstance(g, Arc) else list(g.points)
    uv = [proj.uv(seg.plane, p) for p in pts]
    return "M " + xy(uv[0]) + " L " + " ".join(xy(p) for p in uv[1:])


def _tool_junctions(proj: _Projector, toolpath: Sequence[Segment]) -> list[tuple[Vec2, float]]:
    out: list[tuple[Vec2, float]] = []
    for i, seg in enumerate(toolpath):
        if i == 0 and seg.radius > 0:
            out.append((proj.uv(seg.plane, seg.geometry.start), seg.radius))
        if seg.radius > 0:
            out.append((proj.uv(seg.plane, seg.geometry.end), seg.radius))
    if len(out) > MAX_TOOL_CIRCLES:
        step = (len(out) - 1) / (MAX_TOOL_CIRCLES - 1)
        out = [out[round(k * step)] for k in range(MAX_TOOL_CIRCLES)]
    return out


def _locate(diag: Diagnostic, proj: _Projector, paths: Iterable[Sequence[Segment]]) -> Vec2 | None:
    if not diag.span.line:
        return None
    for segs in paths:
        for seg in segs:
            if seg.span.line == diag.span.line and (diag.span.file in (seg.span.file, "<program>")):
                return proj.uv(seg.plane, seg.geometry.start)
    return None


def render_svg(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    diagnostics: Iterable[Diagnostic] = (),
    *,
    title: str | None = None,
    show_tool: bool = True,
    width_px: int = 900,
    markers: Iterable[tuple[float, float, str]] = (),
) -> str:
    """Render a plan as a standalone SVG document.

    Parameters
    ----------
    programmed:
        Programmed contour (black, thin).
    toolpath:
        Tool-centre path: contour blue, corner elements orange, approach/retract green, rapids and
        positioning grey dashed.
    diagnostics:
        Error/warning diagnostics are drawn as red markers at the start of the first segment of
        their source line (toolpath first, then programmed); the ones that cannot be located are
        listed under the legend.
    title:
        Heading (default ``"trcopt plan"``).
    show_tool:
        Draw the tool (faint circle of ``segment.radius``, mm) at every junction of the
        tool-centre path where the radius is > 0 (at most 400, evenly chosen).
    width_px:
        Width of the picture, px; the height follows the aspect ratio of the drawing.
    markers:
        Extra red markers ``(u, v, label)`` in drawing-plane coordinates (x, y for G17), mm.

    Returns
    -------
    str
        The SVG document (UTF-8 XML).
    """
    programmed = list(programmed)
    toolpath = list(toolpath)
    everything = toolpath or programmed
    proj = _Projector(everything[0].plane if everything else Plane.G17)

    tools = _tool_junctions(proj, toolpath) if show_tool else []
    marks: list[tuple[Vec2, str]] = [((float(u), float(v)), str(label)) for u, v, label in markers]
    unlocated: list[Diagnostic] = []
    for d in diagnostics:
        if d.severity not in (Severity.ERROR, Severity.WARNING):
            continue
        p = _locate(d, proj, (toolpath, programmed))
        label = f"{d.severity.value} {d.alarm if d.alarm is not None else d.code}"
        if d.span.block:
            label += f" ({d.span.block})"
        if p is None:
            unlocated.append(d)
        else:
            marks.append((p, label))

    # bounding box in drawing coordinates
    pts: list[Vec2] = []
    for seg in [*programmed, *toolpath]:
        pts += _segment_points(proj, seg)
    for (u, v), r in tools:
        pts += [(u - r, v - r), (u + r, v + r)]
    pts += [p for p, _ in marks]
    if not pts:
        pts = [(0.0, 0.0)]
    umin, umax = min(p[0] for p in pts), max(p[0] for p in pts)
    vmin, vmax = min(p[1] for p in pts), max(p[1] for p in pts)
    size = max(umax - umin, vmax - vmin, 1e-3)
    margin = 0.04 * size
    vb_x, vb_y = umin - margin, -(vmax + margin)
    vb_w, vb_h = (umax - umin) + 2 * margin, (vmax - vmin) + 2 * margin
    vb_w, vb_h = max(vb_w, 1e-3), max(vb_h, 1e-3)

    width = float(width_px)
    draw_h = min(width * vb_h / vb_w, 4.0 * width)
    px_per_mm = min(width / vb_w, draw_h / vb_h)
    mm_per_px = 1.0 / px_per_mm

    legend = [
        ("programmed contour", PROGRAMMED_COLOUR, None),
        ("tool-centre path", ROLE_COLOURS[Role.CONTOUR], None),
        ("corner element", ROLE_COLOURS[Role.CORNER], None),
        ("approach / retract", ROLE_COLOURS[Role.APPROACH], None),
        ("rapid / positioning", ROLE_COLOURS[Role.RAPID], "4 3"),
    ]
    if tools:
        legend.append(("tool", TOOL_COLOUR, "circle"))
    if marks or unlocated:
        legend.append(("alarm / warning", MARKER_COLOUR, "marker"))
    notes = [f"not located: {d.format()}" for d in unlocated]
    legend_h = _PAD_PX + _LEGEND_LINE_PX * (len(legend) + len(notes)) + _PAD_PX
    total_h = _TITLE_PX + draw_h + legend_h

    out: list[str] = []
    a = out.append
    a('<?xml version="1.0" encoding="UTF-8"?>')
    a(
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{_n(width)}" '
        f'height="{_n(total_h)}" viewBox="0 0 {_n(width)} {_n(total_h)}" '
        'font-family="sans-serif" font-size="12">'
    )
    heading = title if title is not None else "trcopt plan"
    a(f"<title>{escape(heading)}</title>")
    a(f'<rect x="0" y="0" width="{_n(width)}" height="{_n(total_h)}" fill="#ffffff"/>')
    a(f'<text x="{_n(_PAD_PX)}" y="19" font-size="15" font-weight="bold">{escape(heading)}</text>')

    # the drawing, in mm, y flipped by construction (SVG y = -v)
    a(
        f'<svg x="0" y="{_n(_TITLE_PX)}" width="{_n(width)}" height="{_n(draw_h)}" '
        f'viewBox="{_n(vb_x)} {_n(vb_y)} {_n(vb_w)} {_n(vb_h)}" '
        'preserveAspectRatio="xMidYMid meet">'
    )
    if tools:
        a(f'<g class="tool" fill="none" stroke="{TOOL_COLOUR}" stroke-opacity="0.25">')
        for (u, v), r in tools:
            a(
                f'<circle cx="{_n(u)}" cy="{_n(-v)}" r="{_n(r)}" stroke-width="{_n(mm_per_px)}"/>'
            )
        a("</g>")

    def seg_path(seg: Segment, colour: str, width_px_: float, dashed: bool, cls: str) -> str:
        dash = f' stroke-dasharray="{_n(4 * mm_per_px)} {_n(3 * mm_per_px)}"' if dashed else ""
        block = f" data-block={quoteattr(seg.span.block)}" if seg.span.block else ""
        return (
            f'<path class="seg {cls}" d="{_path_d(proj, seg)}" fill="none" stroke="{colour}" '
            f'stroke-width="{_n(width_px_ * mm_per_px)}"{dash} '
            f'data-role="{seg.role.value}" data-line="{seg.span.line}"{block}/>'
        )

    a('<g class="programmed">')
    for seg in programmed:
        a(seg_path(seg, PROGRAMMED_COLOUR, 0.8, False, "programmed"))
    a("</g>")
    a('<g class="toolpath">')
    for seg in toolpath:
        dashed = seg.is_rapid or seg.role in (Role.RAPID, Role.POSITIONING)
        colour = ROLE_COLOURS[Role.RAPID] if dashed else ROLE_COLOURS[seg.role]
        a(seg_path(seg, colour, 1.6, dashed, "toolpath"))
    a("</g>")
    if marks:
        r_mark = 5.0 * mm_per_px
        a(f'<g class="markers" fill="{MARKER_COLOUR}" stroke="{MARKER_COLOUR}">')
        placed: list[tuple[float, float]] = []
        line_h = 13 * mm_per_px
        for (u, v), label in marks:
            a(
                f'<circle cx="{_n(u)}" cy="{_n(-v)}" r="{_n(r_mark)}" fill-opacity="0.5">'
                f"<title>{escape(label)}</title></circle>"
            )
            # labels of nearby markers are stacked instead of drawn over each other
            tx, ty = u + 1.5 * r_mark, -v - 1.5 * r_mark
            while any(abs(ty - py) < line_h and abs(tx - px) < 160 * mm_per_px for px, py in placed):
                ty -= line_h
            placed.append((tx, ty))
            a(
                f'<text x="{_n(tx)}" y="{_n(ty)}" stroke="none" '
                f'font-size="{_n(11 * mm_per_px)}">{escape(label)}</text>'
            )
        a("</g>")
    a("</svg>")

    # legend, in px below the drawing
    y0 = _TITLE_PX + draw_h + _PAD_PX
    a(f'<g class="legend" transform="translate({_n(_PAD_PX)} {_n(y0)})">')
    for k, (label, colour, style) in enumerate(legend):
        y = _n(k * _LEGEND_LINE_PX + 8)
        if style == "circle":
            a(
                f'<circle cx="14" cy="{y}" r="6" fill="none" stroke="{colour}" '
                'stroke-opacity="0.4"/>'
            )
        elif style == "marker":
            a(
                f'<circle cx="14" cy="{y}" r="5" fill="{colour}" '
                f'fill-opacity="0.5" stroke="{colour}"/>'
            )
        else:
            dash = f' stroke-dasharray="{style}"' if style else ""
            a(f'<line x1="0" y1="{y}" x2="28" y2="{y}" stroke="{colour}" stroke-width="2"{dash}/>')
        a(f'<text x="36" y="{_n(k * _LEGEND_LINE_PX + 12)}">{escape(label)}</text>')
    for k, note in enumerate(notes):
        y_note = (len(legend) + k) * _LEGEND_LINE_PX + 12
        a(f'<text x="0" y="{_n(y_note)}" fill="{MARKER_COLOUR}">{escape(note)}</text>')
    a("</g>")
    a("</svg>")
    return "\n".join(out) + "\n"
