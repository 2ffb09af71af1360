"""Smoothing splines across runs of small-deflection corners (CAM polylines).

A contour written as short G1 chords (CAM output) has a tangent discontinuity of a few degrees at
every vertex. A per-corner transition must rejoin the exact path between two corners, at zero
curvature where it meets a line, so it can use at most half a chord; around an outside vertex it
must also stay outside the circle of radius R (no gouge), and is then no flatter than that circle.
Treating the whole run at once removes both limits: one cubic B-spline (C2, so G2) from a point on
the element before the run to a point on the element after it, free to leave the exact path by up
to ε on the free side between the vertices, follows the curve the chords approximate.

The spline is found by sequential convex programming, one OSQP QP per step:

* objective: ∫|C″(s)|² ds over the reference arc length s of the exact path (the curvature, as
  the parametrisation stays close to unit speed);
* equalities: position, unit tangent and normal curvature of the neighbouring elements at both ends
  (G2 joins);
* no gouge: at every sample, for every programmed element within reach, the supporting half-plane
  of the disc-swept element at the current foot point, ``n·C ≥ n·f + R`` (conservative: the set of
  points within R of a line or a point is convex);
* tolerance: at every sample the distance beyond the exact tool-centre path on the side away from
  the material is ≤ ε′ (linearised at the current foot point), ε′ = ε·cos(θmax/2)·(1 − margin):
  the material left at a vertex of deflection θ is the offset over cos(θ/2).

Steps (each with a small proximal term) repeat until the spline moves < 1 µm across itself (at most
MAX_STEPS); the result is accepted only if the dense-sampled clearance ≥ R and offset ≤ ε hold; the
caller measures the cut-part deviation independently (:func:`trcopt.optimize.corners.boundary.cut_deviation`)
and tightens ε′ if it exceeds ε.

The same spline smooths a **curvature jump** (:func:`knot_site`): at a tangent-continuous joint
between a line and an arc, or arcs of different curvature, the acceleration of exact path following
steps, which limits a jerk-limited feed. A single quintic cannot join a line and a circle tangent to
it in G2 without crossing them (the offset from the exact path would have to vanish to second order
at both ends with a jump of its second derivative in between), so it would gouge or leave material
on both sides; the spline has the freedom to stay on the free side within ε. Its ends lie up to
KNOT_SIDE_LENGTHS·:func:`knot_length` from the joint.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.geometry.poly import parametric_curve
from trcopt.optimize.corners.curves import joint_turn, signed_curvature
from trcopt.verify.model import points_distance, points_foot
from trcopt.verify.nearest import ElementSet

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

__all__ = ["ChainSite", "ChainSolution", "find_chains", "knot_site", "knot_length", "solve_chain"]

CHAIN_MAX_TURN_DEG = 20.0  # joints of larger deflection keep per-corner transitions
CHAIN_MAX_CHORD_MM = 5.0  # longest element inside a run
CHAIN_MIN_CORNERS = 3  # shorter runs keep per-corner transitions
CHAIN_MAX_CORNERS = 200  # longer runs are split (the splines meet mid-chord): bounded QP size
CHAIN_END_MM = 10.0  # most of a neighbouring element a spline end may take
KNOT_STEP_MM = 0.5  # longest knot span of the spline
SAMPLES_PER_SPAN = 6  # constraint samples per knot span
EPS_MARGIN = 0.03  # the QP aims this fraction inside ε (linearisation between steps)
SAG_CURVATURE = 1.0  # 1/mm: bound of the spline's curvature for the clearance margin between samples
END_RAMP_MM = 1.0  # the clearance margin grows from 0 at the (exact) spline ends over this length
MAX_STEPS = 6
CONVERGED_MM = 1e-3  # largest movement across the curve of a converged step, mm
PROX = 1e-3  # proximal weight of the step QPs, relative to the mean curvature-Hessian diagonal
KNOT_MIN_JUMP_PER_MM = 1e-3  # smaller curvature jumps (radius ≥ 1 m next to a line) are left alone
# a curvature-jump spline takes up to this many knot_length on each side (1, 2, 3 and 5 measured
# under jerk limits on the gear, star and obround programs: 3 is fastest)
KNOT_SIDE_LENGTHS = 3.0


@dataclass(frozen=True)
class ChainSite:
    """A run of consecutive blendable joints ``joints`` (joint k between toolpath[k] and [k+1]).

    The spline starts at ``lam_a`` (fraction of plane length) on ``toolpath[first]`` and ends at
    ``lam_b`` on ``toolpath[last]``; ``elements`` are the exact tool-centre elements it replaces
    (the first and last trimmed), ``programmed`` the part contour near them."""

    first: int
    last: int
    joints: tuple[int, ...]
    lam_a: float
    lam_b: float
    elements: tuple[Line | Arc, ...]
    full: tuple[Line | Arc, ...]  # the same elements untrimmed (the exact path near the ends)
    programmed: tuple[Line | Arc, ...]
    radius: float
    material_sign: float
    w: float
    max_turn: float  # rad

    @cached_property
    def programmed_set(self) -> ElementSet:
        """:attr:`programmed` as an :class:`~trcopt.verify.nearest.ElementSet` (batched distances)."""
        return ElementSet(self.programmed)


@dataclass
class ChainSolution:
    ok: bool
    message: str
    pieces: list[Poly]  # one per element of the run, in order
    max_curvature: float  # 1/mm
    min_clearance: float  # mm
    max_offset: float  # largest distance beyond the exact path on the free side, mm
    iterations: int
    wall_s: float


def find_chains(
    toolpath: Sequence, joints: Sequence[int], all_joints: set[int], contour: Sequence[Line | Arc]
) -> list[ChainSite]:
    """Maximal runs of ≥ CHAIN_MIN_CORNERS consecutive joints (of ``joints``, sorted) of deflection
    ≤ CHAIN_MAX_TURN_DEG joined by lines ≤ CHAIN_MAX_CHORD_MM, split into runs of at most
    CHAIN_MAX_CORNERS (neighbouring runs share a chord, half each). ``all_joints`` are every corner site
    (a neighbouring per-corner transition owns half of a shared element); ``contour`` the
    programmed part contour (plane elements)."""
    max_turn = math.radians(CHAIN_MAX_TURN_DEG)
    small = [k for k in joints if abs(joint_turn(toolpath[k].geometry, toolpath[k + 1].geometry)) <= max_turn]
    runs: list[list[int]] = []
    for k in small:
        g = toolpath[k].geometry
        if (
            runs
            and runs[-1][-1] == k - 1
            and isinstance(g, Line)
            and g.plane_length <= CHAIN_MAX_CHORD_MM
        ):
            runs[-1].append(k)
        else:
            runs.append([k])
    pieces = []
    for run in runs:
        if len(run) < CHAIN_MIN_CORNERS:
            continue
        parts = -(-len(run) // CHAIN_MAX_CORNERS)
        size = -(-len(run) // parts)
        pieces += [run[i : i + size] for i in range(0, len(run), size)]
    return [_run_site(toolpath, run, all_joints, contour, CHAIN_END_MM) for run in pieces]


def knot_length(curvature_change: float, eps: float) -> float:
    """Length of the clothoid whose largest offset from the line or circles it joins,
    ``L²·|Δκ|/24``, equals ``eps``, mm: the natural length of a transition across a jump of
    curvature ``Δκ`` within ``eps``."""
    return math.sqrt(24.0 * eps / max(abs(curvature_change), 1e-12))


def knot_site(
    toolpath: Sequence, joints: Sequence[int], all_joints: set[int], contour: Sequence[Line | Arc], eps: float
) -> ChainSite:
    """The curvature jumps at the consecutive tangent-continuous ``joints`` (a line↔arc joint,
    arcs of different curvature, or both joints of a G450 transition circle) as one run: the
    spline takes up to KNOT_SIDE_LENGTHS·:func:`knot_length` (of the largest jump) of each end
    element (half of an element shared with another site)."""
    dk = max(
        abs(signed_curvature(toolpath[k + 1].geometry) - signed_curvature(toolpath[k].geometry)) for k in joints
    )
    side = min(KNOT_SIDE_LENGTHS * knot_length(dk, eps), CHAIN_END_MM)
    return _run_site(toolpath, list(joints), all_joints, contour, side)


def _run_site(
    toolpath: Sequence, run: list[int], all_joints: set[int], contour: Sequence[Line | Arc], end_mm: float
) -> ChainSite:
    """The spline site across the joints ``run``: up to ``end_mm`` of each end element."""
    first, last = run[0], run[-1] + 1
    ga, gb = toolpath[first].geometry, toolpath[last].geometry
    share_a = 0.5 if (first - 1) in all_joints else 0.98
    share_b = 0.5 if last in all_joints else 0.98
    da = min(share_a * ga.plane_length, end_mm)
    db = min(share_b * gb.plane_length, end_mm)
    lam_a, lam_b = 1.0 - da / ga.plane_length, db / gb.plane_length
    full = tuple(toolpath[i].geometry for i in range(first, last + 1))
    els = (
        ga.sub(lam_a, 1.0, ga.start[2], ga.end[2]),
        *full[1:-1],
        gb.sub(0.0, lam_b, gb.start[2], gb.end[2]),
    )
    seg0 = toolpath[first]
    P = np.array([e.point2(x) for e in full for x in (0.0, 0.5, 1.0)])
    lo, hi = P.min(axis=0) - 3 * seg0.radius, P.max(axis=0) + 3 * seg0.radius
    prog = tuple(e for e in contour if _boxes_meet(e, lo, hi))
    sign = -1.0 if seg0.side.value == "left" else 1.0
    turn = max(abs(joint_turn(toolpath[k].geometry, toolpath[k + 1].geometry)) for k in run)
    return ChainSite(first, last, tuple(run), lam_a, lam_b, els, full, prog, seg0.radius, sign, ga.end[2], turn)


def _boxes_meet(e: Line | Arc, lo: np.ndarray, hi: np.ndarray) -> bool:
    pts = np.array([e.point2(x) for x in np.linspace(0.0, 1.0, 9)])
    return bool(np.all(pts.max(axis=0) >= lo) and np.all(pts.min(axis=0) <= hi))


# ------------------------------------------------------------------------------ reference path
class _Reference:
    """The exact elements of the run as a function of arc length s."""

    def __init__(self, elements: Sequence[Line | Arc]) -> None:
        self.elements = list(elements)
        self.cum = np.concatenate(([0.0], np.cumsum([e.plane_length for e in elements])))
        self.length = float(self.cum[-1])

    def points(self, s: np.ndarray) -> np.ndarray:
        idx = np.clip(np.searchsorted(self.cum, s, side="right") - 1, 0, len(self.elements) - 1)
        out = np.empty((len(s), 2))
        for i, e in enumerate(self.elements):
            m = idx == i
            if np.any(m):
                lam = np.clip((s[m] - self.cum[i]) / e.plane_length, 0.0, 1.0)
                out[m] = np.array([e.point2(float(x)) for x in lam])
        return out


def _end_frame(e: Line | Arc, at_end: bool) -> tuple[np.ndarray, np.ndarray, float]:
    """Point, unit tangent and signed curvature (left positive) of ``e`` at its start or end."""
    p = np.array(e.point2(1.0 if at_end else 0.0))
    t = np.array(e.end_tangent() if at_end else e.start_tangent(), float)
    k = 0.0 if isinstance(e, Line) else (1.0 if e.sweep > 0 else -1.0) / e.radius
    return p, t, k


def _basis(knots: np.ndarray, x: np.ndarray, nu: int, n: int) -> np.ndarray:
    from scipy.interpolate import BSpline

    return BSpline(knots, np.eye(n), 3, extrapolate=False)(x, nu) if nu else BSpline(knots, np.eye(n), 3)(x)


def solve_chain(site: ChainSite, eps: float, *, knot_step: float = KNOT_STEP_MM) -> ChainSolution:
    """The least-∫κ² cubic spline across the run within ε of the exact cut and ≥ R from the part."""
    import osqp
    from scipy import sparse
    from scipy.interpolate import BSpline

    t0 = time.perf_counter()
    ref = _Reference(site.elements)
    S = ref.length
    chords = [e.plane_length for e in site.elements[1:-1]]
    h = min(knot_step, 0.5 * min(chords)) if chords else knot_step
    n_span = max(4, int(math.ceil(S / h)))
    breaks = np.linspace(0.0, S, n_span + 1)
    knots = np.concatenate(([0.0] * 3, breaks, [S] * 3))
    n = n_span + 3
    # constraint samples and Gauss points of the objective (C″ is linear on a span: 2 points exact)
    spans = zip(breaks, breaks[1:], strict=False)
    xs = np.concatenate([np.linspace(a, b, SAMPLES_PER_SPAN, endpoint=False) for a, b in spans])
    joints_s = np.array([sum(e.plane_length for e in site.full[: i + 1]) for i in range(len(site.full) - 1)])
    joints_s -= site.full[0].plane_length - site.elements[0].plane_length
    xs = np.unique(np.concatenate((xs, [S], joints_s)))
    j_at = np.searchsorted(xs, joints_s)  # sample index of every joint (between full[i] and full[i+1])
    g = 0.5 / math.sqrt(3.0)
    mid, half = 0.5 * (breaks[1:] + breaks[:-1]), breaks[1:] - breaks[:-1]
    xg = np.concatenate((mid - g * half, mid + g * half))
    wg = np.concatenate((0.5 * half, 0.5 * half))
    B0 = _basis(knots, xs, 0, n)
    B1 = _basis(knots, xs, 1, n)
    B0s = sparse.csr_matrix(np.where(np.abs(B0) > 1e-15, B0, 0.0))
    B2g = _basis(knots, xg, 2, n)
    ends = np.array([0.0, S])
    E0, E1, E2 = (_basis(knots, ends, nu, n) for nu in (0, 1, 2))
    # objective ½ xᵀPx: ∫|C″|² for x and y (a tiny ridge keeps P positive definite)
    H = B2g.T @ (wg[:, None] * B2g)
    H = 2.0 * H + 1e-10 * np.eye(n)
    Pm = sparse.block_diag((H, H), format="csc")
    # proximal term on the step (vanishes at the fixed point): conditions the ADMM iterations
    Pprox = (Pm + PROX * float(np.mean(np.diag(H))) * sparse.eye(2 * n)).tocsc()

    def xy_rows(Bm: Any, vecs: np.ndarray) -> Any:
        """Rows of v·C(s) for rows of the basis ``Bm`` and directions ``vecs`` (k×2)."""
        if sparse.issparse(Bm):
            return sparse.hstack((sparse.diags(vecs[:, 0]) @ Bm, sparse.diags(vecs[:, 1]) @ Bm))
        return np.hstack((Bm * vecs[:, :1], Bm * vecs[:, 1:]))

    # end conditions: position, tangent (unit speed) and normal curvature of the neighbours
    eq_rows, eq_val = [], []
    for j, at_end in ((0, False), (1, True)):
        el = site.elements[-1] if at_end else site.elements[0]
        p, t, kap = _end_frame(el, at_end)
        nrm = np.array([-t[1], t[0]])
        for vec, val, Bm in (
            (np.array([1.0, 0.0]), p[0], E0),
            (np.array([0.0, 1.0]), p[1], E0),
            (np.array([1.0, 0.0]), t[0], E1),
            (np.array([0.0, 1.0]), t[1], E1),
            (nrm, kap, E2),
        ):
            eq_rows.append(xy_rows(Bm[j : j + 1], vec[None, :])[0])
            eq_val.append(val)
    A_eq = np.array(eq_rows)
    b_eq = np.array(eq_val)

    R = site.radius
    eps_t = eps * math.cos(0.5 * site.max_turn) * (1.0 - EPS_MARGIN)
    # an iterate stays within ε of the exact path: farther elements cannot come within R in a step
    reach = R + 4.0 * eps + 0.01
    # between two samples a curve of curvature κ comes closer to a line by at most κ·Δ²/8; the ends
    # lie on the exact path (clearance exactly R), where the margin fades out
    gap = float(np.max(np.diff(xs)))
    ramp = np.clip(np.minimum(xs, S - xs) / END_RAMP_MM, 0.0, 1.0) ** 3
    margin = ramp * (SAG_CURVATURE * gap * gap / 8.0 + 1e-7)
    exact = list(site.full)
    # exact path normals away from the material, per exact element (lines and arcs)
    x_cur = None
    pts = ref.points(xs)
    # the QPs are posed in the step from the current spline (small numbers: OSQP's residuals are
    # absolute), starting from the least-squares fit of the exact path
    # the least-squares fit by the normal equations of the banded B-spline basis (well conditioned
    # with several samples per knot span; a dense lstsq costs O(samples·n²))
    gram = (B0s.T @ B0s).toarray()
    fit = np.linalg.solve(gram + 1e-14 * np.trace(gram) / n * np.eye(n), B0s.T @ pts)
    x_lin = np.concatenate((fit[:, 0], fit[:, 1]))
    msg = "max steps"
    x_prev_pts = pts.copy()
    steps = 0
    for it in range(1, MAX_STEPS + 1):
        steps = it
        rows, lo, hi = [], [], []
        # no gouge: supporting half-planes of every programmed element within reach
        for el in site.programmed:
            d = points_distance(el, pts)
            m = np.nonzero(d <= reach)[0]
            if not len(m):
                continue
            foot = points_foot(el, pts[m])
            nv = pts[m] - foot
            nn = np.hypot(nv[:, 0], nv[:, 1])
            ok = nn > 1e-9
            m, foot, nv, nn = m[ok], foot[ok], nv[ok], nn[ok]
            nv = nv / nn[:, None]
            rows.append(xy_rows(B0s[m], nv))
            lo.append(np.sum(nv * foot, axis=1) + R + margin[m])
            hi.append(np.full(len(m), np.inf))
        # tolerance: distance beyond the exact path on the free side (nearest exact element; at the
        # joints, where the distance to a polyline peaks, to both elements)
        dists = np.array([points_distance(e, pts) for e in exact])
        near = np.argmin(dists, axis=0)
        for i, e in enumerate(exact):
            m = np.nonzero(near == i)[0]
            if i >= 1:
                m = np.union1d(m, j_at[i - 1 : i])
            if i < len(exact) - 1:
                m = np.union1d(m, j_at[i : i + 1])
            if not len(m):
                continue
            feet, mv = _free_normals(e, pts[m], site.material_sign)
            rows.append(xy_rows(B0s[m], mv))
            lo.append(np.full(len(m), -np.inf))
            hi.append(np.sum(mv * feet, axis=1) + eps_t)
        A_s = sparse.vstack([sparse.csr_matrix(A_eq), *rows], format="csc")
        lo_all = np.concatenate([b_eq, *lo])
        hi_all = np.concatenate([b_eq, *hi])
        solver = osqp.OSQP()
        ax = A_s @ x_lin
        solver.setup(
            Pprox, Pm @ x_lin, A_s, lo_all - ax, hi_all - ax, verbose=False, eps_abs=1e-5, eps_rel=1e-5,
            max_iter=40000, rho=1e-3, polishing=True,
        )
        res = solver.solve(raise_error=False)
        if res.x is None or not np.all(np.isfinite(res.x)) or res.info.status_val not in (1, 2):
            msg = f"osqp: {res.info.status}"
            break
        x_cur = x_lin = x_lin + np.asarray(res.x)
        new_pts = np.stack((B0 @ x_cur[:n], B0 @ x_cur[n:]), axis=1)
        # movement across the curve (sliding along it is a change of parametrisation only)
        tan = np.stack((B1 @ x_cur[:n], B1 @ x_cur[n:]), axis=1)
        tan /= np.maximum(np.hypot(tan[:, 0], tan[:, 1]), 1e-300)[:, None]
        move = new_pts - x_prev_pts
        step = float(np.max(np.abs(move[:, 0] * tan[:, 1] - move[:, 1] * tan[:, 0])))
        pts = x_prev_pts = new_pts
        if step < CONVERGED_MM:
            msg = "converged"
            break
    if x_cur is None:
        return ChainSolution(False, msg, [], math.inf, 0.0, math.inf, steps, time.perf_counter() - t0)
    cx, cy = BSpline(knots, x_cur[:n], 3), BSpline(knots, x_cur[n:], 3)
    # exact checks on dense samples
    dense = np.linspace(0.0, S, max(2001, int(S / 0.01)))
    P = np.stack((cx(dense), cy(dense)), axis=1)
    clear = site.programmed_set.min_distance(P)
    offset = _free_offset(site, P)
    d1 = np.stack((cx(dense, 1), cy(dense, 1)), axis=1)
    d2 = np.stack((cx(dense, 2), cy(dense, 2)), axis=1)
    sp = np.hypot(d1[:, 0], d1[:, 1])
    kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(sp, 1e-300) ** 3
    ok = clear >= R - 1e-9 and offset <= eps and float(sp.min()) > 0.2
    if not ok:
        why = f"clearance {clear:.6f} < R" if clear < R - 1e-9 else f"offset {offset:.5f} mm > ε"
        if float(sp.min()) <= 0.2:
            why = "degenerate parametrisation"
        msg = f"{msg}; {why}"
    cuts = np.concatenate(([0.0], ref.cum[1:-1], [S]))
    pieces = [_piece(cx, cy, a, b, site.w) for a, b in zip(cuts, cuts[1:], strict=False)] if ok else []
    return ChainSolution(ok, msg, pieces, float(kappa.max()), clear, offset, steps, time.perf_counter() - t0)


def _lam_of(e: Line | Arc, feet: np.ndarray) -> np.ndarray:
    if isinstance(e, Line):
        a, b = np.array(e.start2), np.array(e.end2)
        d = b - a
        return np.clip((feet - a) @ d / float(d @ d), 0.0, 1.0)
    ang = np.arctan2(feet[:, 1] - e.center[1], feet[:, 0] - e.center[0])
    return np.clip(np.mod((ang - e.a0) * np.sign(e.sweep), 2 * math.pi) / abs(e.sweep), 0.0, 1.0)


def _tangents(e: Line | Arc, lam: np.ndarray) -> np.ndarray:
    if isinstance(e, Line):
        return np.repeat(np.array([e.direction2()], float), len(lam), axis=0)
    return np.array([e.tangent2(float(x)) for x in lam], float).reshape(-1, 2)


def _free_normals(e: Line | Arc, P: np.ndarray, material_sign: float) -> tuple[np.ndarray, np.ndarray]:
    """Foot points on ``e`` and unit directions of the distance beyond ``e`` on the side away from
    the material (the element normal; radial beyond an end, in the outer wedge of a vertex)."""
    f = points_foot(e, P)
    lam = _lam_of(e, f)
    tan = _tangents(e, lam)
    free = -material_sign * np.stack((-tan[:, 1], tan[:, 0]), axis=1)
    off = P - f
    dn = np.hypot(off[:, 0], off[:, 1])
    at_end = (lam <= 1e-12) | (lam >= 1.0 - 1e-12)
    radial = at_end & (dn > 1e-9) & (np.sum(off * free, axis=1) > 0.0)
    return f, np.where(radial[:, None], off / np.maximum(dn, 1e-300)[:, None], free)


def _free_offset(site: ChainSite, P: np.ndarray) -> float:
    """Largest distance of the points beyond the exact path on the side away from the material."""
    worst = 0.0
    near = np.argmin(np.array([points_distance(e, P) for e in site.full]), axis=0)
    for i, e in enumerate(site.full):
        m = near == i
        if np.any(m):
            feet, mv = _free_normals(e, P[m], site.material_sign)
            worst = max(worst, float(np.sum((P[m] - feet) * mv, axis=1).max()))
    return worst


def _piece(cx: BSpline, cy: BSpline, a: float, b: float, w: float) -> Poly:
    L = b - a

    def f(u: float) -> tuple[float, float, float]:
        s = a + u * L
        return float(cx(s)), float(cy(s)), w

    def df(u: float) -> tuple[float, float, float]:
        s = a + u * L
        return float(cx(s, 1)) * L, float(cy(s, 1)) * L, 0.0

    def d2f(u: float) -> tuple[float, float, float]:
        s = a + u * L
        return float(cx(s, 2)) * L * L, float(cy(s, 2)) * L * L, 0.0

    return parametric_curve(f, df, d2f, "chain-spline")
