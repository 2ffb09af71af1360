"""DXF export of a plan (optional extra ``trcopt[dxf]``; ezdxf is imported inside the function).

Layers: ``PROGRAMMED`` (the programmed contour), ``TOOLPATH`` (tool-centre contour, rapids and
positioning; rapids with linetype DASHED) and ``INSERTED`` (corner elements, approach and retract
contours the compensation inserted).
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Sequence
from pathlib import Path

from trcopt.codes import Code
from trcopt.errors import TrcoptError
from trcopt.geometry.plane import Plane
from trcopt.geometry.poly import Poly
from trcopt.geometry.primitives import Arc, Line
from trcopt.io.atomic import write_text_atomic
from trcopt.path import Role, Segment

__all__ = ["write_dxf", "DXF_LAYERS"]

DXF_LAYERS = {
    "PROGRAMMED": 7,
    "TOOLPATH": 5,
    "INSERTED": 30,
}  # ACI colours: white/black, blue, orange
_INSERTED_ROLES = (Role.CORNER, Role.APPROACH, Role.RETRACT)


def _uv(draw: Plane, seg_plane: Plane, p: Sequence[float]) -> tuple[float, float, float]:
    if seg_plane is draw:
        return (float(p[0]), float(p[1]), float(p[2]))
    return draw.to_uvw(seg_plane.to_xyz((p[0], p[1], p[2])))


def write_dxf(
    path: str | os.PathLike[str], programmed: Sequence[Segment], toolpath: Sequence[Segment]
) -> Path:
    """Write the programmed contour and the tool-centre path to a DXF file (R2013, mm).

    Drawn in the plane of the first segment: for G17 the DXF x, y, z are the workpiece X, Y, Z;
    for a G18/G19 plan the DXF x, y are that plane's (u, v) — G18: (Z, X), G19: (Y, Z) — and the
    DXF z is the applicate. Lines are LINE entities (3D), arcs ARC entities (degrees,
    counter-clockwise; a clockwise arc is written with start and end angle swapped; a full circle
    is a CIRCLE) at the start applicate — a helix is flattened to its start height — and polys
    LWPOLYLINEs through their samples at the start applicate. Segments in another plane than the
    first one are projected onto the drawing plane (arcs then as LWPOLYLINEs).

    Parameters
    ----------
    path:
        Destination ``.dxf`` file; written atomically.
    programmed, toolpath:
        The two paths (mm).

    Raises
    ------
    TrcoptError
        ezdxf is not installed ("install trcopt[dxf]").
    OutputError
        The file cannot be written.
    """
    try:
        import ezdxf  # noqa: PLC0415 - optional extra, loaded on use
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise TrcoptError(
            "DXF output needs ezdxf: install trcopt[dxf] (pip install 'trcopt[dxf]')",
            code=Code.DXF_MISSING,
        ) from exc

    programmed, toolpath = list(programmed), list(toolpath)
    everything = toolpath or programmed
    draw = everything[0].plane if everything else Plane.G17

    doc = ezdxf.new("R2013", setup=True)
    doc.units = ezdxf.units.MM
    for name, colour in DXF_LAYERS.items():
        if name not in doc.layers:
            doc.layers.add(name, color=colour)
    msp = doc.modelspace()

    def add(seg: Segment, layer: str) -> None:
        attribs: dict[str, object] = {"layer": layer}
        if seg.is_rapid or seg.role in (Role.RAPID, Role.POSITIONING):
            attribs["linetype"] = "DASHED"
        g = seg.geometry
        if isinstance(g, Line):
            a, b = _uv(draw, seg.plane, g.start), _uv(draw, seg.plane, g.end)
            if math.dist(a, b) > 0.0:
                msp.add_line(a, b, dxfattribs=attribs)
            return
        if isinstance(g, Arc) and seg.plane is draw:
            centre = (g.center[0], g.center[1], g.w0)
            if abs(g.sweep) >= 2 * math.pi - 1e-12:
                msp.add_circle(centre, g.radius, dxfattribs=attribs)
                return
            a0, a1 = math.degrees(g.a0), math.degrees(g.a0 + g.sweep)
            start, end = (a0, a1) if g.sweep > 0 else (a1, a0)
            msp.add_arc(centre, g.radius, start % 360.0, end % 360.0, dxfattribs=attribs)
            return
        if isinstance(g, Arc):
            n = max(8, int(abs(g.sweep) / (math.pi / 64)) + 1)
            pts = [(*g.point2(k / n), g.w0 + (g.w1 - g.w0) * k / n) for k in range(n + 1)]
        elif isinstance(g, Poly):
            pts = list(g.points)
        else:  # pragma: no cover - Segment geometry is Line | Arc | Poly
            raise TrcoptError(f"cannot write {type(g).__name__} to DXF")
        uvw = [_uv(draw, seg.plane, p) for p in pts]
        poly_attribs = dict(attribs, elevation=uvw[0][2])
        msp.add_lwpolyline([(p[0], p[1]) for p in uvw], format="xy", dxfattribs=poly_attribs)

    for seg in programmed:
        add(seg, "PROGRAMMED")
    for seg in toolpath:
        add(seg, "INSERTED" if seg.role in _INSERTED_ROLES else "TOOLPATH")

    stream = io.StringIO()
    doc.write(stream)
    return write_text_atomic(path, stream.getvalue())
