"""The indexed verification: the grid gives the brute-force candidates, so the residuals are
identical; lead blocks are not part contour; a failed family is a VERIFY-… diagnostic."""

from __future__ import annotations

import json
import math
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
from gouge import gouges
from hypothesis import given, settings
from hypothesis import strategies as st
from test_verify_plan import elements

from trcopt.cli import main as cli_main
from trcopt.codes import Code
from trcopt.errors import Severity, SourceSpan
from trcopt.geometry import Plane
from trcopt.modes import Side
from trcopt.path import Role, Segment
from trcopt.pipeline import PlanOptions, plan, plan_file
from trcopt.verify import plan as verify_module
from trcopt.verify import verify_plan
from trcopt.verify.contour import contour_blocks, part_contour
from trcopt.verify.index import MAX_CELLS_PER_BOX, BoxGrid

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"
CAM_PLATE = PROBLEMS / "siemens" / "ex13_cam_plate_leads.mpf"
GOLDEN = sorted(p for p in PROBLEMS.glob("*/*.expected.json"))
VERIFY_CODES = {c for c in Code if c.value.startswith("VERIFY-")}

# two square bosses 4 mm apart, each with its own G41 contour: the tool (R = 3) running around the
# second cuts 2 mm into the first (a genuine gouge the compensation cannot see)
TWO_BOSSES = """; two bosses 4 mm apart
$TC_DP1[1,1]=120 $TC_DP6[1,1]=3
N10 G17 G90 T1 D1 G0 X-10 Y-10 Z0
N20 G1 G41 X0 Y0 F500
N30 X0 Y20
N40 X20 Y20
N50 X20 Y0
N60 X0 Y0
N70 G40 X-10 Y-10
N80 G0 X24 Y-10
N90 G1 G41 X24 Y0
N100 X24 Y20
N110 X44 Y20
N120 X44 Y0
N130 X24 Y0
N140 G40 X24 Y-10
N150 M30
"""


class BruteForce:
    """The reference candidate filter: every box (vertex) for every query."""

    def __init__(self, boxes: np.ndarray) -> None:
        self.boxes = np.asarray(boxes, float).reshape(-1, 4)

    def near(self, box: tuple[float, float, float, float], margin: float) -> np.ndarray:
        b = self.boxes
        return np.nonzero(
            (b[:, 0] <= box[2] + margin)
            & (b[:, 2] >= box[0] - margin)
            & (b[:, 1] <= box[3] + margin)
            & (b[:, 3] >= box[1] - margin)
        )[0]

    def nearest_distance(self, p: tuple[float, float]) -> float:
        if len(self.boxes) == 0:
            return math.inf
        return float(np.min(np.hypot(self.boxes[:, 0] - p[0], self.boxes[:, 1] - p[1])))


def _both(programmed, toolpath, moves=None):
    indexed = verify_plan(programmed, toolpath, moves)
    with mock.patch.object(verify_module, "BoxGrid", BruteForce):
        brute = verify_plan(programmed, toolpath, moves)
    return indexed, brute


# ---- the grid itself ------------------------------------------------------------------------



coord = st.floats(-50, 50, allow_nan=False)


@st.composite
def boxes(draw):
    n = draw(st.integers(0, 60))
    rows = []
    for _ in range(n):
        u, v = draw(coord), draw(coord)
        # mostly small boxes, some degenerate, some spanning the whole field (the big list)
        w = draw(st.sampled_from([0.0, 0.5, 2.0, 5.0, 100.0]))
        h = draw(st.sampled_from([0.0, 0.5, 2.0, 5.0, 100.0]))
        rows.append([u, v, u + w, v + h])
    return np.array(rows, float).reshape(-1, 4)


@settings(max_examples=80, deadline=None)
@given(boxes(), st.lists(st.tuples(coord, coord, st.floats(0, 10), st.floats(0, 10)), min_size=1, max_size=10),
       st.floats(0.0, 8.0))
def test_grid_candidates_equal_brute_force(b, queries, margin) -> None:
    grid, brute = BoxGrid(b), BruteForce(b)
    for u, v, w, h in queries:
        q = (u, v, u + w, v + h)
        assert grid.near(q, margin).tolist() == sorted(brute.near(q, margin).tolist())
        p = (u, v)
        assert grid.nearest_distance(p) == brute.nearest_distance(p)


def test_big_boxes_are_not_copied_into_every_cell() -> None:
    rng = np.random.default_rng(1)
    small = rng.uniform(0, 100, (500, 2))
    b = np.vstack([np.hstack([small, small + 0.5]), [[0.0, 0.0, 100.0, 100.0]]])
    grid = BoxGrid(b)
    assert grid.nx * grid.ny > MAX_CELLS_PER_BOX
    assert grid._big.tolist() == [500]
    assert len(grid._ids) <= 4 * 500


# ---- verification: indexed == brute force ---------------------------------------------------


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(elements(50.0), elements(50.0), st.sampled_from([Role.CONTOUR, Role.CORNER])), min_size=1,
                max_size=25), st.floats(0.5, 6.0))
def test_random_paths_give_identical_residuals(pairs, radius) -> None:
    programmed, toolpath = [], []
    for k, (prog, tool, role) in enumerate(pairs):
        span = SourceSpan("random.mpf", k + 1, 1, f"N{k + 1}")
        programmed.append(Segment(prog, Plane.G17, Role.CONTOUR, span, 10.0))
        toolpath.append(Segment(tool, Plane.G17, role, span, 10.0, Side.LEFT, radius))
    indexed, brute = _both(programmed, toolpath)
    assert indexed.to_json() == brute.to_json()


@pytest.mark.parametrize("expected", GOLDEN, ids=[p.name.split(".")[0] for p in GOLDEN])
def test_golden_paths_give_identical_residuals(expected: Path) -> None:
    stem = expected.with_suffix("").with_suffix("")
    program = next(stem.with_suffix(s) for s in (".mpf", ".spf", ".h", ".ngc") if stem.with_suffix(s).exists())
    r = plan_file(program, PlanOptions(timing=False, verify=False))
    indexed, brute = _both(r.programmed, r.toolpath, r.nc.moves)
    assert indexed.to_json() == brute.to_json()


def test_long_wavy_contour_gives_identical_residuals() -> None:
    n = 600
    lines = ["$TC_DP1[1,1]=120 $TC_DP6[1,1]=2", "N1 G17 G90 T1 D1 G0 X150 Y-20 Z0", "N2 G1 G42 G450 X100 Y0 F500"]
    for i in range(1, n + 1):
        a = 2 * math.pi * i / n
        r = 100 + 5 * math.sin(7 * a)
        lines.append(f"N{i + 2} X{r * math.cos(a):.4f} Y{r * math.sin(a):.4f}")
    lines.append("G40 X150 Y0")
    res = plan("\n".join(lines), options=PlanOptions(timing=False, verify=False))
    indexed, brute = _both(res.programmed, res.toolpath)
    assert indexed.to_json() == brute.to_json()
    assert indexed.families["clearance"].checks >= n


# ---- part contour and leads -----------------------------------------------------------------


def test_cam_lead_blocks_are_not_part_contour() -> None:
    r = plan_file(CAM_PLATE, PlanOptions(timing=False))
    blocks = contour_blocks(r.programmed, r.toolpath)
    leads = {p.span.block for p in blocks.compensated if p.span.line in blocks.lead_lines}
    assert leads == {"N40", "N110", "N120"}
    assert {p.span.block for p in part_contour(r.programmed, r.toolpath)} == {
        "N50", "N60", "N70", "N80", "N90", "N100"
    }
    rep = r.verification
    assert rep.ok and rep.max_residual("clearance") <= 1e-9 and rep.families["clearance"].checks > 0
    # the lead segments are still measured (informationally) against the part contour
    assert rep.max_residual("lead_clearance") <= 1e-9 and rep.families["lead_clearance"].checks >= 5
    assert not [d for d in r.diagnostics if d.code in VERIFY_CODES]
    assert r.ok and "— ok" in r.summary() and "0 alarm(s), 0 warning(s)" in r.summary()


def test_cam_plate_exits_0_on_the_command_line(capsys) -> None:
    assert cli_main(["plan", "--no-timing", str(CAM_PLATE)]) == 0
    assert cli_main(["check", "--strict", str(CAM_PLATE)]) == 0
    out = capsys.readouterr().out
    assert "VERIFY-" not in out


def _polyline_pocket(sides: int = 120) -> str:
    """A CAM-style polygon pocket (``sides`` chords on a circle R 25, G41 inside, R = 3) entered at
    the middle M of its edge on the X axis by a lead-in arc of radius 5 tangent to that edge, left
    by a lead-out arc the same way."""
    m = 25.0 * math.cos(math.pi / sides)
    out = [
        "$TC_DP1[1,1]=120 $TC_DP6[1,1]=3",
        f"N10 G17 G90 T1 D1 G0 X{m - 15:.6f} Y-10 Z0",
        f"N20 G1 G41 X{m - 5:.6f} Y-5 F500",
        f"N30 G3 X{m:.6f} Y0 CR=5",
    ]
    for k in range(sides):
        a = (k + 0.5) * 2 * math.pi / sides
        out.append(f"G1 X{25 * math.cos(a):.6f} Y{25 * math.sin(a):.6f}")
    out += [f"G1 X{m:.6f} Y0", f"G3 X{m - 5:.6f} Y5 CR=5", f"G1 G40 X{m - 15:.6f} Y0", "M30"]
    return "\n".join(out) + "\n"


def test_polyline_pocket_with_leads_plans_without_warnings() -> None:
    r = plan(_polyline_pocket(), file="pocket.mpf", options=PlanOptions(timing=False))
    blocks = contour_blocks(r.programmed, r.toolpath)
    assert len(blocks.lead_lines) == 2  # the two arcs
    assert r.ok and r.verification.ok, r.summary()
    assert [d for d in r.diagnostics if d.severity is not Severity.INFO] == []
    # the independent check, with its own reading of the leads, agrees: no gouge
    assert gouges(r.programmed, r.toolpath) == []


def test_open_profiles_have_no_leads() -> None:
    # an open profile starting with an arc: everything is part contour
    src = """$TC_DP1[1,1]=120 $TC_DP6[1,1]=3
N10 G17 G90 T1 D1 G0 X30 Y-20 Z0
N20 G1 G41 X30 Y-10 F500
N30 G3 X20 Y0 CR=10
N40 G1 X0 Y0
N50 X0 Y30
N60 G40 X-10 Y40
N70 M30
"""
    r = plan(src, options=PlanOptions(timing=False))
    blocks = contour_blocks(r.programmed, r.toolpath)
    assert blocks.lead_lines == frozenset()
    assert blocks.part == blocks.compensated
    assert {p.span.block for p in blocks.part} == {"N30", "N40", "N50"}


# ---- a failed check is a diagnostic ---------------------------------------------------------


def test_gouge_is_a_warning_and_an_error_under_strict() -> None:
    r = plan(TWO_BOSSES, file="two.mpf", options=PlanOptions(timing=False))
    verify = [d for d in r.diagnostics if d.code in VERIFY_CODES]
    assert [(d.severity, d.code, d.span.block, d.span.line) for d in verify] == [
        (Severity.WARNING, Code.VERIFY_CLEARANCE, "N50", 7)
    ]
    assert "clearance residual 2 mm" in verify[0].message
    assert r.ok and not r.verification.ok
    assert "FAILED: clearance violated by 2 mm" in r.summary()
    assert "0 alarm(s), 1 warning(s)" in r.summary()
    assert r.to_json()["ok"] is True and r.to_json()["verification"]["ok"] is False

    s = plan(TWO_BOSSES, file="two.mpf", options=PlanOptions(timing=False, strict=True))
    errors = [(d.severity, d.code, d.span.block) for d in s.errors]
    assert errors == [(Severity.ERROR, Code.VERIFY_CLEARANCE, "N50")]
    assert not s.ok and s.to_json()["ok"] is False
    assert "1 alarm(s), 0 warning(s) — the verification failed (strict)" in s.summary()


def test_cli_exit_code_agrees_with_the_verification(tmp_path, capsys) -> None:
    prog = tmp_path / "two.mpf"
    prog.write_text(TWO_BOSSES)
    out_json = tmp_path / "plan.json"
    assert cli_main(["plan", "--no-timing", "--json", str(out_json), str(prog)]) == 0
    assert json.loads(out_json.read_text())["ok"] is True
    assert cli_main(["plan", "--no-timing", "--strict", "--json", str(out_json), str(prog)]) == 1
    data = json.loads(out_json.read_text())
    assert data["ok"] is False and data["verification"]["ok"] is False
    assert [d["code"] for d in data["diagnostics"] if d["severity"] == "error"] == ["VERIFY-CLEARANCE"]
    assert cli_main(["check", str(prog)]) == 0
    assert cli_main(["check", "--strict", str(prog)]) == 1
    captured = capsys.readouterr()
    assert "warning VERIFY-CLEARANCE (N50)" in captured.out
    assert "error VERIFY-CLEARANCE (N50)" in captured.err


def test_every_model_family_has_a_code() -> None:
    assert set(verify_module.FAMILY_CODES) == set(verify_module.FAMILIES) - set(verify_module.INFORMATIONAL)
    assert set(verify_module.FAMILY_CODES.values()) == VERIFY_CODES


@settings(max_examples=80, deadline=None)
@given(boxes(), st.lists(st.tuples(coord, coord, st.floats(0, 10), st.floats(0, 10), st.floats(0.0, 8.0)),
                         min_size=1, max_size=12),
       st.sampled_from([None, 0.5, 3.0]))
def test_batch_queries_equal_single_queries(b, queries, margin_hint) -> None:
    # BoxGrid.near_many (the verification's batch query) gives every query exactly near()'s
    # candidates, in order, whatever cell size the grid is built with
    grid, brute = BoxGrid(b, margin=margin_hint), BruteForce(b)
    qb = np.array([(u, v, u + w, v + h) for u, v, w, h, _ in queries], float)
    margins = np.array([m for *_, m in queries], float)
    q, i = grid.near_many(qb, margins)
    for n, row in enumerate(qb):
        expected = sorted(brute.near(tuple(row), float(margins[n])).tolist())
        assert i[q == n].tolist() == expected
        assert grid.near(tuple(row), float(margins[n])).tolist() == expected
