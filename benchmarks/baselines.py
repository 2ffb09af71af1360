"""Corner-smoothing baselines from the literature, implemented from the papers' descriptions.

Run:  python benchmarks/baselines.py      (prints a table of cycle times; numpy only)

Two planners for a polyline of G01 moves under *vector* limits V (mm/s), A (mm/s²), J (mm/s³):

1. :func:`g01_baseline` — the classic G01 junction-speed planner used as the reference in the
   corner-smoothing literature (e.g. the comparison tables of Zhao, Zhu & Ding 2013 and of
   Xu & Sun 2018): the path is *not* smoothed, the tool passes every vertex at

       v_j = min(V, A·Ts / (2·sin β + 1e-6)),   β = half the turning angle at the vertex,

   i.e. the velocity vector may turn by at most A·Ts within one interpolation period Ts
   (|Δv| = 2·v·sin β for a turn of 2β), speed 0 at the start and the end. Every block is a
   jerk-limited S-curve (see below) between its entry and exit speed, the speeds made
   feasible by a bidirectional scan (:func:`bidirectional_scan`).

2. :func:`zhao2013` — H. Zhao, L. Zhu, H. Ding, "A real-time look-ahead interpolation
   methodology with curvature-continuous B-spline transition scheme for CNC machining of
   short line segments", Int. J. Machine Tools & Manufacture 65 (2013) 88–98.
   Every interior corner is replaced by a symmetric cubic B-spline with five control points
   (the paper's form; see :class:`Transition` for the derivation of the deviation and the
   curvature), G2 with both lines; the speed on a transition is capped by its curvature
   maximum, the feed along lines and transitions is the same jerk-limited S-curve over the
   arc length of the smoothed path with a bidirectional scan.

   Readings chosen where the description leaves room (the paper itself was not at hand):
   * overlap: a transition replaces 2d of each adjacent line and may use at most half of each
     (2d ≤ min(L_in, L_out)/2), so neighbours never overlap; a shortened transition has a
     deviation below ε;
   * speed cap min(V, sqrt(A/κmax), (J/κmax²)^(1/3)) imposed at the transition's middle, which
     becomes a look-ahead junction (blocks run from one transition middle to the next). The
     conservative alternative, the cap held over the whole transition, is available as
     ``transition_speed="constant"`` and is much slower (0.571 s instead of 0.368 s on the
     rotated square, where Xu & Sun 2018 report 0.405 s);
   * no chord-error or interpolation-period quantisation of the feed; times are continuous.

The jerk-limited S-curve (:func:`plan_block`, :class:`Profile`)
-----------------------------------------------------------------
A speed change v0 → v1 under jerk J and acceleration A (jerk +J, [constant A,] jerk −J) takes

    T = Δv/A + A/J        if Δv > A²/J   (the acceleration reaches A: 3 phases)
    T = 2·sqrt(Δv/J)      otherwise      (triangular acceleration: 2 phases)

and, the speed curve being point-symmetric about its midpoint, covers the distance
(v0 + v1)/2 · T. A block is acceleration + cruise + deceleration: the 7-phase profile. A block
too short to reach its cruise cap gets the highest peak speed for which acceleration and
deceleration fit its length, found by bisection (the remainder of the bisection is a cruise of
at most a few ulp of the length, so the profile ends exactly at the block's end). With the
reference limits (V = 100 < A²/J = 150 mm/s) no speed change ever reaches A, so the
constant-acceleration phases are empty and the profile is the 5-phase S-curve (jerk-up,
jerk-down, cruise, jerk-down, jerk-up) of Zhao et al.: the two papers' S-curves coincide here.

Reference check (rotated square, see :func:`rotated_square`): the G01 baseline gives
0.453818 s against the published reproduction's 0.45382 s. Its corners are 90°, where half the
turning angle and half the interior angle are both 45°, so the reference cannot tell those two
readings of β apart; the turning-angle reading is the one with the physical meaning above (a
straight continuation, β = 0, must not limit the speed) and is the one implemented.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "Limits",
    "Profile",
    "PlanResult",
    "Transition",
    "accel_time",
    "accel_distance",
    "reachable_speed",
    "plan_block",
    "bidirectional_scan",
    "vector_load",
    "g01_baseline",
    "zhao_transitions",
    "transition_cap",
    "zhao2013",
    "normal_load",
    "rotated_square",
    "butterfly",
    "zigzag",
    "main",
]

#: Relative slack accepted when a scan result is fed back into :func:`plan_block` (rounding only).
_FEAS_RTOL = 1e-9


@dataclass(frozen=True)
class Limits:
    """Vector limits: feed V (mm/s), acceleration A (mm/s²), jerk J (mm/s³), period Ts (s)."""

    V: float = 100.0
    A: float = 3000.0
    J: float = 60000.0
    Ts: float = 0.0005


# --------------------------------------------------------------------------------------------
# Jerk-limited S-curve
# --------------------------------------------------------------------------------------------


def accel_time(dv: float, A: float, J: float) -> float:
    """Duration of a jerk-limited speed change of magnitude ``dv`` (closed form, see module doc)."""
    dv = abs(dv)
    if dv <= 0.0:
        return 0.0
    if dv > A * A / J:
        return dv / A + A / J
    return 2.0 * math.sqrt(dv / J)


def accel_distance(v0: float, v1: float, A: float, J: float) -> float:
    """Distance covered by the jerk-limited speed change v0 → v1 (either direction)."""
    return 0.5 * (v0 + v1) * accel_time(v1 - v0, A, J)


def reachable_speed(v0: float, length: float, A: float, J: float, vmax: float = math.inf) -> float:
    """Highest speed reachable from ``v0`` (or from which ``v0`` is reachable) within ``length``.

    Closed form: with Δv ≤ A²/J the distance is (2·v0 + J·x²)·x for x = sqrt(Δv/J), a monotone
    cubic in x (one real root, Cardano in its hyperbolic form); beyond, it is
    (2·v0 + Δv)(Δv/A + A/J)/2, a quadratic in Δv. The result is stepped down by an ulp or two
    where v0 + Δv rounds up, so the change always fits ``length``.
    """
    if length <= 0.0 or v0 >= vmax:
        return min(v0, vmax)
    dv_knee = A * A / J
    if length <= accel_distance(v0, v0 + dv_knee, A, J):
        # J x³ + 2 v0 x − L = 0  →  x³ + p x + q = 0 (one real root; hyperbolic form, stable)
        p = 2.0 * v0 / J
        q = -length / J
        if p > 0.0:
            r = math.sqrt(p / 3.0)
            x = -2.0 * r * math.sinh(math.asinh(1.5 * q / (p * r)) / 3.0)
        else:
            x = math.cbrt(-q)
        dv = J * x * x
    else:
        # dv²/A + dv (2 v0/A + A/J) + 2 v0 A/J − 2 L = 0, positive root in the stable form
        a2 = 1.0 / A
        b2 = 2.0 * v0 / A + A / J
        c2 = 2.0 * v0 * A / J - 2.0 * length
        dv = -2.0 * c2 / (b2 + math.sqrt(b2 * b2 - 4.0 * a2 * c2))
    v = min(v0 + max(dv, 0.0), vmax)
    # v0 + dv rounds; step down to the nearest representable speed whose change fits the length
    for _ in range(65):
        if v <= v0 or accel_distance(v0, v, A, J) <= length:
            return v
        v = float(np.nextafter(v, -math.inf))
    return v0


def _phase(v_from: float, v_to: float, A: float, J: float) -> list[tuple[float, float]]:
    """(duration, jerk) pieces of the speed change v_from → v_to."""
    dv = v_to - v_from
    if dv == 0.0:
        return []
    sign = 1.0 if dv > 0 else -1.0
    dv = abs(dv)
    if dv > A * A / J:
        tj = A / J
        return [(tj, sign * J), (dv / A - tj, 0.0), (tj, -sign * J)]
    tj = math.sqrt(dv / J)
    return [(tj, sign * J), (tj, -sign * J)]


@dataclass(frozen=True)
class Profile:
    """Jerk-limited S-curve of one block: piecewise-constant jerk, starting at s = 0, a = 0."""

    length: float
    v_entry: float
    v_exit: float
    v_peak: float
    pieces: tuple[tuple[float, float], ...]  # (duration s, jerk mm/s³)

    @property
    def duration(self) -> float:
        return float(sum(t for t, _ in self.pieces))

    def knots(self) -> np.ndarray:
        """State (t, s, v, a) at the start of every piece and at the end, shape (n+1, 4)."""
        out = [(0.0, 0.0, self.v_entry, 0.0)]
        t, s, v, a = out[0]
        for dt, j in self.pieces:
            s = s + v * dt + a * dt * dt / 2.0 + j * dt**3 / 6.0
            v = v + a * dt + j * dt * dt / 2.0
            a = a + j * dt
            t = t + dt
            out.append((t, s, v, a))
        return np.array(out)

    def sample(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Exact (s, v, a, jerk) at times ``t`` (clipped to [0, duration])."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        k = self.knots()
        jerks = np.array([j for _, j in self.pieces] + [0.0])
        idx = np.clip(np.searchsorted(k[:, 0], t, side="right") - 1, 0, len(self.pieces) - 1 if self.pieces else 0)
        if not self.pieces:
            z = np.zeros_like(t)
            return z, z + self.v_entry, z, z
        tau = t - k[idx, 0]
        s0, v0, a0, j = k[idx, 1], k[idx, 2], k[idx, 3], jerks[idx]
        s = s0 + v0 * tau + a0 * tau**2 / 2.0 + j * tau**3 / 6.0
        v = v0 + a0 * tau + j * tau**2 / 2.0
        a = a0 + j * tau
        return s, v, a, j


def plan_block(length: float, v_entry: float, v_exit: float, vmax: float, A: float, J: float) -> Profile:
    """7-phase S-curve over ``length`` from ``v_entry`` to ``v_exit``, cruise at most ``vmax``.

    Raises ``ValueError`` when even the direct change v_entry → v_exit does not fit (the scan
    must have lowered the speeds before).
    """
    if v_entry > vmax * (1 + _FEAS_RTOL) or v_exit > vmax * (1 + _FEAS_RTOL):
        raise ValueError("entry/exit speed above the block's cruise cap")
    v_entry, v_exit = min(v_entry, vmax), min(v_exit, vmax)
    direct = accel_distance(v_entry, v_exit, A, J)
    if direct > length * (1 + _FEAS_RTOL) + 1e-12:
        raise ValueError(f"v {v_entry:g} -> {v_exit:g} infeasible within {length:g} mm (needs {direct:g} mm)")

    def need(vp: float) -> float:
        return accel_distance(v_entry, vp, A, J) + accel_distance(vp, v_exit, A, J)

    if need(vmax) <= length:
        vp = vmax
    else:
        lo, hi = max(v_entry, v_exit), vmax
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if need(mid) <= length:
                lo = mid
            else:
                hi = mid
            if hi - lo <= 1e-13 * max(hi, 1.0):
                break
        vp = lo
    cruise_len = max(length - need(vp), 0.0)
    pieces = _phase(v_entry, vp, A, J)
    if cruise_len > 0.0 and vp > 0.0:
        pieces.append((cruise_len / vp, 0.0))
    pieces += _phase(vp, v_exit, A, J)
    return Profile(float(length), float(v_entry), float(v_exit), float(vp), tuple(pieces))


def bidirectional_scan(
    lengths: Sequence[float], junction_caps: Sequence[float], A: float, J: float
) -> np.ndarray:
    """Feasible junction speeds (len(lengths)+1 values) under the given caps.

    Backward pass (from the end, how fast may each block be entered so that its exit speed is
    reachable), then forward pass (how fast can each block be left from its entry speed). After
    both passes every |v_k → v_k+1| speed change fits its block.
    """
    n = len(lengths)
    caps = np.asarray(junction_caps, dtype=float)
    if caps.shape != (n + 1,):
        raise ValueError("need one cap per junction (blocks + 1)")
    w = caps.copy()
    for i in range(n - 1, -1, -1):
        w[i] = min(w[i], reachable_speed(w[i + 1], lengths[i], A, J))
    u = w.copy()
    for i in range(n):
        u[i + 1] = min(u[i + 1], reachable_speed(u[i], lengths[i], A, J))
    return u


@dataclass
class PlanResult:
    """Total time, junction speeds and per-block profiles of a plan."""

    total_time: float
    junction_speeds: np.ndarray
    profiles: list[Profile]
    caps: np.ndarray  # cruise cap per block
    transitions: list[Transition] = field(default_factory=list)
    transition_starts: np.ndarray = field(default_factory=lambda: np.zeros(0))  # arc length at each start


def _time_blocks(lengths: Sequence[float], block_caps: Sequence[float], junction_caps: Sequence[float],
                 lim: Limits) -> PlanResult:
    lengths = np.asarray(lengths, dtype=float)
    block_caps = np.asarray(block_caps, dtype=float)
    jc = np.asarray(junction_caps, dtype=float).copy()
    # a junction speed may not exceed the cruise cap of either block it joins
    jc[:-1] = np.minimum(jc[:-1], block_caps)
    jc[1:] = np.minimum(jc[1:], block_caps)
    v = bidirectional_scan(lengths, jc, lim.A, lim.J)
    profiles = [plan_block(L, v[i], v[i + 1], block_caps[i], lim.A, lim.J) for i, L in enumerate(lengths)]
    return PlanResult(float(sum(p.duration for p in profiles)), v, profiles, block_caps)


def _clean(points: np.ndarray) -> np.ndarray:
    pts = np.asarray(points, dtype=float)
    keep = np.r_[True, np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-12]
    return pts[keep]


def _turning_angles(pts: np.ndarray) -> np.ndarray:
    """Turning angle (rad, 0 = straight on) at every interior vertex."""
    d = np.diff(pts, axis=0)
    u = d / np.linalg.norm(d, axis=1)[:, None]
    c = np.clip(np.einsum("ij,ij->i", u[:-1], u[1:]), -1.0, 1.0)
    return np.arccos(c)


# --------------------------------------------------------------------------------------------
# 1. G01 junction-speed baseline
# --------------------------------------------------------------------------------------------


def g01_baseline(points: np.ndarray, lim: Limits = Limits()) -> PlanResult:
    """G01 baseline: stop-free junctions at v_j = min(V, A·Ts/(2 sin β + 1e-6)), β = turn/2.

    Start and end speed 0; every block a 7-phase S-curve; bidirectional scan. Returns the total
    time and the per-block profiles.
    """
    pts = _clean(points)
    lengths = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    beta = 0.5 * _turning_angles(pts)
    vj = np.minimum(lim.V, lim.A * lim.Ts / (2.0 * np.sin(beta) + 1e-6))
    caps = np.r_[0.0, vj, 0.0]
    return _time_blocks(lengths, np.full(len(lengths), lim.V), caps, lim)


# --------------------------------------------------------------------------------------------
# 2. Zhao, Zhu & Ding 2013: curvature-continuous cubic B-spline transitions
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Transition:
    """Symmetric 5-control-point cubic B-spline at one corner (Zhao, Zhu & Ding 2013).

    Control points, with P the corner vertex, a the unit vector from P back along the incoming
    line, b the unit vector from P along the outgoing line and d the control-point spacing::

        B0 = P + 2d·a,  B1 = P + d·a,  B2 = P,  B3 = P + d·b,  B4 = P + 2d·b

    knot vector [0, 0, 0, 0, 1/2, 1, 1, 1, 1]. B0, B1, B2 collinear (and B2, B3, B4) make the
    curve tangent to both lines with zero curvature at its ends: G2 with the lines; it replaces
    a length 2d of each line.

    Derivation. Inserting the knot 1/2 twice (Boehm) gives two cubic Bézier pieces,
    [B0, B1, (B1+B2)/2, M] and [M, (B2+B3)/2, B3, B4] with M = C(1/2) = (B1 + 2·B2 + B3)/4.
    Hence C(1/2) − P = d·(a + b)/4 and, with θ the turning angle (π − θ the angle between the
    lines), |a + b| = 2·sin(θ/2):

        ε = |C(1/2) − P| = (d/2)·sin(θ/2)        ⇔    d = 2ε / sin(θ/2).

    C(1/2) is on the bisector and is the point of the curve closest to P (the deviation of the
    corner). At the end of the first Bézier piece (local parameter t = 1, i.e. u = 1/2, with
    P = 0): C' = 3(M − (B1+B2)/2) = 3d(b − a)/4 and C'' = 6(M − (B1+B2) + B1) = 3d(a + b)/2, so
    |C' × C''| = (9d²/8)·|(b − a) × (a + b)| = (9d²/4)·sin θ, |C'| = (3d/2)·cos(θ/2) and

        κ(1/2) = 4·sin(θ/2) / (3·d·cos²(θ/2))      (= 2·tan²(θ/2)/(3ε) at d = 2ε/sin(θ/2)).

    The curvature maximum is at the middle: checked numerically for turning angles 1°–179°
    (and by the test suite), so κmax = κ(1/2).
    """

    vertex: np.ndarray
    a: np.ndarray
    b: np.ndarray
    theta: float
    d: float
    d_eps: float  # spacing the tolerance alone would allow

    @property
    def control_points(self) -> np.ndarray:
        P, a, b, d = self.vertex, self.a, self.b, self.d
        return np.array([P + 2 * d * a, P + d * a, P, P + d * b, P + 2 * d * b])

    @property
    def knots(self) -> np.ndarray:
        return np.array([0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0])

    @property
    def shortened(self) -> bool:
        return self.d < self.d_eps * (1 - 1e-12)

    @property
    def deviation(self) -> float:
        return 0.5 * self.d * math.sin(0.5 * self.theta)

    @property
    def kappa_max(self) -> float:
        return 4.0 * math.sin(0.5 * self.theta) / (3.0 * self.d * math.cos(0.5 * self.theta) ** 2)

    @property
    def span(self) -> float:
        """Length of each line the transition replaces (2d)."""
        return 2.0 * self.d

    def bezier(self) -> tuple[np.ndarray, np.ndarray]:
        B = self.control_points
        M = (B[1] + 2 * B[2] + B[3]) / 4.0
        return (np.array([B[0], B[1], (B[1] + B[2]) / 2, M]), np.array([M, (B[2] + B[3]) / 2, B[3], B[4]]))

    def evaluate(self, u: np.ndarray, der: int = 0) -> np.ndarray:
        """Point (der=0) or derivative (1, 2) w.r.t. the B-spline parameter u ∈ [0, 1]."""
        u = np.atleast_1d(np.asarray(u, dtype=float))
        first, second = self.bezier()
        out = np.empty((len(u), len(self.vertex)))
        for piece, mask, t in ((first, u <= 0.5, 2 * u), (second, u > 0.5, 2 * u - 1)):
            tt = t[mask][:, None]
            if der == 0:
                val = ((1 - tt) ** 3 * piece[0] + 3 * tt * (1 - tt) ** 2 * piece[1]
                       + 3 * tt**2 * (1 - tt) * piece[2] + tt**3 * piece[3])
            elif der == 1:
                val = 2 * 3 * ((1 - tt) ** 2 * (piece[1] - piece[0]) + 2 * tt * (1 - tt) * (piece[2] - piece[1])
                               + tt**2 * (piece[3] - piece[2]))
            elif der == 2:
                val = 4 * 6 * ((1 - tt) * (piece[2] - 2 * piece[1] + piece[0]) + tt * (piece[3] - 2 * piece[2]
                                                                                       + piece[1]))
            else:
                raise ValueError("der must be 0, 1 or 2")
            out[mask] = val
        return out

    def curvature(self, u: np.ndarray) -> np.ndarray:
        d1, d2 = self.evaluate(u, 1), self.evaluate(u, 2)
        n1 = np.einsum("ij,ij->i", d1, d1)
        if d1.shape[1] == 2:
            cross = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        else:
            cross = np.linalg.norm(np.cross(d1, d2), axis=1)
        return cross / n1**1.5

    @property
    def arc_length(self) -> float:
        """Arc length: 16-point Gauss–Legendre on a grading toward the middle of the curve, where
        |C'| nearly vanishes for sharp turns (relative error < 1e-12 for turns up to 179.9°)."""
        x, w = np.polynomial.legendre.leggauss(16)
        # breakpoints in the first half u ∈ [0, 1/2], geometric toward u = 1/2; mirrored for the second
        edges = 0.5 - 0.5 * np.r_[0.5 ** np.arange(40), 0.0]
        lo, hi = edges[:-1], edges[1:]
        mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        u = (mid[:, None] + half[:, None] * x[None, :]).ravel()
        ww = (half[:, None] * w[None, :]).ravel()
        first = float(np.sum(ww * np.linalg.norm(self.evaluate(u, 1), axis=1)))
        second = float(np.sum(ww * np.linalg.norm(self.evaluate(1.0 - u, 1), axis=1)))
        return first + second


def zhao_transitions(points: np.ndarray, eps: float, share: float = 0.5) -> list[Transition | None]:
    """One transition per interior vertex (``None`` where the path goes straight on).

    Spacing d = 2ε/sin(θ/2) (deviation exactly ε), shortened adaptively so that a transition
    uses at most ``share`` (default half) of each adjacent line: 2d ≤ share·min(L_in, L_out).
    With share ≤ 1/2 two transitions sharing a line can never overlap; a shortened transition
    keeps the same shape at a smaller scale, so its deviation (d/2)·sin(θ/2) stays below ε.
    """
    pts = _clean(points)
    d_vec = np.diff(pts, axis=0)
    lengths = np.linalg.norm(d_vec, axis=1)
    u = d_vec / lengths[:, None]
    theta = _turning_angles(pts)
    out: list[Transition | None] = []
    for k, th in enumerate(theta):
        if th < 1e-9:
            out.append(None)
            continue
        d_eps = 2.0 * eps / math.sin(0.5 * th)
        d = min(d_eps, 0.5 * share * min(lengths[k], lengths[k + 1]))
        out.append(Transition(pts[k + 1].copy(), -u[k], u[k + 1].copy(), float(th), float(d), float(d_eps)))
    return out


def transition_cap(t: Transition, lim: Limits, every_term: bool = False) -> float:
    """Speed cap of a transition: min(V, sqrt(A/κmax), (J/κmax²)^(1/3)); with ``every_term`` the
    jerk of the curvature change as well: at constant speed ``|j| = v³·sqrt(κ⁴ + κ′²)`` (κ′ =
    dκ/ds, sampled), so ``v ≤ (J / max sqrt(κ⁴ + κ′²))^(1/3)``."""
    kap = t.kappa_max
    cap = min(lim.V, math.sqrt(lim.A / kap), (lim.J / kap**2) ** (1.0 / 3.0))
    if every_term:
        u = np.linspace(0.0, 1.0, 4001)
        k = t.curvature(u)
        worst = float(np.max(np.hypot(k * k, np.gradient(k, _arc_param(t, u)))))
        cap = min(cap, (lim.J / worst) ** (1.0 / 3.0))
    return cap


def zhao2013(points: np.ndarray, eps: float, lim: Limits = Limits(), share: float = 0.5,
             transition_speed: str = "midpoint") -> PlanResult:
    """Zhao, Zhu & Ding (2013): B-spline transitions + curvature-limited look-ahead S-curve.

    The smoothed path is line, transition, line, …, line (the start and end vertex are not
    blended), transitions from :func:`zhao_transitions`. Each transition gets the speed cap
    min(V, sqrt(A/κmax), (J/κmax²)^(1/3)) (κmax at its middle: centripetal acceleration
    v²κ ≤ A and the circle's normal jerk v³κ² ≤ J there). The jerk-limited S-curve of
    :func:`plan_block` runs over arc length after a bidirectional scan, start and end speed 0.

    ``transition_speed`` chooses where the cap applies:

    * ``"midpoint"`` (default, the reading used for the benchmark): the middle of every
      transition — its curvature maximum — is a look-ahead junction whose speed is capped; the
      S-curve blocks run from one transition middle to the next (half transition + trimmed line
      + half transition), cruising at V. Away from the middle the curvature falls (to 0 at the
      ends) and the speed may rise; :func:`normal_load` reports what v²κ and v³κ² that gives.
    * ``"constant"``: conservative variant, every transition is its own block with the cap as
      its cruise limit (crossed at constant speed between long lines).
    * ``"every-term"``: ``"constant"`` with the cap bounding the jerk of the curvature change as
      well (:func:`transition_cap` ``every_term``) — the reading that keeps |j| ≤ J
      (:func:`vector_load`), not in the paper.
    """
    if transition_speed not in ("midpoint", "constant", "every-term"):
        raise ValueError("transition_speed must be 'midpoint', 'constant' or 'every-term'")
    every = transition_speed == "every-term"
    if every:
        transition_speed = "constant"
    pts = _clean(points)
    lengths = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    trans = zhao_transitions(pts, eps, share)
    trim = lengths.copy()
    for k, t in enumerate(trans):
        if t is not None:
            trim[k] -= t.span
            trim[k + 1] -= t.span
    trim = np.maximum(trim, 0.0)
    block_len: list[float] = []
    block_cap: list[float] = []
    junction_cap: list[float] = [0.0]
    starts: list[float] = []
    s_path = 0.0
    acc_len = 0.0  # midpoint mode: length of the block being assembled
    for k in range(len(lengths)):
        s_path += trim[k]
        if transition_speed == "constant":
            block_len.append(float(trim[k]))
            block_cap.append(lim.V)
            junction_cap.append(math.inf)
        else:
            acc_len += trim[k]
        t = trans[k] if k < len(trans) else None
        if t is None:
            continue
        starts.append(s_path)
        arc = t.arc_length
        s_path += arc
        cap = transition_cap(t, lim, every)
        if transition_speed == "constant":
            block_len.append(arc)
            block_cap.append(cap)
            junction_cap.append(math.inf)
        else:
            block_len.append(acc_len + 0.5 * arc)
            block_cap.append(lim.V)
            junction_cap.append(cap)
            acc_len = 0.5 * arc
    if transition_speed == "midpoint":
        block_len.append(acc_len)
        block_cap.append(lim.V)
        junction_cap.append(0.0)
    else:
        junction_cap[-1] = 0.0
    res = _time_blocks(block_len, block_cap, junction_cap, lim)
    res.transitions = [t for t in trans if t is not None]
    res.transition_starts = np.array(starts)
    return res


def _arc_param(t: Transition, u: np.ndarray) -> np.ndarray:
    """Arc length along transition ``t`` at its parameters ``u`` (trapezoid of |C′|, scaled to
    the transition's arc length)."""
    speed = np.linalg.norm(t.evaluate(u, 1), axis=1)
    s_loc = np.r_[0.0, np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(u))]
    return s_loc * (t.arc_length / s_loc[-1])


def _transition_states(res: PlanResult, samples: int, per_block: int):
    """Per transition of a :func:`zhao2013` plan: curvature κ, dκ/ds and the planned v, a_t, j_t
    at ``samples`` parameters (the profiles sampled ``per_block`` times and at their knots)."""
    parts = []
    offset = 0.0
    for p in res.profiles:
        t = np.unique(np.r_[np.linspace(0.0, p.duration, per_block), p.knots()[:, 0]])
        s, v, a, j = p.sample(t)
        parts.append(np.c_[s + offset, v, a, j])
        offset += p.length
    table = np.concatenate(parts)
    table = table[np.argsort(table[:, 0], kind="stable")]
    u = np.linspace(0.0, 1.0, samples)
    for t, s0 in zip(res.transitions, res.transition_starts, strict=True):
        s_loc = _arc_param(t, u)
        v, a_t, j_t = (np.interp(s0 + s_loc, table[:, 0], table[:, c]) for c in (1, 2, 3))
        kap = t.curvature(u)
        yield kap, np.gradient(kap, s_loc), v, a_t, j_t


def normal_load(res: PlanResult, lim: Limits, samples: int = 801) -> tuple[float, float]:
    """Largest v²κ/A and v³κ²/J on the transitions of a :func:`zhao2013` plan (sampled)."""
    acc = jerk = 0.0
    for kap, _, v, _, _ in _transition_states(res, samples, 400):
        acc = max(acc, float(np.max(v**2 * kap)) / lim.A)
        jerk = max(jerk, float(np.max(v**3 * kap**2)) / lim.J)
    return acc, jerk


def vector_load(res: PlanResult, lim: Limits, samples: int = 2001) -> tuple[float, float]:
    """Largest |a|/A and |j|/J on the transitions of a :func:`zhao2013` plan, with every term:
    ``a = a_t·T + κv²·N`` and ``j = (j_t − κ²v³)·T + (3κ·v·a_t + κ′v³)·N`` (plane curve in arc
    length; κ′ = dκ/ds). :func:`normal_load` keeps only κv² and κ²v³, the terms the plan's
    speed cap controls."""
    acc = jerk = 0.0
    for kap, dkap, v, a_t, j_t in _transition_states(res, samples, 2000):
        a_norm = np.hypot(a_t, kap * v**2)
        j_norm = np.hypot(j_t - kap**2 * v**3, 3.0 * kap * v * a_t + dkap * v**3)
        acc = max(acc, float(np.max(a_norm)) / lim.A)
        jerk = max(jerk, float(np.max(j_norm)) / lim.J)
    return acc, jerk


# --------------------------------------------------------------------------------------------
# Test paths
# --------------------------------------------------------------------------------------------


def rotated_square() -> np.ndarray:
    """(2,0) → (4,2) → (2,4) → (0,2) → (2,0) mm: three interior 90° corners."""
    return np.array([(2.0, 0.0), (4.0, 2.0), (2.0, 4.0), (0.0, 2.0), (2.0, 0.0)])


def butterfly(n: int = 100, size: float = 50.0) -> np.ndarray:
    """Closed outline r(θ) = e^{sin θ} − 2 cos 4θ + sin⁵((2θ − π)/24) at ``n`` points, θ ∈ [0, 2π),
    scaled so that its bounding box is ``size`` mm wide (larger side); the first point is repeated at
    the end (that vertex is not blended)."""
    th = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    r = np.exp(np.sin(th)) - 2.0 * np.cos(4.0 * th) + np.sin((2.0 * th - np.pi) / 24.0) ** 5
    xy = np.c_[r * np.cos(th), r * np.sin(th)]
    xy *= size / np.ptp(xy, axis=0).max()
    return np.vstack([xy, xy[:1]])


def zigzag(n: int = 100, max_turn_deg: float = 170.0, seed: int = 2013) -> np.ndarray:
    """Random zig-zag of ``n`` points: segment lengths U[0.5, 5] mm, turns of alternating sign with
    magnitude U[10°, max_turn_deg] (fixed seed)."""
    rng = np.random.default_rng(seed)
    lengths = rng.uniform(0.5, 5.0, n - 1)
    turns = np.radians(rng.uniform(10.0, max_turn_deg, n - 2)) * np.where(np.arange(n - 2) % 2 == 0, 1.0, -1.0)
    heading = np.r_[0.0, np.cumsum(turns)]
    steps = lengths[:, None] * np.c_[np.cos(heading), np.sin(heading)]
    return np.vstack([np.zeros(2), np.cumsum(steps, axis=0)])


#: Published value for the rotated square (public reproduction of F. Xu, Y. Sun, "A circumscribed
#: corner rounding method based on double cubic B-splines for a five-axis linear tool path",
#: Int. J. Adv. Manuf. Technol. 94 (2018) 451–462), not recomputed here.
XU_SUN_2018_SQUARE = 0.40467
#: Published G01-baseline value for the rotated square from the same reproduction.
G01_SQUARE_REFERENCE = 0.45382


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Corner-smoothing baselines: G01 junction speed, Zhao 2013.")
    parser.add_argument("--V", type=float, default=100.0)
    parser.add_argument("--A", type=float, default=3000.0)
    parser.add_argument("--J", type=float, default=60000.0)
    parser.add_argument("--Ts", type=float, default=0.0005)
    args = parser.parse_args(argv)
    lim = Limits(args.V, args.A, args.J, args.Ts)
    cases = [
        ("rotated square (3 x 90 deg)", rotated_square(), 0.2),
        ("butterfly, 100 pts, ~50 mm", butterfly(), 0.05),
        ("zig-zag, 100 pts, turns <= 170 deg", zigzag(), 0.05),
    ]
    print(f"limits: V={lim.V:g} mm/s, A={lim.A:g} mm/s^2, J={lim.J:g} mm/s^3, Ts={lim.Ts:g} s (vector)\n")
    print("| path | segments | length mm | eps mm | method | time s | notes |")
    print("|---|---|---|---|---|---|---|")
    for name, pts, eps in cases:
        pts = _clean(pts)
        length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
        nseg = len(pts) - 1
        g = g01_baseline(pts, lim)
        note = f"reference {G01_SQUARE_REFERENCE}" if name.startswith("rotated") else ""
        print(f"| {name} | {nseg} | {length:.3f} | {eps:g} | G01 junction speed | {g.total_time:.5f} | {note} |")
        for mode, label in (("midpoint", "Zhao, Zhu & Ding 2013"),
                            ("constant", "Zhao 2013, cap held over whole transition")):
            z = zhao2013(pts, eps, lim, transition_speed=mode)
            tr = z.transitions
            caps = [transition_cap(t, lim) for t in tr] or [lim.V]
            nshort = sum(t.shortened for t in tr)
            acc, jerk = normal_load(z, lim)
            print(f"| {name} | {nseg} | {length:.3f} | {eps:g} | {label} | {z.total_time:.5f} | "
                  f"{len(tr)} transitions ({nshort} shortened), max dev {max(t.deviation for t in tr):.4f} mm, "
                  f"caps {min(caps):.2f}-{max(caps):.2f} mm/s, max v²κ/A {acc:.3f}, max v³κ²/J {jerk:.3f} (sampled) |")
        if name.startswith("rotated"):
            print(f"| {name} | {nseg} | {length:.3f} | {eps:g} | Xu & Sun 2018 (published, not recomputed) | "
                  f"{XU_SUN_2018_SQUARE:.5f} | |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
