"""The distances of the no-gouge check: every compensated tool-centre segment against the
programmed part elements near it (:func:`clearance_distances`), for :func:`trcopt.verify.plan.verify_plan`."""

from __future__ import annotations

from collections.abc import Collection, Sequence
from itertools import chain

import numpy as np

from trcopt.geometry import Line
from trcopt.path import Role, Segment
from trcopt.verify.index import BoxGrid
from trcopt.verify.model import bbox, element_distance, line_pair_distances

__all__ = ["clearance_distances", "QUERY_CHUNK", "PAIR_CHUNK"]

QUERY_CHUNK = 1 << 13  # tool segments whose candidates are gathered at once (bounded memory)
PAIR_CHUNK = 1 << 16  # pairs of lines measured at once


def _ends(segments: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """Plane start and end point of every line (n×4, NaN for the other elements) and which are lines."""
    is_line = np.fromiter((isinstance(s.geometry, Line) for s in segments), bool, len(segments))
    ends = np.full((len(segments), 4), np.nan)
    count = int(is_line.sum())
    if count:
        flat = chain.from_iterable(
            (s.geometry.start[0], s.geometry.start[1], s.geometry.end[0], s.geometry.end[1])
            for s, li in zip(segments, is_line.tolist(), strict=True)
            if li
        )
        ends[is_line] = np.fromiter(flat, float, 4 * count).reshape(count, 4)
    return ends, is_line


def clearance_distances(
    toolpath: Sequence[Segment], part: Sequence[Segment], grid: BoxGrid, roles: Collection[Role]
) -> tuple[list[int], np.ndarray, np.ndarray, np.ndarray]:
    """For every compensated tool-centre segment (of ``roles``; their indices, ascending, are the
    first result), the exact distance to each programmed part element within R of its box: the
    pairs (tool segment, part element, distance) as three arrays, by tool segment and then by
    part element. The pairs of two lines all at once
    (:func:`~trcopt.verify.model.line_pair_distances`), the others one by one."""
    empty = np.zeros(0, dtype=np.intp)
    if not part:
        return [], empty, empty, np.zeros(0)
    ks = [
        k for k, seg in enumerate(toolpath)
        if seg.radius > 0.0 and seg.geometry.plane_length > 0.0 and seg.role in roles
    ]  # fmt: skip
    if not ks:
        return ks, empty, empty, np.zeros(0)
    kk = np.array(ks, dtype=np.intp)
    boxes = np.fromiter(chain.from_iterable(bbox(toolpath[k].geometry) for k in ks), float, 4 * len(ks)).reshape(-1, 4)
    radii = np.array([toolpath[k].radius for k in ks], float)
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
    tool_ends, tool_line = _ends(toolpath)
    part_ends, part_line = _ends(part)
    lines = tool_line[pk] & part_line[pi]
    dist = np.empty(len(pk))
    both = np.nonzero(lines)[0]
    for a in range(0, len(both), PAIR_CHUNK):  # in chunks: the temporaries stay small
        n = both[a : a + PAIR_CHUNK]
        t, p = tool_ends[pk[n]], part_ends[pi[n]]
        dist[n] = line_pair_distances(t[:, 0:2], t[:, 2:4], p[:, 0:2], p[:, 2:4])
    for n in np.nonzero(~lines)[0].tolist():
        dist[n] = element_distance(toolpath[int(pk[n])].geometry, part[int(pi[n])].geometry)[0]
    return ks, pk, pi, dist
