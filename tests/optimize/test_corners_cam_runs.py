"""G2 splines across the runs of CAM chords of real-size programs: through the transition arcs of a
compensated contour (LinuxCNC inserts one at every outside vertex) and on a tool-centre polyline
without compensation (G40 CAM output) — within the tolerance, no gouge, every limit held, never
slower than the circular blends."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gouge import gouges  # noqa: E402

from trcopt.geometry import Arc, Line  # noqa: E402
from trcopt.modes import TransitionKind  # noqa: E402
from trcopt.optimize.corners import (
    blend_corners,  # noqa: E402
    cut_deviation,  # noqa: E402
)
from trcopt.pipeline import PlanOptions, plan  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402

EPS = 0.01


def _freeform(chords: int, compensated: bool) -> str:
    """A closed freeform contour r = 30 + 5 sin 5t + 2 cos 11t (mm) as ``chords`` G1 chords
    (LinuxCNC), entered and left from outside; with ``G41.1 D2`` or as a G40 tool-centre path."""
    out = ["G21 G17 G90 G40 F6000", "G0 X50 Y0 Z1", "G1 Z0"]
    pts = []
    for i in range(chords + 1):
        t = 2 * math.pi * i / chords
        r = 30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t)
        pts.append((r * math.cos(t), r * math.sin(t)))
    out.append(("G41.1 D2 " if compensated else "") + f"G1 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}")
    out += [f"G1 X{x:.5f} Y{y:.5f}" for x, y in pts[1:]]
    if compensated:
        out.append("G40 G1 X50 Y0")
    return "\n".join([*out, "G0 Z5", "M2"]) + "\n"


def _polyline_distance(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Distance of every point to the polyline through ``vertices`` (brute force, plane)."""
    a, b = vertices[:-1], vertices[1:]
    d = b - a
    t = np.clip(np.einsum("pkj,kj->pk", points[:, None, :] - a[None], d) / np.einsum("kj,kj->k", d, d), 0.0, 1.0)
    foot = a[None] + t[..., None] * d[None]
    return np.min(np.linalg.norm(points[:, None, :] - foot, axis=2), axis=1)


@pytest.fixture(scope="module")
def compensated():
    exact = plan(_freeform(200, True), file="cam.ngc", options=PlanOptions(timing=False))
    arc = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="arc")
    opt = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="optimal", workers=1)
    return exact, arc, opt


def test_compensated_runs_continue_through_the_transition_arcs(compensated):
    exact, arc, opt = compensated
    arcs = [s for s in exact.toolpath if isinstance(s.geometry, Arc) and s.radius > 0]
    assert len(arcs) > 20  # LinuxCNC's transition arcs at the outside vertices
    spline = [c for c in opt.corners if c.transition is TransitionKind.SPLINE]
    assert len(spline) > 0.8 * len(opt.corners)
    # the transition arcs inside the runs are replaced (a spline piece per element)
    left = [s for s in opt.segments if isinstance(s.geometry, Arc) and s.radius > 0 and s.geometry.radius < 1.01]
    assert len(left) < 0.5 * len(arcs)  # 20 of 58 left: sweeps over 20°, and the ends of runs


def test_compensated_runs_keep_tolerance_and_clearance_and_are_faster(compensated):
    exact, arc, opt = compensated
    assert cut_deviation(exact.programmed, exact.toolpath, opt.segments)[0] <= EPS
    # no closer to the part than R, or than the exact path itself is at a near-tangent joint
    base = min((g[2] for g in gouges(exact.programmed, exact.toolpath, tol=0.0)), default=2.0)
    worst = min((g[2] for g in gouges(exact.programmed, opt.segments, tol=0.0)), default=2.0)
    assert worst >= min(1.0, base) - 1e-6
    t_opt, t_arc = (time_parameterize(r.segments) for r in (opt, arc))
    assert t_opt.check_limits().ok and t_arc.check_limits().ok
    assert t_opt.duration < 0.95 * t_arc.duration  # measured 4.18 against 4.64 s


def test_g40_cam_polyline_runs_become_splines_within_the_tolerance_on_both_sides():
    exact = plan(_freeform(200, False), file="cam.ngc", options=PlanOptions(timing=False))
    arc = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="arc")
    opt = blend_corners(exact.toolpath, exact.programmed, tolerance_mm=EPS, mode="optimal", workers=1)
    assert opt.count(TransitionKind.SPLINE) > 0.9 * len(opt.corners)
    # the vertices of the programmed polyline and the new path within ε of each other, both ways
    feed = [s for s in exact.toolpath if isinstance(s.geometry, Line) and not s.is_rapid]
    vertices = np.array([feed[0].geometry.start[:2]] + [s.geometry.end[:2] for s in feed if s.geometry.plane_length])
    curve = [s.geometry for s in opt.segments if not s.is_rapid and s.geometry.plane_length > 0]
    pts = np.vstack([np.array([g.point2(x) for x in np.linspace(0.0, 1.0, 40)]) for g in curve])
    pts = pts[np.concatenate(([True], np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-9))]
    assert _polyline_distance(pts, vertices).max() <= EPS + 1e-9
    assert _polyline_distance(vertices[1:-1], pts).max() <= EPS + 1e-3  # (sampled new path)
    t_opt, t_arc = (time_parameterize(r.segments) for r in (opt, arc))
    assert t_opt.check_limits().ok
    assert t_opt.duration < 0.97 * t_arc.duration  # measured 3.40 against 3.62 s
