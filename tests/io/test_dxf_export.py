"""DXF export: layers, entity types, CW arcs with swapped angles, round trip through ezdxf."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane, hermite_curve
from trcopt.path import Role, Segment


def seg(geom, role=Role.CONTOUR, feed=10.0, plane=Plane.G17):
    return Segment(geom, plane, role, SourceSpan("sq.mpf", 1, 1), feed, radius=5.0)


def test_io_package_import_is_cheap():
    code = (
        "import sys, trcopt.io; "
        "bad = [m for m in ('ezdxf', 'matplotlib') if m in sys.modules]; "
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_dxf_round_trip(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    from trcopt.io.dxf import write_dxf

    programmed = [seg(Line((0, 0, 0), (0, 40, 0)))]
    toolpath = [
        seg(Line((-5, -10, 0), (-5, 0, 0)), Role.APPROACH),
        seg(Line((-5, 0, 0), (-5, 40, 0))),
        seg(Arc((0, 40), 5.0, math.pi, -math.pi / 2, -2.0, -2.0), Role.CORNER),  # G2
        seg(Arc((0, 0), 3.0, 0.0, math.pi / 2)),  # G3
        seg(Arc((0, 0), 2.0, 0.0, 2 * math.pi)),  # full circle
        seg(hermite_curve((0, 0, 1), (5, 0, 0), (5, 5, 1), (0, 5, 0))),
        seg(Line((0, 0, 0), (0, 0, 10)), Role.RAPID, feed=None),
    ]
    path = write_dxf(tmp_path / "plan.dxf", programmed, toolpath)
    doc = ezdxf.readfile(path)
    assert {"PROGRAMMED", "TOOLPATH", "INSERTED"} <= {layer.dxf.name for layer in doc.layers}
    msp = doc.modelspace()
    kinds = [(e.dxftype(), e.dxf.layer) for e in msp]
    assert kinds == [
        ("LINE", "PROGRAMMED"),
        ("LINE", "INSERTED"),
        ("LINE", "TOOLPATH"),
        ("ARC", "INSERTED"),
        ("ARC", "TOOLPATH"),
        ("CIRCLE", "TOOLPATH"),
        ("LWPOLYLINE", "TOOLPATH"),
        ("LINE", "TOOLPATH"),
    ]
    ents = list(msp)
    cw = ents[3]
    # CW from 180° to 90° is written CCW from 90° to 180°
    assert cw.dxf.start_angle == pytest.approx(90.0) and cw.dxf.end_angle == pytest.approx(180.0)
    assert tuple(cw.dxf.center) == pytest.approx((0.0, 40.0, -2.0))
    assert cw.dxf.radius == pytest.approx(5.0)
    ccw = ents[4]
    assert (ccw.dxf.start_angle, ccw.dxf.end_angle) == pytest.approx((0.0, 90.0))
    poly = ents[6]
    assert len(poly) == len(toolpath[5].geometry.points)
    assert poly.dxf.elevation == pytest.approx(1.0)
    assert ents[7].dxf.linetype == "DASHED"
    assert tuple(ents[0].dxf.end) == pytest.approx((0.0, 40.0, 0.0))


def test_dxf_g18_plan_uses_plane_coordinates(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    from trcopt.io.dxf import write_dxf

    arc = Arc((0, 0), 5.0, 0.0, -math.pi / 2, 7.0, 7.0)  # G18: u = Z, v = X, w = Y
    path = write_dxf(tmp_path / "g18.dxf", [], [seg(arc, plane=Plane.G18)])
    (e,) = list(ezdxf.readfile(path).modelspace())
    assert e.dxftype() == "ARC"
    assert (e.dxf.start_angle, e.dxf.end_angle) == pytest.approx((270.0, 0.0))
    assert tuple(e.dxf.center) == pytest.approx((0.0, 0.0, 7.0))
