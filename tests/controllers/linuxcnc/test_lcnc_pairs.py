"""Acceptance against LinuxCNC's own outputs: the programmed/compensated pairs of
``shared/peer_cases/linuxcnc/pairs.json`` (README there).

* ``clearance_ok`` pairs: the ``linuxcnc`` profile reproduces LinuxCNC's tool-centre path element
  by element (kind, end points, arc centres, rotation) within 2e-4 program units;
* the other pairs (LinuxCNC gouges there: it only looks at neighbours): the Siemens engine with
  CDON must not gouge, checked with the independent distance check of ``tests/gouge.py``.
"""

from __future__ import annotations

import json
import math
import sys
from functools import lru_cache
from pathlib import Path

import pytest

from trcopt.compensation import compensate
from trcopt.controllers.linuxcnc.compensation import compensate_linuxcnc
from trcopt.errors import Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.modes import CollisionMode, Side
from trcopt.nc.model import CompState, Move, MoveKind
from trcopt.path import Segment

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from gouge import gouges  # noqa: E402

PEER = Path(__file__).resolve().parents[3] / ".." / "shared" / "peer_cases" / "linuxcnc"
TOL = 2e-4  # program units
_PLANES = {"XY": Plane.G17, "XZ": Plane.G18}
_UNIT_MM = {"inch": 25.4, "mm": 1.0}


@lru_cache(maxsize=1)
def load_pairs() -> list[dict]:
    path = PEER / "pairs.json"
    if not path.is_file():
        return []
    return json.loads(path.read_text())


def _pair_ids() -> list[tuple[int, bool]]:
    return [(i, bool(p["clearance_ok"])) for i, p in enumerate(load_pairs())]


needs_peer = pytest.mark.skipif(
    not (PEER / "pairs.json").is_file(), reason=f"LinuxCNC peer data not found at {PEER.resolve()}"
)


def _xyz(p: list[float | None], fallback: list[float], k: float) -> tuple[float, float, float]:
    return tuple(k * (v if v is not None else f) for v, f in zip(p, fallback, strict=True))  # type: ignore[return-value]


def pair_moves(pair: dict, collision: CollisionMode = CollisionMode.CDOF) -> list[Move]:
    """Canonical moves (mm) of a pair's programmed path with the pair's side and radius."""
    k = _UNIT_MM[pair["units"]]
    plane = _PLANES[pair["plane"]]
    side = Side.LEFT if pair["side"] == "left" else Side.RIGHT
    radius = pair["radius"] * k
    prog = pair["programmed"]
    moves = []
    for part in ("pre", "entry", "contour", "exit", "post"):
        for _n, s in enumerate(prog[part]):
            if part in ("entry", "contour"):
                comp = CompState(
                    side, radius, True, collision=collision, side_programmed=(part == "entry")
                )
            else:
                comp = CompState(
                    Side.OFF, 0.0, True, collision=collision, side_programmed=(part == "exit")
                )
            start, end = _xyz(s["start"], s["start"], k), _xyz(s["end"], s["end"], k)
            span = SourceSpan("pair", int(s["line"]), 1)
            if s["type"] == "arc":
                rot = int(s["rotation"])
                moves.append(
                    Move(
                        MoveKind.ARC,
                        start,
                        end,
                        plane,
                        span,
                        comp,
                        1.0,
                        center=_xyz(s["center"], s["start"], k),
                        ccw=rot > 0,
                        turns=abs(rot) - 1,
                    )
                )
            else:
                kind = MoveKind.RAPID if s["type"] == "rapid" else MoveKind.LINE
                moves.append(
                    Move(
                        kind, start, end, plane, span, comp, None if kind is MoveKind.RAPID else 1.0
                    )
                )
    return moves


def expected_segments(pair: dict) -> list[dict]:
    exp = pair["expected"]
    return [s for part in ("pre", "entry", "contour", "exit", "post") for s in exp[part]]


def segment_deviation(seg: Segment, exp: dict, k: float) -> float:
    """Largest coordinate difference (program units) between one of our segments and one
    LinuxCNC canon segment; inf when kind or rotation differ."""
    kind = "arc" if seg.kind == "arc" else "line"
    if kind != ("arc" if exp["type"] == "arc" else "line"):
        return math.inf
    dev = 0.0
    for ours, theirs in ((seg.start_xyz, exp["start"]), (seg.end_xyz, exp["end"])):
        dev = max(dev, max(abs(a / k - b) for a, b in zip(ours, theirs, strict=True)))
    if kind == "arc":
        g = seg.geometry
        rot = int(exp["rotation"])
        turns = math.floor(abs(g.sweep) / (2 * math.pi) + 1e-9)  # type: ignore[union-attr]
        if (
            (g.sweep > 0) != (rot > 0)
            or turns != abs(rot) - 1
            and abs(abs(g.sweep) - 2 * math.pi * turns) > 1e-6
        ):  # type: ignore[union-attr]
            return math.inf
        c = seg.center_xyz
        assert c is not None
        u, v, _ = seg.plane.axes
        dev = max(dev, abs(c[u] / k - exp["center"][u]), abs(c[v] / k - exp["center"][v]))
    return dev


def compare_pair(pair: dict) -> tuple[float, str]:
    """(worst deviation in program units, description of the first mismatch)."""
    k = _UNIT_MM[pair["units"]]
    diags: list = []
    ours = list(compensate_linuxcnc(pair_moves(pair), None, diags))
    errors = [d for d in diags if d.severity is Severity.ERROR]
    if errors:
        return math.inf, f"alarm {errors[0].code}: {errors[0].message}"
    exp = expected_segments(pair)
    if len(ours) != len(exp):
        return math.inf, f"{len(ours)} segments, LinuxCNC has {len(exp)}"
    worst, where = 0.0, ""
    for i, (s, e) in enumerate(zip(ours, exp, strict=True)):
        d = segment_deviation(s, e, k)
        if d > worst:
            worst, where = d, f"element {i} (line {e['line']}, {e['type']})"
    return worst, where


@needs_peer
@pytest.mark.parametrize("index", [i for i, ok in _pair_ids() if ok] or [0])
def test_linuxcnc_profile_reproduces_linuxcnc(index: int) -> None:
    pair = load_pairs()[index]
    worst, where = compare_pair(pair)
    assert worst <= TOL, f"{pair['source']} group {pair['group']}: deviation {worst} at {where}"


# crazy-paths group 50: the open contour's last arc (line 575) ends 0.31 mm from the outside corner
# between lines 573 and 574 (r = 0.25 mm). No two tool-centre elements intersect there, so collision
# detection by offset intersections (what CDON is, R26) cannot see it: the tool going round that
# corner passes 0.065 mm from the arc. A SINUMERIK control gouges the same way.
_SIEMENS_SLIVER = {("interp-crazy-paths", 50)}


def _self_crossings(moves: list[Move]) -> list[tuple[int, int]]:
    """Pairs of non-adjacent programmed elements (entry + contour) that meet or cross."""
    from trcopt.geometry import bounded_intersections

    segs = _programmed([m for m in moves if m.comp.side is not Side.OFF])
    return [
        (i, j)
        for i in range(len(segs))
        for j in range(i + 2, len(segs))
        if bounded_intersections(segs[i].geometry, segs[j].geometry)
    ]


@needs_peer
@pytest.mark.parametrize("index", [i for i, ok in _pair_ids() if not ok] or [0])
def test_siemens_cdon_does_not_gouge_where_linuxcnc_does(index: int) -> None:
    pair = load_pairs()[index]
    key = (pair["source"].split("/")[-2], pair["group"])
    if key in _SIEMENS_SLIVER:
        pytest.xfail(
            "the contour's open end passes 0.31 mm from an outside corner; no offset intersection "
            "exists for CDON (R26) to find"
        )
    moves = pair_moves(pair, CollisionMode.CDON)
    diags: list = []
    toolpath = list(compensate(moves, None, diags))
    assert toolpath
    assert not any(d.severity is Severity.ERROR for d in diags), [d.format() for d in diags]
    found = gouges(_programmed(moves), toolpath)
    if found and _self_crossings(moves):
        pytest.skip(
            f"{key}: the programmed contour meets or crosses itself {_self_crossings(moves)[:2]}; "
            "no tool path keeps r from every element"
        )
    assert not found, f"{pair['source']} group {pair['group']}: {found[:3]}"


def _programmed(moves: list[Move]) -> list[Segment]:
    from trcopt.compensation import programmed_segment

    return [s for s in (programmed_segment(m) for m in moves) if s is not None]


@needs_peer
def test_pair_summary() -> None:
    """All clearance_ok pairs match; prints the count and the worst deviation."""
    results = [(p, compare_pair(p)) for p in load_pairs() if p["clearance_ok"]]
    matched = [w for _, (w, _) in results if w <= TOL]
    worst = max(w for _, (w, _) in results)
    print(
        f"\nLinuxCNC pairs matched: {len(matched)}/{len(results)}, worst deviation {worst:.3g} program units"
    )
    assert len(matched) == len(results) == 52
