"""The distances of the no-gouge check: every compensated tool-centre segment against the
programmed part elements near it (:func:`clearance_distances`), for :func:`trcopt.verify.plan.verify_plan`."""

from __future__ import annotations

from collections.abc import Collection, Sequence

import numpy as np

from trcopt.geometry import Line
from trcopt.path import Role, Segment
from trcopt.verify.index import BoxGrid
from trcopt.verify.model import bbox, element_distance, line_pair_distances

__all__ = ["clearance_distances"]


def clearance_distances(
    toolpath: Sequence[Segment], part: Sequence[Segment], grid: BoxGrid, roles: Collection[Role]
) -> dict[int, list[tuple[int, float]]]:
    """For every compensated tool-centre segment (of ``roles``), the exact distance to each programmed part
    element within R of its box: the pairs of two lines all at once
    (:func:`~trcopt.verify.model.line_pair_distances`), the others one by one."""
    out: dict[int, list[tuple[int, float]]] = {}
    if not part:
        return out
    pairs: list[tuple[int, int]] = []
    for k, seg in enumerate(toolpath):
        g = seg.geometry
        if seg.radius <= 0.0 or g.plane_length <= 0.0 or seg.role not in roles:
            continue
        out[k] = []
        pairs += [(k, int(i)) for i in grid.near(bbox(g), seg.radius)]
    lines = [
        n for n, (k, i) in enumerate(pairs)
        if isinstance(toolpath[k].geometry, Line) and isinstance(part[i].geometry, Line)
    ]  # fmt: skip
    dist = np.empty(len(pairs))
    if lines:
        ends = np.array(
            [(*toolpath[pairs[n][0]].geometry.start2, *toolpath[pairs[n][0]].geometry.end2,
              *part[pairs[n][1]].geometry.start2, *part[pairs[n][1]].geometry.end2) for n in lines]
        )  # fmt: skip
        dist[lines] = line_pair_distances(ends[:, 0:2], ends[:, 2:4], ends[:, 4:6], ends[:, 6:8])
    is_line = np.zeros(len(pairs), dtype=bool)
    is_line[lines] = True
    for n, (k, i) in enumerate(pairs):
        d = float(dist[n]) if is_line[n] else element_distance(toolpath[k].geometry, part[i].geometry)[0]
        out[k].append((i, d))
    return out
