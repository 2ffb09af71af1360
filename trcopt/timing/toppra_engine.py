"""toppra on the exact section path: the engine for general geometry (Poly curves) and fallback.

Settings follow spec timing.md §0–§1.2: explicit grid with every knot and a point just before each
knot, ``seidel`` solver, per-axis velocity limits combined with the feed as a varying velocity
constraint, per-axis acceleration limits, ``compute_parameterization(0, 0)`` on each section (the
ends of a section are tangent discontinuities or the path ends, so the speed is zero there), and
the const-acceleration reading of the result (``ParametrizeConstAccel``'s model, which follows the
path exactly). toppra is imported here only, inside the function.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from trcopt.codes import Code
from trcopt.errors import TimingError
from trcopt.modes import TimingEngine
from trcopt.path import Segment
from trcopt.timing.grid import KNOT_EPS_MM, segment_grid
from trcopt.timing.path import SectionPath
from trcopt.timing.sections import Section

__all__ = ["section_grid_toppra", "solve_section_toppra", "CURVED_ACC_MARGIN"]

CURVED_ACC_MARGIN = 0.9985


def section_grid_toppra(path: SectionPath, feeds: np.ndarray, amin: float) -> np.ndarray:
    """Grid of a section for toppra: the adaptive segment grids plus ``s_k − ε`` before knots."""
    parts = []
    for k, ev in enumerate(path.evals):
        local, _ = segment_grid(ev, float(feeds[k]), amin, TimingEngine.TOPPRA)
        parts.append(path.knots[k] + local)
        if k + 1 < len(path.evals):
            parts.append(np.array([path.knots[k + 1] - KNOT_EPS_MM]))
    grid = np.unique(np.concatenate(parts))
    grid[0], grid[-1] = 0.0, path.length
    return grid[np.concatenate(([True], np.diff(grid) > 1e-9))]


def _block_at(segments: Sequence[Segment], path: SectionPath, s: float) -> Segment:
    return segments[int(path.segment_index(np.array([s]))[0])]


def solve_section_toppra(
    section: Section,
    segments: Sequence[Segment],
    feeds: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    grid: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Solve one section with toppra; returns (section-local grid s, x = ṡ²).

    Raises
    ------
    TimingError
        toppra returned no parameterisation (empty controllable set); the message names the
        section, the arc length s, the source block and a remedy.
    """
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    segs = list(segments)
    path = SectionPath(segs)
    if any(e.kind != "line" for e in path.evals):
        # toppra checks the rows at grid points only; curvature turning inside an interval can
        # raise the per-axis acceleration between them (≤ 1/cos(Δθ/2) on arcs): keep a margin
        amax = amax * CURVED_ACC_MARGIN
    if grid is None:
        grid = section_grid_toppra(path, feeds, float(amax.min()))
    knots = path.knots
    d1 = path(grid, 1)
    idx = path.segment_index(grid)
    idx_left = path.segment_index(grid, left=True)
    feed_grid = np.minimum(feeds[idx], feeds[idx_left])

    vlim_table = np.empty((grid.shape[0], 3, 2))
    with np.errstate(divide="ignore"):
        feed_axis = feed_grid[:, None] * np.abs(d1)
    upper = np.where(np.abs(d1) > 1e-12, np.minimum(vmax[None, :], feed_axis), vmax[None, :])
    vlim_table[:, :, 0] = -upper
    vlim_table[:, :, 1] = upper
    lookup = {float(s): i for i, s in enumerate(grid)}

    def vlim(s: float) -> np.ndarray:
        i = lookup.get(float(s))
        if i is None:
            i = int(np.clip(np.searchsorted(grid, s), 0, grid.shape[0] - 1))
        return vlim_table[i]

    pc_vel = constraint.JointVelocityConstraintVarying(vlim)
    pc_acc = constraint.JointAccelerationConstraint(np.stack((-amax, amax), axis=1))
    instance = algo.TOPPRA(
        [pc_vel, pc_acc], path, gridpoints=grid, solver_wrapper="seidel", parametrizer="ParametrizeConstAccel"
    )
    sdd, sd, _, K = instance.compute_parameterization(0.0, 0.0, return_data=True)
    if sd is None or not np.all(np.isfinite(sd)):
        bad = 0
        if K is not None:
            K = np.asarray(K)
            empty = ~np.isfinite(K).all(axis=1) | (K[:, 1] < K[:, 0])
            if np.any(empty):
                bad = int(np.nonzero(empty)[0][-1])
        s_bad = float(grid[min(bad, grid.shape[0] - 1)])
        seg = _block_at(segs, path, s_bad)
        raise TimingError(
            f"toppra found no parameterisation of section {section.index} at s={s_bad:.6f} mm "
            f"(section-local; path s={section.s_start + s_bad:.6f} mm), block {seg.span.block_label()}: "
            "empty controllable set; remedy: check that the section is tangent-continuous and "
            "curvature-bounded, or refine the grid (smaller grid.RAMP_POINTS spacing)",
            seg.span,
            Code.TIMING_TOPPRA,
        )
    del toppra, knots, sdd
    x = np.asarray(sd, dtype=float) ** 2
    x[0] = x[-1] = 0.0
    return grid, x
