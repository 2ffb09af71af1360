"""toppra on the exact section path: the engine for general geometry (Poly curves) and fallback.

Settings follow spec timing.md §0–§1.2: explicit grid with every knot and a point just before each
knot, ``seidel`` solver, per-axis velocity limits combined with the feed as a varying velocity
constraint, per-axis acceleration limits, ``compute_parameterization(0, 0)`` on each section (the
ends of a section are tangent discontinuities or the path ends, so the speed is zero there), and
the const-acceleration reading of the result (``ParametrizeConstAccel``'s model, which follows the
path exactly). toppra is imported here only, inside the function.

A vector acceleration limit ``A`` (``machine.path.amax_mm_s2``) is one more linear constraint: with
``p'' = p'·s̈ + c·ṡ²`` written in the orthonormal frame of the tangent and the normal part of the
curvature vector, ``|p''| ≤ A`` is a disc in the plane of ``(w₁, w₂) = (|p'|s̈ + (e₁·c)ṡ², |c⊥|ṡ²)``
(``w₂ ≥ 0``); toppra gets the ``PATH_ACC_EDGES`` edges of the half of the inscribed regular
polygon with vertices at ``(±A, 0)`` and ``(0, A)``, so the straight-line ramps and the
maximum-velocity curve ``ṡ² = A/|c|`` stay exact and elsewhere at most ``1 − cos(π/(2·PATH_ACC_EDGES))``
of ``A`` is given away.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.errors import TimingError
from trcopt.modes import TimingEngine
from trcopt.path import Segment
from trcopt.timing.grid import KNOT_EPS_MM, segment_grid
from trcopt.timing.path import SectionPath
from trcopt.timing.sections import Section

__all__ = [
    "section_grid_toppra",
    "solve_section_toppra",
    "path_acceleration_rows",
    "CURVED_ACC_MARGIN",
    "PATH_ACC_EDGES",
]

CURVED_ACC_MARGIN = 0.9985
PATH_ACC_EDGES = 32  # edges of the inscribed half polygon of the |a| ≤ A disc (even: a vertex at (0, A))


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
    *,
    path_amax: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Solve one section with toppra; returns (section-local grid s, x = ṡ²).

    ``feeds`` are the path-speed limits per segment (mm/s; the vector speed limit is already in
    them), ``vmax``/``amax`` the per-axis limits and ``path_amax`` the optional limit on |a|
    (mm/s²).

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
    curved = any(e.kind != "line" for e in path.evals)
    if curved:
        # toppra checks the rows at grid points only; curvature turning inside an interval can
        # raise the per-axis acceleration between them (≤ 1/cos(Δθ/2) on arcs): keep a margin
        amax = amax * CURVED_ACC_MARGIN
    if grid is None:
        amin = float(amax.min()) if path_amax is None else min(float(amax.min()), path_amax)
        grid = section_grid_toppra(path, feeds, amin)
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
    constraints = [pc_vel, pc_acc]
    if path_amax is not None:
        limit = path_amax * CURVED_ACC_MARGIN if curved else path_amax
        constraints.append(_path_acceleration_constraint(constraint, limit))
    instance = algo.TOPPRA(
        constraints, path, gridpoints=grid, solver_wrapper="seidel", parametrizer="ParametrizeConstAccel"
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


def path_acceleration_rows(d1: np.ndarray, d2: np.ndarray, amax: float) -> tuple[np.ndarray, ...]:
    """Canonical rows of ``|p'' | ≤ amax`` at grid points with derivatives ``d1 = p'``, ``d2 = p''``.

    Returns toppra's ``(a, b, c, F, g)`` of a :class:`toppra.constraint.LinearConstraint` with
    ``F``, ``g`` identical at every point: ``w = a·u + b·x + c`` are the coordinates of ``p''`` in
    the frame (unit tangent e₁, unit normal part of ``d2``), and ``F w ≤ g`` the half polygon.
    """
    n = d1.shape[0]
    speed = np.linalg.norm(d1, axis=1)
    e1 = d1 / np.where(speed > 0, speed, 1.0)[:, None]
    along = (e1 * d2).sum(axis=1)
    normal = np.linalg.norm(d2 - along[:, None] * e1, axis=1)
    a = np.zeros((n, 2))
    b = np.zeros((n, 2))
    a[:, 0] = speed
    b[:, 0] = along
    b[:, 1] = normal
    m = PATH_ACC_EDGES
    psi = (np.arange(m) + 0.5) * np.pi / m  # edge normals between the vertices kπ/m, k = 0..m
    F = np.stack((np.cos(psi), np.sin(psi)), axis=1)
    g = np.full(m, amax * np.cos(0.5 * np.pi / m))
    return a, b, np.zeros((n, 2)), F, g


def _path_acceleration_constraint(constraint: Any, amax: float) -> Any:
    """A toppra linear constraint for ``|p''| ≤ amax`` (interpolation scheme, like the axis rows)."""

    class PathAcceleration(constraint.LinearConstraint):
        def __init__(self) -> None:
            super().__init__()
            self.dof = 3
            self.identical = True
            self.set_discretization_type(constraint.DiscretizationType.Interpolation)

        def compute_constraint_params(self, path: Any, gridpoints: np.ndarray, *args: Any, **kwargs: Any) -> Any:
            from toppra.constraint.linear_constraint import canlinear_colloc_to_interpolate

            a, b, c, F, g = path_acceleration_rows(path(gridpoints, 1), path(gridpoints, 2), amax)
            return canlinear_colloc_to_interpolate(a, b, c, F, g, None, None, gridpoints, identical=True)

    return PathAcceleration()
