"""Smoothing splines across runs of small-deflection corners (CAM polylines).

A contour written as short G1 chords (CAM output) has a tangent discontinuity of a few degrees at
every vertex. A per-corner transition must rejoin the exact path between two corners, at zero
curvature where it meets a line, so it can use at most half a chord; around an outside vertex it
must also stay outside the circle of radius R (no gouge), and is then no flatter than that circle.
Treating the whole run at once removes both limits: one cubic B-spline (C2, so G2) from a point on
the element before the run to a point on the element after it, free to leave the exact path by up
to ε on the free side between the vertices, follows the curve the chords approximate. On a
compensated contour the run continues through the short transition arcs of small sweep at the
outside vertices (tangent joints): the spline replaces them with the chords around them, so a
convex stretch of CAM chords is no longer bound to circles of radius R.

The spline is found by sequential convex programming, one QP per step (Clarabel, interior point:
:func:`~trcopt.optimize.corners.chain_qp.solve_rows`; the rows are built for all samples at once
through a k-d tree of the samples, :mod:`.chain_geometry`, on the sparse B-spline bases of
:mod:`.chain_spline`):

* objective: ∫|C″(s)|² ds over the reference arc length s of the exact path (the curvature, as
  the parametrisation stays close to unit speed);
* equalities: position, unit tangent and normal curvature of the neighbouring elements at both ends
  (G2 joins);
* no gouge: at every sample, for every programmed element within reach, the supporting half-plane
  of the disc-swept element at the current foot point, ``n·C ≥ n·f + R`` (conservative: the set of
  points within R of a line or a point is convex), plus a sag margin for the curve between samples
  (from the current spline's curvature); where the exact path itself comes closer than R (a
  controller's near-tangent joint, R·(1 − cos turn) at most), as close as the exact path is there;
* tolerance: at every sample the distance beyond the exact tool-centre path on the side away from
  the material is ≤ ε′ (linearised at the current foot point), ε′ = ε·cos(θmax/2)·(1 − margin):
  the material left at a vertex of deflection θ is the offset over cos(θ/2).

Steps (each with a small proximal term and a penalty on sliding along the curve) repeat until the
spline moves < 1 µm across itself, or < 5 µm with ∫κ² settled (at most MAX_STEPS); the knot spacing
is at most a third of the length over which the sharpest corner of the run turns within ε (on a
path without compensation: of the nearest corners, growing by a quarter of the distance from them,
:func:`~trcopt.optimize.corners.chain_spline.breakpoints`). The result is accepted only if the
dense-sampled clearance (≥ R, or the exact path's own) and offset ≤ ε hold; the
caller measures the cut-part deviation independently (:func:`trcopt.optimize.corners.deviation.cut_deviation`)
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
from typing import TYPE_CHECKING

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.optimize.corners.chain_geometry import Elements, free_directions, nearest
from trcopt.optimize.corners.chain_qp import solve_rows
from trcopt.optimize.corners.chain_spline import SplineBasis, breakpoints, pieces, ppoly, rows
from trcopt.optimize.corners.curves import joint_turn, signed_curvature
from trcopt.path import Role
from trcopt.verify.model import bbox

if TYPE_CHECKING:
    pass

__all__ = ["ChainSite", "ChainSolution", "PartContour", "find_chains", "knot_site", "knot_length", "solve_chain"]

CHAIN_MAX_TURN_DEG = 20.0  # joints of larger deflection keep per-corner transitions
CHAIN_MAX_CHORD_MM = 5.0  # longest element inside a run
CHAIN_MIN_CORNERS = 3  # shorter runs keep per-corner transitions
TANGENT_MAX_RAD = 1e-6  # a joint this close to tangent continues a run through an arc
CHAIN_MAX_CORNERS = 200  # longer runs are split (the splines meet mid-chord): bounded QP size
CHAIN_END_MM = 10.0  # most of a neighbouring element a spline end may take
KNOT_STEP_MM = 0.5  # longest knot span of the spline
SAMPLES_PER_SPAN = 3  # constraint samples per knot span
EPS_MARGIN = 0.03  # the QP aims this fraction inside ε (linearisation between steps)
SAG_CURVATURE = 1.0  # 1/mm: bound of the spline's curvature for the clearance margin between samples
END_RAMP_MM = 1.0  # the clearance margin grows from 0 at the (exact) spline ends over this length
MAX_STEPS = 6
CONVERGED_MM = 1e-3  # largest movement across the curve of a converged step, mm
SETTLED_MM = 5e-3  # … or this with ∫κ² improved by less than SETTLED_GAIN (relative) in the step
SETTLED_GAIN = 2e-3
PROX = 1e-3  # proximal weight of the step QPs, relative to the mean curvature-Hessian diagonal
KNOT_MIN_JUMP_PER_MM = 1e-3  # smaller curvature jumps (radius ≥ 1 m next to a line) are left alone
# a curvature-jump spline takes up to this many knot_length on each side (1, 2, 3 and 5 measured
# under jerk limits on the gear, star and obround programs: 3 is fastest)
KNOT_SIDE_LENGTHS = 3.0
SLIDE = 1e-3  # weight of sliding along the curve in a step, relative to the mean curvature-Hessian diagonal


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
    max_turn: float  # rad, largest deflection at a joint (the arcs inside the run are smooth)


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
    toolpath: Sequence,
    joints: Sequence[int],
    all_joints: set[int],
    contour: Sequence[Line | Arc] | PartContour,
    *,
    compensated: bool = True,
) -> list[ChainSite]:
    """Maximal runs of ≥ CHAIN_MIN_CORNERS consecutive joints (of ``joints``, sorted) of deflection
    ≤ CHAIN_MAX_TURN_DEG joined by lines ≤ CHAIN_MAX_CHORD_MM, split into runs of at most
    CHAIN_MAX_CORNERS (neighbouring runs share a chord, half each). ``all_joints`` are every corner site
    (a neighbouring per-corner transition owns half of a shared element); ``contour`` the
    programmed part contour (plane elements). Short arcs of small sweep inside a run are taken
    from the compensated segments (``compensated``) or from the others only."""
    max_turn = math.radians(CHAIN_MAX_TURN_DEG)
    small = {k for k in joints if abs(joint_turn(toolpath[k].geometry, toolpath[k + 1].geometry)) <= max_turn}
    # the short arcs of small sweep between the chords (the transition circles around the outside
    # vertices of a compensated CAM contour, or short programmed arcs): their tangent joints join
    # the run, and the spline replaces the arc with the chords around it
    for i in range(1, len(toolpath) - 1):
        if _small_arc(toolpath, i, compensated) and not ({i - 1, i} & set(all_joints)):
            if all(
                abs(joint_turn(toolpath[k].geometry, toolpath[k + 1].geometry)) <= TANGENT_MAX_RAD for k in (i - 1, i)
            ):
                small |= {i - 1, i}
    runs: list[list[int]] = []
    for k in sorted(small):
        if runs and runs[-1][-1] == k - 1 and _chord(toolpath, k):
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
    part = _as_part(contour)
    return [_run_site(toolpath, run, all_joints, part, CHAIN_END_MM) for run in pieces]


def _chord(toolpath: Sequence, i: int) -> bool:
    """Whether ``toolpath[i]`` may lie inside a run: a short plane feed line or a short arc of small
    sweep."""
    seg = toolpath[i]
    g = seg.geometry
    if seg.is_rapid or not isinstance(g, Line | Arc) or g.start[2] != g.end[2]:
        return False
    if isinstance(g, Line):
        return g.plane_length <= CHAIN_MAX_CHORD_MM
    return _small_arc(toolpath, i, seg.radius > 0)


def _small_arc(toolpath: Sequence, i: int, compensated: bool | None = None) -> bool:
    """A short arc of small sweep; with ``compensated`` True one of a compensated path (its
    transition arcs included), False one of an uncompensated path that was programmed (not a blend
    trcopt inserted: the tolerance is measured from the programmed path)."""
    seg = toolpath[i]
    g = seg.geometry
    if compensated is not None and (seg.radius > 0) != compensated:
        return False
    if compensated is False and seg.role is Role.CORNER:
        return False
    return (
        isinstance(g, Arc)
        and not seg.is_rapid
        and g.w0 == g.w1
        and abs(g.sweep) <= math.radians(CHAIN_MAX_TURN_DEG)
        and g.plane_length <= CHAIN_MAX_CHORD_MM
    )


def knot_length(curvature_change: float, eps: float) -> float:
    """Length of the clothoid whose largest offset from the line or circles it joins,
    ``L²·|Δκ|/24``, equals ``eps``, mm: the natural length of a transition across a jump of
    curvature ``Δκ`` within ``eps``."""
    return math.sqrt(24.0 * eps / max(abs(curvature_change), 1e-12))


def knot_site(
    toolpath: Sequence,
    joints: Sequence[int],
    all_joints: set[int],
    contour: Sequence[Line | Arc] | PartContour,
    eps: float,
) -> ChainSite:
    """The curvature jumps at the consecutive tangent-continuous ``joints`` (a line↔arc joint,
    arcs of different curvature, or both joints of a G450 transition circle) as one run: the
    spline takes up to KNOT_SIDE_LENGTHS·:func:`knot_length` (of the largest jump) of each end
    element (half of an element shared with another site)."""
    dk = max(abs(signed_curvature(toolpath[k + 1].geometry) - signed_curvature(toolpath[k].geometry)) for k in joints)
    side = min(KNOT_SIDE_LENGTHS * knot_length(dk, eps), CHAIN_END_MM)
    return _run_site(toolpath, list(joints), all_joints, contour, side)


def _run_site(
    toolpath: Sequence, run: list[int], all_joints: set[int], contour: Sequence[Line | Arc] | PartContour,
    end_mm: float,
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
    prog = _as_part(contour).within(lo, hi)
    sign = -1.0 if seg0.side.value == "left" else 1.0
    turn = max(abs(joint_turn(toolpath[k].geometry, toolpath[k + 1].geometry)) for k in run)
    return ChainSite(first, last, tuple(run), lam_a, lam_b, els, full, prog, seg0.radius, sign, ga.end[2], turn)


class PartContour:
    """The programmed part contour's plane elements with their bounding boxes (the elements near a
    run are found by one comparison over the boxes, not element by element)."""

    def __init__(self, elements: Sequence[Line | Arc]) -> None:
        self.elements = list(elements)
        self.boxes = np.array([bbox(e) for e in self.elements], float).reshape(-1, 4)

    def within(self, lo: np.ndarray, hi: np.ndarray) -> tuple[Line | Arc, ...]:
        """The elements whose boxes meet the box ``lo``–``hi``, in contour order."""
        b = self.boxes
        hit = (b[:, 2] >= lo[0]) & (b[:, 3] >= lo[1]) & (b[:, 0] <= hi[0]) & (b[:, 1] <= hi[1])
        return tuple(self.elements[i] for i in np.nonzero(hit)[0])


def _as_part(contour: Sequence[Line | Arc] | PartContour) -> PartContour:
    return contour if isinstance(contour, PartContour) else PartContour(contour)


def _end_frame(e: Line | Arc, at_end: bool) -> tuple[np.ndarray, np.ndarray, float]:
    """Point, unit tangent and signed curvature (left positive) of ``e`` at its start or end."""
    p = np.array(e.point2(1.0 if at_end else 0.0))
    t = np.array(e.end_tangent() if at_end else e.start_tangent(), float)
    k = 0.0 if isinstance(e, Line) else (1.0 if e.sweep > 0 else -1.0) / e.radius
    return p, t, k


def _sag_margin(d1: np.ndarray, d2x: np.ndarray, d2y: np.ndarray, gap: float, ramp: np.ndarray) -> np.ndarray:
    """Per sample, how much closer the curve may come to a line between two samples ``gap`` apart:
    κ·gap²/8 with κ 1.5× the largest curvature of the current spline around the sample (at most
    SAG_CURVATURE), fading to 0 at the exact ends (``ramp``); ``d1``, ``d2x``, ``d2y``: the
    spline's first and second derivatives at the samples."""
    d2 = np.stack((d2x, d2y), axis=1)
    kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(np.hypot(d1[:, 0], d1[:, 1]), 1e-9) ** 3
    k = SAMPLES_PER_SPAN
    padded = np.pad(kappa, k, mode="edge")
    local = np.max(np.stack([padded[i : i + len(kappa)] for i in range(2 * k + 1)]), axis=0)
    return ramp * (np.minimum(1.5 * local, SAG_CURVATURE) * gap * gap / 8.0 + 1e-7)


def solve_chain(site: ChainSite, eps: float, *, knot_step: float = KNOT_STEP_MM) -> ChainSolution:
    """The least-∫κ² cubic spline across the run within ε of the exact cut and ≥ R from the part."""
    from scipy import sparse
    from scipy.interpolate import BSpline
    from scipy.sparse.linalg import spsolve
    from scipy.spatial import cKDTree

    t0 = time.perf_counter()
    ref = Elements(site.elements)
    cum = np.concatenate(([0.0], np.cumsum(ref.length)))
    S = float(cum[-1])
    chords = [e.plane_length for e in site.elements[1:-1] if isinstance(e, Line)]
    h = min(knot_step, 0.5 * min(chords)) if chords else knot_step
    # a corner of deflection θ rounded within ε turns over about 8ε/θ (the circle of that sag):
    # three knot spans there
    fine = min(h, 8.0 * eps / (3.0 * max(site.max_turn, 1e-9)))
    R = site.radius
    two_sided = R <= 0.0  # a path without compensation: no material side, no programmed contour
    if two_sided and fine < h:
        # the spans grow from 8ε/3θ at every corner of deflection θ (and the finest at the ends,
        # where the G2 joins take the neighbours' curvature) to the coarse spacing between them
        turns = np.abs([joint_turn(a, b) for a, b in zip(site.full[:-1], site.full[1:], strict=True)])
        places = np.concatenate(([0.0], cum[1:-1], [S]))
        spans = np.concatenate(([fine], 8.0 * eps / (3.0 * np.maximum(turns, 1e-300)), [fine]))
        breaks = breakpoints(S, h, places, spans)
    else:
        # on a compensated run one spacing everywhere: its transition arcs and no-gouge half-planes
        # need it between the corners too (spans graded as above left runs infeasible or slower)
        breaks = np.linspace(0.0, S, max(4, int(math.ceil(S / fine))) + 1)
    n_span = len(breaks) - 1
    knots = np.concatenate(([0.0] * 3, breaks, [S] * 3))
    n = n_span + 3
    # constraint samples and Gauss points of the objective (C″ is linear on a span: 2 points exact)
    xs = (breaks[:-1, None] + np.diff(breaks)[:, None] * np.arange(SAMPLES_PER_SPAN) / SAMPLES_PER_SPAN).ravel()
    joints_s = cum[1:-1]
    xs = np.unique(np.concatenate((xs, [S], joints_s)))
    j_at = np.searchsorted(xs, joints_s)  # sample index of every joint (between full[i] and full[i+1])
    g = 0.5 / math.sqrt(3.0)
    mid, half = 0.5 * (breaks[1:] + breaks[:-1]), breaks[1:] - breaks[:-1]
    xg = np.concatenate((mid - g * half, mid + g * half))
    wg = np.concatenate((0.5 * half, 0.5 * half))
    sb = SplineBasis(knots, n)
    B0s, B1s, B2g = sb.at(xs, 0), sb.at(xs, 1), sb.at(xg, 2)
    ends = np.array([0.0, S])
    E0, E1, E2 = (sb.at(ends, nu).toarray() for nu in (0, 1, 2))
    # objective ½ xᵀPx: ∫|C″|² for x and y (a tiny ridge keeps P positive definite)
    H = (B2g.T @ sparse.diags(wg) @ B2g).tocsc()
    H = 2.0 * H + 1e-10 * sparse.eye(n)
    Pm = sparse.block_diag((H, H), format="csc")
    # proximal term on the step (vanishes at the fixed point): keeps the linearisation local
    h_scale = float(np.mean(H.diagonal()))
    Pprox = (Pm + PROX * h_scale * sparse.eye(2 * n)).tocsc()

    # end conditions: position, tangent (unit speed) and normal curvature of the neighbours
    eq_rows, eq_val = [], []
    for j, at_end in ((0, False), (1, True)):
        p, t, kap = _end_frame(site.elements[-1] if at_end else site.elements[0], at_end)
        nrm = np.array([-t[1], t[0]])
        for vec, val, Bm in (((1.0, 0.0), p[0], E0), ((0.0, 1.0), p[1], E0), ((1.0, 0.0), t[0], E1),
                             ((0.0, 1.0), t[1], E1), (nrm, kap, E2)):  # fmt: skip
            eq_rows.append(np.concatenate((Bm[j] * vec[0], Bm[j] * vec[1])))
            eq_val.append(val)
    A_eq = sparse.csr_matrix(np.array(eq_rows))
    b_eq = np.array(eq_val)

    eps_t = eps * math.cos(0.5 * site.max_turn) * (1.0 - EPS_MARGIN)
    # an iterate stays within ε of the exact path and moves less than ε in a step: farther elements
    # cannot come within R
    reach = R + 2.0 * eps + 0.002
    near_exact = 4.0 * eps + 0.05
    # between two samples a curve of curvature κ comes closer to a line by at most κ·Δ²/8; the ends
    # lie on the exact path (clearance exactly R), where the margin fades out
    gap = float(np.max(np.diff(xs)))
    ramp = np.clip(np.minimum(xs, S - xs) / END_RAMP_MM, 0.0, 1.0) ** 3
    B2s = sb.at(xs, 2)
    prog = Elements(site.programmed)
    exact = Elements(site.full)
    idx = np.clip(np.searchsorted(cum, xs, side="right") - 1, 0, ref.n - 1)
    pts = ref_pts = ref.points(idx, np.clip((xs - cum[idx]) / ref.length[idx], 0.0, 1.0))
    # joints: the distance beyond a polyline peaks there; both elements bound it
    joint_m = np.concatenate((j_at, j_at))
    joint_e = np.concatenate((np.arange(len(j_at)), np.arange(len(j_at)) + 1))
    # the QPs are posed in the step from the current spline, starting from the least-squares fit of
    # the exact path (normal equations of the banded basis: several samples per knot span)
    gram = (B0s.T @ B0s).tocsc()
    fit = spsolve((gram + 1e-14 * gram.diagonal().mean() * sparse.eye(n)).tocsc(), B0s.T @ pts)
    x_cur = None
    x_lin = np.concatenate((fit[:, 0], fit[:, 1]))
    d1 = np.stack((B1s @ x_lin[:n], B1s @ x_lin[n:]), axis=1)  # the spline's first derivative at xs
    msg = "max steps"
    steps = 0
    f_prev = math.inf
    for it in range(1, MAX_STEPS + 1):
        steps = it
        tree = cKDTree(pts)
        # no gouge: supporting half-planes of every programmed element within reach
        m, e = prog.near(pts, reach, tree)
        ft = prog.feet(e, pts[m])
        ok = ft.dist > 1e-9
        m, e, foot = m[ok], e[ok], ft.foot[ok]
        nv = (pts[m] - foot) / ft.dist[ok][:, None]
        A_ng = rows(B0s, m, nv, n)
        # at least R, or as far as the exact path is at that place where it is closer (the
        # controller's near-tangent joints: R·(1 − cos turn) at most, accepted by the verification)
        clear_ref = np.minimum(R, prog.distances(e, ref_pts[m]))
        lo_ng = np.sum(nv * foot, axis=1) + clear_ref + _sag_margin(d1, B2s @ x_lin[:n], B2s @ x_lin[n:], gap, ramp)[m]
        # tolerance: distance beyond the exact path on the free side (nearest exact element, and
        # both elements at the joints)
        m, e = nearest(exact, pts, near_exact, tree)
        m, e = np.concatenate((m, joint_m)), np.concatenate((e, joint_e))
        feet, mv, radial = free_directions(exact, e, pts[m], site.material_sign, two_sided)
        A_tol = rows(B0s, m, mv, n)
        bound = np.sum(mv * feet, axis=1)
        # without compensation the spline keeps within ε of the path on both sides
        both = ~radial if two_sided else np.zeros(len(m), bool)
        # sliding along the curve changes only the parametrisation: penalised, so the spline keeps
        # about unit speed (its second derivative stays its curvature)
        tan = d1 / np.maximum(np.hypot(d1[:, 0], d1[:, 1]), 1e-300)[:, None]
        T = rows(B0s, np.arange(len(xs)), tan, n)
        P_step = (Pprox + SLIDE * h_scale * (T.T @ T)).tocsc()
        # the QP in the step from x_lin: the rows' bounds less their values there
        ax_tol = A_tol @ x_lin
        res = solve_rows(
            P_step,
            Pm @ x_lin,
            (A_eq, b_eq - A_eq @ x_lin),
            [(A_ng, lo_ng - A_ng @ x_lin), (A_tol[both], (bound - eps_t)[both] - ax_tol[both])],
            [(A_tol, bound + eps_t - ax_tol)],
        )
        if res.x is None:
            msg = f"qp: {res.status}"
            break
        x_cur = x_lin = x_lin + res.x
        new_pts = np.stack((B0s @ x_cur[:n], B0s @ x_cur[n:]), axis=1)
        # movement across the curve (sliding along it is a change of parametrisation only)
        d1 = np.stack((B1s @ x_cur[:n], B1s @ x_cur[n:]), axis=1)
        tan = d1 / np.maximum(np.hypot(d1[:, 0], d1[:, 1]), 1e-300)[:, None]
        move = new_pts - pts
        step = float(np.max(np.abs(move[:, 0] * tan[:, 1] - move[:, 1] * tan[:, 0])))
        pts = new_pts
        f = 0.5 * float(x_cur @ (Pm @ x_cur))
        # converged: the curve stopped moving, or it moves a few µm a step with ∫κ² settled (the
        # linearised half-planes turn a little at every step; the final checks are exact)
        if step < CONVERGED_MM or (step < SETTLED_MM and f_prev - f < SETTLED_GAIN * f_prev):
            msg = "converged"
            break
        f_prev = f
    if x_cur is None:
        return ChainSolution(False, msg, [], math.inf, 0.0, math.inf, steps, time.perf_counter() - t0)
    cx, cy = BSpline(knots, x_cur[:n], 3), BSpline(knots, x_cur[n:], 3)
    # exact checks on dense samples
    dense = np.linspace(0.0, S, max(2001, int(S / 0.01)))
    P = np.stack((cx(dense), cy(dense)), axis=1)
    tree = cKDTree(P)
    # the clearance: the least distance within R + 1 mm, found among the closer pairs when there are
    # any (the spline runs within ε of the exact path, at R from the part)
    _, _, d = prog.near_distances(P, R + near_exact, tree, ordered=False)
    if not len(d):
        _, _, d = prog.near_distances(P, R + 1.0, tree, ordered=False)
    clear = float(d.min()) if len(d) else math.inf
    # the exact path's own clearance along the run (below R only at near-tangent joints)
    dense_idx = np.clip(np.searchsorted(cum, dense, side="right") - 1, 0, ref.n - 1)
    Q = ref.points(dense_idx, np.clip((dense - cum[dense_idx]) / ref.length[dense_idx], 0.0, 1.0))
    _, _, d = prog.near_distances(Q, R, cKDTree(Q), ordered=False)
    need = min(R, float(d.min()) if len(d) else R) - 1e-9
    m, e = nearest(exact, P, near_exact + eps, tree)
    feet, mv, _ = free_directions(exact, e, P[m], site.material_sign, two_sided)
    along = np.sum((P[m] - feet) * mv, axis=1)
    offset = max(0.0, float((np.abs(along) if two_sided else along).max(initial=0.0)))
    if len(m) < len(P):  # a point farther than that from the exact path
        offset = math.inf
    d1 = np.stack((cx(dense, 1), cy(dense, 1)), axis=1)
    d2 = np.stack((cx(dense, 2), cy(dense, 2)), axis=1)
    sp = np.hypot(d1[:, 0], d1[:, 1])
    kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(sp, 1e-300) ** 3
    ok = clear >= need and offset <= eps and float(sp.min()) > 0.2
    if not ok:
        why = f"clearance {clear:.6f} < R" if clear < need else f"offset {offset:.5f} mm > ε"
        if float(sp.min()) <= 0.2:
            why = "degenerate parametrisation"
        msg = f"{msg}; {why}"
    cuts = np.concatenate(([0.0], cum[1:-1], [S]))
    pp = ppoly(cx, cy) if ok else None
    polys = pieces(pp, cuts, site.w) if pp is not None else []
    return ChainSolution(ok, msg, polys, float(kappa.max()), clear, offset, steps, time.perf_counter() - t0)
