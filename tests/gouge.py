"""An independent no-gouge check, written separately from the engine.

It samples every tool-centre segment densely and measures, with its own closed-form distance
functions, the distance to every programmed contour element in force while compensation is on —
except the lead-in and lead-out blocks around a closed contour (CAM output): in each chain of
connected compensated elements that contains a closed loop, only the widest loop is the part.
"""

from __future__ import annotations

import math

import numpy as np

from trcopt.path import Role, Segment


def _line_distance(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = b - a
    dd = float(d @ d)
    if dd == 0.0:
        return np.linalg.norm(pts - a, axis=1)
    t = np.clip((pts - a) @ d / dd, 0.0, 1.0)
    return np.linalg.norm(pts - (a + t[:, None] * d), axis=1)


def _arc_distance(pts: np.ndarray, c: np.ndarray, r: float, a0: float, sweep: float) -> np.ndarray:
    rel = pts - c
    ang = np.arctan2(rel[:, 1], rel[:, 0])
    if sweep >= 0:
        d = np.mod(ang - a0, 2 * math.pi)
    else:
        d = np.mod(a0 - ang, 2 * math.pi)
    inside = d <= abs(sweep) + 1e-12
    radial = np.abs(np.linalg.norm(rel, axis=1) - r)
    p_start = c + r * np.array([math.cos(a0), math.sin(a0)])
    p_end = c + r * np.array([math.cos(a0 + sweep), math.sin(a0 + sweep)])
    ends = np.minimum(np.linalg.norm(pts - p_start, axis=1), np.linalg.norm(pts - p_end, axis=1))
    return np.where(inside, radial, ends)


def _element_distance(pts: np.ndarray, seg: Segment) -> np.ndarray:
    g = seg.geometry
    if hasattr(g, "sweep"):
        return _arc_distance(pts, np.array(g.center, float), g.radius, g.a0, g.sweep)
    a = np.array(g.start[:2], float)
    b = np.array(g.end[:2], float)
    return _line_distance(pts, a, b)


def _samples(seg: Segment, step: float = 0.05) -> np.ndarray:
    g = seg.geometry
    n = max(8, int(math.ceil(g.length / step)) + 1)
    return np.array([g.point(s)[:2] for s in np.linspace(0.0, g.length, n)])


def _without_leads(contour: list[Segment], tol: float = 1e-6) -> list[Segment]:
    """The elements of the widest closed loop of each connected chain (the whole chain if open)."""
    chains: list[list[Segment]] = []
    for p in contour:
        if chains and math.dist(chains[-1][-1].geometry.end[:2], p.geometry.start[:2]) <= tol:
            chains[-1].append(p)
        else:
            chains.append([p])
    out = []
    for chain in chains:
        loop = None
        for i, a in enumerate(chain):
            start = a.geometry.start[:2]
            closing = [j for j in range(i, len(chain)) if math.dist(chain[j].geometry.end[:2], start) <= tol]
            if closing:
                loop = (i, closing[-1])
                break
        out.extend(chain if loop is None else chain[loop[0] : loop[1] + 1])
    return out


def gouges(programmed: list[Segment], toolpath: list[Segment], tol: float = 1e-6) -> list[tuple]:
    """(segment index, block, worst distance, radius) for every tool-centre segment that comes
    closer than radius − tol to a programmed contour element of a compensated block."""
    blocks_on = {s.span.line for s in toolpath if s.radius > 0 and s.role in (Role.CONTOUR, Role.CORNER)}
    contour = _without_leads([
        p for p in programmed
        if p.span.line in blocks_on and p.role is Role.CONTOUR and p.geometry.plane_length > 0
    ])
    out = []
    for k, seg in enumerate(toolpath):
        if seg.radius <= 0 or seg.role not in (Role.CONTOUR, Role.CORNER) or seg.geometry.plane_length <= 0:
            continue
        pts = _samples(seg)
        worst = min(float(_element_distance(pts, p).min()) for p in contour) if contour else math.inf
        if worst < seg.radius - tol:
            out.append((k, seg.span.block, worst, seg.radius))
    return out
