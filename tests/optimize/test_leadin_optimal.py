"""Optimal lead-in: constraints hold (checked independently), errors name the binding constraint,
G-code round trip, CLI."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import pytest

from trcopt.cli.leadin import add_arguments
from trcopt.errors import SolverError
from trcopt.geometry import Arc, Line, Poly
from trcopt.modes import LeadObjective
from trcopt.optimize.leads.leadin import optimal_lead
from trcopt.optimize.leads.report import compare_with_sar, leadin_gcode, leadin_svg
from trcopt.pipeline import PlanOptions, plan

PROBLEMS = Path(__file__).resolve().parents[2] / "problems" / "siemens"
SQUARE = [
    Line((0, 0, 0), (0, 40, 0)),
    Line((0, 40, 0), (40, 40, 0)),
    Line((40, 40, 0), (40, 0, 0)),
    Line((40, 0, 0), (0, 0, 0)),
]
# a contour starting with an arc (offset curvature at P4c) and a notch near the start
ARC_PART = [
    Arc.from_points((0, 0, 0), (20, 20, 0), (20, 0), ccw=False),
    Line((20, 20, 0), (40, 20, 0)),
    Line((40, 20, 0), (40, -10, 0)),
    Line((40, -10, 0), (0, -10, 0)),
    Line((0, -10, 0), (0, 0, 0)),
]


# ---- independent checks (dense sampling, own distance functions) -----------------------------


def _samples(el, n=400):
    if isinstance(el, Poly):
        return np.array([p for p in el.points])
    return np.array([el.point(s) for s in np.linspace(0.0, el.length, n)])


def _dist_to_contour(pts2, contour):
    best = np.full(len(pts2), np.inf)
    for el in contour:
        if isinstance(el, Line):
            a, b = np.array(el.start[:2]), np.array(el.end[:2])
            d = b - a
            t = np.clip((pts2 - a) @ d / (d @ d), 0, 1)
            dist = np.linalg.norm(pts2 - (a + t[:, None] * d), axis=1)
        else:
            q = np.array([el.point2(u) for u in np.linspace(0, 1, 4000)])
            dist = np.min(np.linalg.norm(pts2[:, None, :] - q[None, :, :], axis=2), axis=1)
        best = np.minimum(best, dist)
    return best


def _check_lead(res, contour, R, safety, rho_min, region=None):
    pts = np.vstack([_samples(e) for e in res.elements])
    d = _dist_to_contour(pts[:, :2], contour)
    assert d.min() >= R - 1e-6, "the lead gouges the contour"
    # away from the contact at P4c the lead keeps R + safety from the elements not meeting P4
    far = [e for e in contour if min(math.dist(e.start[:2], res.p4[:2]), math.dist(e.end[:2], res.p4[:2])) > 1e-9]
    if far:
        assert _dist_to_contour(pts[:, :2], far).min() >= R + safety - 1e-4
    # ends at P4c with the contour's tangent
    last = res.elements[-1]
    assert math.dist(last.end, res.p4c) <= 1e-6
    te = last.end_tangent()
    assert (
        abs(te[0] * res.tangent[1] - te[1] * res.tangent[0]) <= 1e-6
        and te[0] * res.tangent[0] + te[1] * res.tangent[1] > 0
    )
    # starts at P0, continuous, no reversal of the applicate
    assert math.dist(res.elements[0].start, res.p0) <= 1e-9
    for a, b in zip(res.elements, res.elements[1:], strict=False):
        assert math.dist(a.end, b.start) <= 1e-6
    w = pts[:, 2]
    sign = 1.0 if w[-1] >= w[0] else -1.0
    assert np.all(np.diff(sign * w) >= -1e-9)
    # curvature
    for e in res.elements:
        if isinstance(e, Arc):
            assert e.radius >= rho_min - 1e-9
        if isinstance(e, Poly):
            p = np.array([q[:2] for q in e.points])
            a, b, c = p[:-2], p[1:-1], p[2:]
            ab, bc, ca = (np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1))
            cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
            kappa = 2 * cross / np.maximum(ab * bc * ca, 1e-300)
            assert kappa.max() <= 1.0 / rho_min * 1.001
    if region is not None:
        poly = np.array(region)
        for i in range(len(poly)):
            a, b = poly[i], poly[(i + 1) % len(poly)]
            cr = (b[0] - a[0]) * (pts[:, 1] - a[1]) - (b[1] - a[1]) * (pts[:, 0] - a[0])
            assert cr.min() >= -1e-6


@pytest.mark.parametrize(
    "contour, start, side",
    [
        pytest.param(SQUARE, (-20.0, -20.0, 10.0), "left", id="square-behind"),
        pytest.param(SQUARE, (25.0, -25.0, 3.0), "left", id="square-side", marks=pytest.mark.slow),
        pytest.param(ARC_PART, (-15.0, 15.0, 5.0), "left", id="arc-start", marks=pytest.mark.slow),
    ],
)
def test_optimal_lead_satisfies_the_constraints(contour, start, side) -> None:
    res = optimal_lead(start, contour, 5.0, side, rho_min=3.0, safety=1.0, feed_mm_s=20.0)
    _check_lead(res, contour, 5.0, 1.0, 3.0)
    assert res.objective in (LeadObjective.TIME, LeadObjective.SURROGATE)
    assert res.candidates and all(c.solution.ok for c in res.candidates)
    assert res.time_s == min(c.time_s for c in res.candidates)
    json.dumps(res.to_json())


def test_region_is_respected() -> None:
    region = [(-31.0, -31.0), (-4.0, -31.0), (-4.0, 1.0), (-31.0, 1.0)]
    res = optimal_lead((-30.0, -30.0, 0.0), SQUARE, 5.0, "left", rho_min=3.0, safety=1.0, region=region)
    _check_lead(res, SQUARE, 5.0, 1.0, 3.0, region)


def test_optimal_lead_is_not_slower_than_sar_defaults_that_fit() -> None:
    res = optimal_lead((-20.0, -20.0, 10.0), SQUARE, 5.0, "left", rho_min=3.0, safety=1.0, feed_mm_s=20.0)
    base = compare_with_sar(res, SQUARE, __import__("trcopt.config", fromlist=["x"]).DEFAULT_MACHINE)
    assert [b.code for b in base] == ["G147", "G247", "G347"]
    for b in base:
        if b.gouge_mm <= 1e-6:
            assert res.time_s <= b.time_s * (1 + 1e-9), (b.code, res.time_s, b.time_s)


def test_start_too_close_is_an_error_naming_clearance() -> None:
    with pytest.raises(SolverError, match="binding constraint 'clearance'"):
        optimal_lead((-2.0, 20.0, 0.0), SQUARE, 5.0, "left", rho_min=3.0)


def test_start_behind_the_part_is_an_error_naming_clearance() -> None:
    with pytest.raises(SolverError, match="binding constraint 'clearance'"):
        optimal_lead((60.0, 60.0, 0.0), SQUARE, 5.0, "left", rho_min=3.0, safety=1.0)


@pytest.mark.slow
def test_too_narrow_region_is_an_error_naming_region() -> None:
    region = [(-8.5, -40.0), (-4.5, -40.0), (-4.5, 10.0), (-8.5, 10.0)]
    with pytest.raises(SolverError, match="binding constraint 'region'"):
        optimal_lead((-8.0, -2.0, 0.0), SQUARE, 5.0, "left", rho_min=3.0, region=region)


def test_non_convex_region_is_rejected() -> None:
    with pytest.raises(ValueError, match="convex"):
        optimal_lead((-20.0, -20.0, 0.0), SQUARE, 5.0, "left", region=[(0, 0), (10, 0), (5, 2), (10, 10), (0, 10)])


def test_sar_shaped_optimum_is_written_as_g147_and_replans_to_the_same_path() -> None:
    res = optimal_lead((-5.0, -30.0, 5.0), SQUARE, 5.0, "left", rho_min=3.0, feed_mm_s=20.0)
    assert res.sar is not None and res.sar.contour == "G147"
    assert res.sar.disr == pytest.approx(25.0, abs=1e-6) and res.sar.discl == pytest.approx(5.0)
    code = leadin_gcode(res)
    assert "G41 G147 G340 DISR=25 DISCL=5 X0 Y0 Z0" in code
    sar_block = next(ln for ln in code.splitlines() if "G147" in ln and not ln.startswith(";"))
    program = "\n".join(
        [
            "$TC_DP1[1,1]=120 $TC_DP6[1,1]=5",
            "N10 T1 D1 G17 G90 G0 X-5 Y-30 Z5",
            "N20 " + sar_block,
            "N30 G1 Y40",
            "N40 X40",
            "N50 Y0",
            "N60 X0",
            "N70 G40 X-20 Y-20",
            "M30",
        ]
    )
    planned = plan(program, file="lead.mpf", options=PlanOptions(timing=False))
    assert planned.ok, [d.format() for d in planned.diagnostics]
    approach = [s for s in planned.toolpath if s.role.value == "approach" and s.geometry.plane_length > 0]
    lead = res.elements[-1]
    assert math.dist(approach[-1].geometry.start, lead.start) <= 1e-9
    assert math.dist(approach[-1].geometry.end, lead.end) <= 1e-9


def test_explicit_moves_gcode_and_svg() -> None:
    res = optimal_lead((-20.0, -20.0, 10.0), SQUARE, 5.0, "left", rho_min=3.0, feed_mm_s=20.0)
    if res.sar is None:
        code = leadin_gcode(res)
        assert "G40" in code or "explicit" in code
        last = code.strip().splitlines()[-1]
        assert "X-5" in last and "Y0" in last
    svg = leadin_svg(res, SQUARE)
    assert svg.startswith("<svg") and "polyline" in svg


# ---- CLI ---------------------------------------------------------------------------------------


def _parser():
    ap = argparse.ArgumentParser(prog="trcopt")
    add_arguments(ap.add_subparsers().add_parser("leadin"))
    return ap


def test_cli_leadin_writes_outputs(tmp_path, capsys) -> None:
    args = _parser().parse_args(
        [
            "leadin",
            str(PROBLEMS / "ex02_square_g450.mpf"),
            "--rho-min",
            "3",
            "--json",
            str(tmp_path / "l.json"),
            "--gcode",
            str(tmp_path / "l.mpf"),
            "--svg",
            str(tmp_path / "l.svg"),
        ]
    )
    assert args.handler(args) == 0
    out = capsys.readouterr().out
    assert "optimal lead" in out and "G147" in out and "G247" in out and "G347" in out
    data = json.loads((tmp_path / "l.json").read_text())
    assert data["kind"] in ("line_arc", "poly") and len(data["baselines"]) == 3
    assert (tmp_path / "l.mpf").read_text().startswith("; optimal lead-in")


def test_cli_leadin_errors(tmp_path, capsys) -> None:
    ap = _parser()
    args = ap.parse_args(["leadin", str(tmp_path / "missing.mpf")])
    assert args.handler(args) == 2
    region = tmp_path / "r.txt"
    region.write_text("0 0\n1 0\n1 1\n0 1\n")
    args = ap.parse_args(["leadin", str(PROBLEMS / "ex02_square_g450.mpf"), "--region", str(region)])
    assert args.handler(args) == 1
    err = capsys.readouterr().err
    assert "binding constraint 'region'" in err and "Traceback" not in err
