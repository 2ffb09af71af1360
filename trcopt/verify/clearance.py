"""The distances of the no-gouge check: every compensated tool-centre segment against the
programmed part elements near it (:func:`clearance_distances`), for :func:`trcopt.verify.plan.verify_plan`."""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from typing import Any

import numpy as np

from trcopt.path import Role, Segment
from trcopt.verify.index import BoxGrid
from trcopt.verify.model import element_distance, line_pair_distances_uv
from trcopt.verify.pairs import arc_pair_distances
from trcopt.verify.table import LINE, OTHER, SegmentTable

__all__ = ["clearance_distances", "pair_distances", "QUERY_CHUNK", "PAIR_CHUNK"]

QUERY_CHUNK = 1 << 13  # tool segments whose candidates are gathered at once (bounded memory)
PAIR_CHUNK = 1 << 16  # pairs of lines measured at once


def clearance_distances(
    toolpath: Sequence[Segment],
    part: Sequence[Segment],
    grid: BoxGrid,
    roles: Collection[Role],
    tool: SegmentTable | None = None,
    part_table: SegmentTable | None = None,
) -> tuple[list[int], np.ndarray, np.ndarray, np.ndarray]:
    """For every compensated tool-centre segment (of ``roles``; their indices, ascending, are the
    first result), the exact distance to each programmed part element within R of its box: the
    pairs (tool segment, part element, distance) as three arrays, by tool segment and then by
    part element. The pairs of two lines all at once
    (:func:`~trcopt.verify.model.line_pair_distances_uv`), those of lines and arcs too
    (:func:`~trcopt.verify.pairs.arc_pair_distances`), the others one by one. ``tool`` and
    ``part_table``: the tables of ``toolpath`` and ``part`` (:mod:`trcopt.verify.table`), if
    already read."""
    empty = np.zeros(0, dtype=np.intp)
    if not part:
        return [], empty, empty, np.zeros(0)
    tool = SegmentTable(toolpath) if tool is None else tool
    part_table = SegmentTable(part) if part_table is None else part_table
    kk = np.nonzero((tool.radius > 0.0) & (tool.plen > 0.0) & tool.roles(*roles))[0].astype(np.intp)
    ks = kk.tolist()
    if not ks:
        return ks, empty, empty, np.zeros(0)
    boxes = tool.bboxes(kk)
    radii = tool.radius[kk]
    near_many = getattr(grid, "near_many", None)
    pk_parts, pi_parts = [empty], [empty]
    for a in range(0, len(ks), QUERY_CHUNK):
        if near_many is not None:
            q, i = near_many(boxes[a : a + QUERY_CHUNK], radii[a : a + QUERY_CHUNK])
        else:  # a grid without the batch query (a reference filter in the tests)
            found = [grid.near(tuple(boxes[j]), float(radii[j])) for j in range(a, min(a + QUERY_CHUNK, len(ks)))]
            q = np.repeat(np.arange(len(found)), [len(f) for f in found])
            i = np.concatenate([empty, *[np.asarray(f, dtype=np.intp) for f in found]])
        pk_parts.append(kk[a + q])
        pi_parts.append(i.astype(np.intp))
    pk, pi = np.concatenate(pk_parts), np.concatenate(pi_parts)
    dist = pair_distances(tool, part_table, pk, pi, lambda k: toolpath[k].geometry, lambda i: part[i].geometry)
    return ks, pk, pi, dist


def pair_distances(
    tool: SegmentTable, part_table: SegmentTable, pk: np.ndarray, pi: np.ndarray,
    tool_geometry: Callable[[int], Any], part_geometry: Callable[[int], Any],
) -> np.ndarray:
    """The exact distances of the pairs (row ``pk`` of ``tool``, row ``pi`` of ``part_table``):
    lines all at once, lines and arcs too, polynomial curves one by one (``tool_geometry``,
    ``part_geometry``: the geometry of a row)."""
    lines = (tool.kind[pk] == LINE) & (part_table.kind[pi] == LINE)
    dist = np.empty(len(pk))
    both = np.nonzero(lines)[0]
    for a in range(0, len(both), PAIR_CHUNK):  # in chunks: the temporaries stay small
        n = both[a : a + PAIR_CHUNK]
        k, i = pk[n], pi[n]
        t, p = tool, part_table
        dist[n] = line_pair_distances_uv(t.sx[k], t.sy[k], t.ex[k], t.ey[k], p.sx[i], p.sy[i], p.ex[i], p.ey[i])
    # pairs with an arc: all at once (the same values); polynomial curves one by one
    rest = np.nonzero(~lines)[0]
    simple = (tool.kind[pk[rest]] != OTHER) & (part_table.kind[pi[rest]] != OTHER) & (part_table.plen[pi[rest]] > 0.0)
    todo, one_by_one = rest[simple], [rest[~simple]]
    for a in range(0, len(todo), PAIR_CHUNK):
        n = todo[a : a + PAIR_CHUNK]
        d, ok = arc_pair_distances(tool, part_table, pk[n], pi[n])
        dist[n[ok]] = d[ok]
        one_by_one.append(n[~ok])
    for n in np.concatenate(one_by_one).tolist():
        dist[n] = element_distance(tool_geometry(int(pk[n])), part_geometry(int(pi[n])))[0]
    return dist
