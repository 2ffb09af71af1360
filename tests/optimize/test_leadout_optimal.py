"""Optimal lead-out: the mirrored lead-in, from the contour end's tool-centre point to the end point."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gouge import _element_distance, _samples  # noqa: E402

from trcopt.cli import main
from trcopt.errors import SolverError, SourceSpan
from trcopt.geometry import Line, Plane
from trcopt.optimize.leads import optimal_lead_out
from trcopt.path import Role, Segment

ROOT = Path(__file__).resolve().parents[2]
CONTOUR = [Line((0.0, 0.0, 0.0), (40.0, 0.0, 0.0)), Line((40.0, 0.0, 0.0), (40.0, 30.0, 0.0))]


def test_lead_out_leaves_tangentially_and_reaches_the_end_point() -> None:
    lead = optimal_lead_out((60.0, 40.0, 0.0), CONTOUR, 5.0, "right", rho_min=3.0, safety=1.0)
    first, last = lead.elements[0], lead.elements[-1]
    # G42 along +y at x = 40: the tool centre leaves at (45, 30) in the direction (0, 1)
    assert first.start[:2] == pytest.approx((45.0, 30.0), abs=1e-9)
    assert first.start_tangent() == pytest.approx((0.0, 1.0), abs=1e-7)
    assert last.end[:2] == pytest.approx((60.0, 40.0), abs=1e-9)
    for a, b in zip(lead.elements, lead.elements[1:], strict=False):
        assert math.dist(a.end, b.start) < 1e-9
        assert a.end_tangent() == pytest.approx(b.start_tangent(), abs=1e-6)
    assert {s.role for s in lead.segments} == {Role.RETRACT}
    assert lead.side.value == "right"
    # independent clearance: no lead point closer than R to the contour (R + safety away from the exit)
    for seg in lead.segments:
        pts = _samples(seg, 0.02)
        for c in CONTOUR:
            d = _element_distance(pts, Segment(c, Plane.G17, Role.CONTOUR, SourceSpan(), None))
            assert float(np.min(d)) >= 5.0 - 1e-6


def test_lead_out_that_cannot_fit_names_the_binding_constraint() -> None:
    # the end point lies inside the part, 2 mm from the first edge: no lead keeps R = 5 clearance
    with pytest.raises(SolverError, match="clearance|region|start"):
        optimal_lead_out((20.0, 2.0, 0.0), CONTOUR, 5.0, "right", rho_min=3.0, safety=1.0)


def test_trcopt_leadin_out_writes_json_and_gcode(tmp_path: Path) -> None:
    out, nc = tmp_path / "lo.json", tmp_path / "lo.nc"
    rc = main(["leadin", str(ROOT / "problems" / "siemens" / "ex02_square_g450.mpf"), "--out", "--rho-min", "2",
               "--json", str(out), "--gcode", str(nc)])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["direction"] == "out" and data["side"] == "left"
    segs = data["segments"]
    assert segs[0]["start"][:2] == pytest.approx([0.0, -5.0], abs=1e-9)
    assert segs[-1]["end"][:2] == pytest.approx([-20.0, -20.0], abs=1e-9)
    assert "G41" not in nc.read_text() and nc.read_text().rstrip().endswith("M30")
