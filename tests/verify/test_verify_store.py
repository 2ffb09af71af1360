"""The streaming verification's compact part: :class:`ProgramStore` gives back the tables and the
geometry of the programmed segments exactly (read in batches of any size), and
:class:`CompactGrid`, built a chunk of boxes at a time, is the same grid for every chunk size and
answers exactly the pairs of its ``float32`` boxes."""

from __future__ import annotations

import bisect
import math
import random

import numpy as np
import pytest

from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane
from trcopt.geometry.poly import conic_curve
from trcopt.path import Role, Segment
from trcopt.verify import store as store_module
from trcopt.verify.cellgrid import CompactGrid, outward
from trcopt.verify.store import ProgramStore
from trcopt.verify.table import _ARRAYS, SegmentTable


def _path(rng: random.Random, n: int) -> list[Segment]:
    """A chained path of lines, arcs (their computed start points are not the previous end
    points), curves, zero-length lines and rapids, several elements on some source lines and
    source lines skipped."""
    out, p, line = [], (0.0, 0.0, 0.0), 1
    for _ in range(n):
        pick = rng.random()
        z = p[2] if rng.random() < 0.8 else p[2] + rng.uniform(-1.0, 1.0)
        if pick < 0.45:
            q = (p[0] + rng.uniform(-5.0, 5.0), p[1] + rng.uniform(-5.0, 5.0), z)
            g = Line(p, q)
        elif pick < 0.55:
            g = Line(p, p)
        elif pick < 0.9:
            r, a0 = rng.uniform(0.5, 8.0), rng.uniform(-math.pi, math.pi)
            centre = (p[0] - r * math.cos(a0), p[1] - r * math.sin(a0))
            g = Arc(centre, r, a0, rng.uniform(0.1, 3.0) * rng.choice([1, -1]), p[2], z)
        else:
            q1 = (p[0] + rng.uniform(1.0, 4.0), p[1] + rng.uniform(-3.0, 3.0))
            q2 = (q1[0] + rng.uniform(1.0, 4.0), q1[1] + rng.uniform(-3.0, 3.0))
            g = conic_curve((p[0], p[1]), q1, q2, rng.uniform(0.5, 2.0), p[2])
        role = rng.choice([Role.CONTOUR, Role.CONTOUR, Role.CONTOUR, Role.RAPID, Role.APPROACH])
        line += rng.choice([0, 1, 1, 1, 3])
        out.append(Segment(g, Plane.G17, role, SourceSpan("t.ngc", line, 1, f"N{line}"), 10.0))
        p = g.end
    return out


def _bits(a: np.ndarray) -> np.ndarray:
    return np.asarray(a, float).view(np.int64)


@pytest.mark.parametrize("batch", [1, 3, 64, 1 << 12])
def test_store_gives_back_the_segments(monkeypatch: pytest.MonkeyPatch, batch: int) -> None:
    monkeypatch.setattr(store_module, "BATCH", batch)
    rng = random.Random(batch)
    segs = _path(rng, 300)
    store = ProgramStore(iter(segs))
    ref = SegmentTable(segs)
    assert store.n == len(segs) and store.monotone
    for rows in (np.arange(len(segs)), np.sort(rng.sample(range(len(segs)), 40)), np.array([len(segs) - 1])):
        got = store.table(rows)
        for c in _ARRAYS:
            if c in ("radius", "side"):
                continue
            assert np.array_equal(_bits(getattr(got, c)), _bits(getattr(ref, c)[rows])), c
        assert got.line.dtype == np.int64
        assert np.array_equal(_bits(got.bboxes(np.arange(len(rows)))), _bits(ref.bboxes(rows)))
    for j, s in enumerate(segs):
        assert store.geometry(j) == s.geometry
        for got_end, ref_end in ((store.ex, ref.ex), (store.ey, ref.ey), (store.ez, ref.ez)):
            assert float(got_end[j]).hex() == float(ref_end[j]).hex()
    # the part candidates and their boxes, the source lines of the candidates and of the continuations
    star = np.isin(ref.role, store_module._PART_ROLES) & (ref.plen > 0.0)
    assert np.array_equal(store.star, star) and 0 < star.sum() < len(segs)
    assert np.array_equal(store.boxes, outward(ref.bboxes(np.nonzero(star)[0])))
    lines = ref.line
    top = int(lines[-1])
    for lo, hi in ((lines[0], top), (lines[50], lines[120]), (lines[7], lines[7]), (top + 1, top + 9), (-5, 0)):
        want = sorted(set(lines[store.star & (lines >= lo) & (lines <= hi)].tolist()))
        assert store.star_lines(int(lo), int(hi)).tolist() == want
    sel = (ref.plen > 0.0) & (ref.kind <= 1)
    for line in [0, *lines.tolist()[::7], int(lines[-1])]:
        after = lines[sel & (lines > line)]
        assert store.next_line(line) == (int(after.min()) if after.size else -1)


def _boxes(rng: random.Random, n: int) -> np.ndarray:
    """Small boxes along two distant strokes, points, a few long ones (over many cells) and
    repeated boxes."""
    out = []
    for k in range(n):
        t = rng.uniform(0.0, 2.0 * math.pi)
        if k % 2:
            u, v = 500.0 + 80.0 * math.cos(t), -300.0 + 50.0 * math.sin(3 * t)
        else:
            u, v = -200.0 + 30.0 * t, 40.0 * math.sin(t)
        w, h = rng.choice([0.0, rng.uniform(0.0, 1.5)]), rng.uniform(0.0, 1.5)
        out.append((u, v, u + w, v + h))
    for _ in range(5):
        u, v = rng.uniform(-200.0, 500.0), rng.uniform(-300.0, 40.0)
        out.append((u, v, u + rng.uniform(150.0, 400.0), v + rng.uniform(0.0, 30.0)))
    out += out[:7]
    rng.shuffle(out)
    return np.array(out, float)


def _cells(grid: CompactGrid, max_cells: int) -> tuple[list[int], list[tuple[int, int]]]:
    """The big boxes and the (cell, box) pairs of the grid, one box at a time."""
    big, pairs = [], []
    for j, b in enumerate(grid.boxes.astype(float).tolist()):
        ix0, ix1 = (int(grid._index(np.array([x]), grid.origin[0], grid.nx)[0]) for x in (b[0], b[2]))
        iy0, iy1 = (int(grid._index(np.array([y]), grid.origin[1], grid.ny)[0]) for y in (b[1], b[3]))
        if (ix1 - ix0 + 1) * (iy1 - iy0 + 1) > max_cells:
            big.append(j)
            continue
        pairs += [(ix * grid.ny + iy, j) for ix in range(ix0, ix1 + 1) for iy in range(iy0, iy1 + 1)]
    return big, sorted(pairs)


@pytest.mark.parametrize("margin", [0.0, 2.5])
def test_compact_grid_is_the_same_for_every_chunk(margin: float) -> None:
    rng = random.Random(11)
    boxes = _boxes(rng, 1500)
    ids = np.array(rng.sample(range(10**6), len(boxes)))
    one = CompactGrid(boxes, ids, margin, max_cells=16, chunk=len(boxes))
    big, pairs = _cells(one, 16)
    assert one._big.tolist() == big and len(big) >= 5
    keys = [k for k, _ in pairs]
    assert one._cells_ids.tolist() == [j for _, j in pairs]
    assert one._keys.tolist() == sorted(set(keys))
    assert one._starts.tolist() == [bisect.bisect_left(keys, k) for k in sorted(set(keys))] + [len(keys)]
    queries = _boxes(rng, 300)
    margins = np.array([rng.choice([0.0, 0.3, 4.0, 60.0]) for _ in queries])
    q_one, i_one = one.near_many(queries, margins)
    # exactly the pairs of the float32 boxes (every box within the margin, by the same comparisons)
    b = one.boxes.astype(float)
    lo_u, lo_v = queries[:, 0] - margins, queries[:, 1] - margins
    hi_u, hi_v = queries[:, 2] + margins, queries[:, 3] + margins
    hit = (b[None, :, 0] <= hi_u[:, None]) & (b[None, :, 2] >= lo_u[:, None])
    hit &= (b[None, :, 1] <= hi_v[:, None]) & (b[None, :, 3] >= lo_v[:, None])
    qq, jj = np.nonzero(hit)
    assert q_one.tolist() == qq.tolist() and i_one.tolist() == ids[jj].tolist()
    assert len(q_one) > len(queries)
    for chunk in (1, 7, 100, 1000):
        grid = CompactGrid(boxes, ids, margin, max_cells=16, chunk=chunk)
        for name in ("boxes", "ids", "_big", "_cells_ids", "_keys", "_starts"):
            assert np.array_equal(getattr(grid, name), getattr(one, name)), (chunk, name)
        assert (grid.cell, grid.origin, grid.nx, grid.ny, grid.extent()) == (one.cell, one.origin, one.nx, one.ny,
                                                                            one.extent())  # fmt: skip
        q, i = grid.near_many(queries, margins)
        assert np.array_equal(q, q_one) and np.array_equal(i, i_one)
    # boxes already rounded outwards are taken as they are
    same = CompactGrid(one.boxes, ids, margin, max_cells=16, chunk=64)
    assert same.boxes is one.boxes or np.shares_memory(same.boxes, one.boxes)
    assert np.array_equal(same._cells_ids, one._cells_ids)


def test_compact_grid_of_no_boxes() -> None:
    grid = CompactGrid(np.zeros((0, 4)), np.zeros(0, np.int64), 1.0)
    q, i = grid.near_many(np.array([[0.0, 0.0, 1.0, 1.0]]), np.array([1.0]))
    assert q.size == 0 and i.size == 0 and grid.extent() == 0.0
