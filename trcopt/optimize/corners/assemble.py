"""Building the new tool-centre path from the transitions of its corners, within the tolerance.

* :class:`TransitionPlan` — the transitions of one tool path while they are fitted: the sites,
  each one's tolerance, the G2 quintic solutions, the splines across runs of corners;
* :func:`assemble` — the new path and the corner records for a plan: each site gets its G2
  quintic where one is solved (and chosen), else the largest same-ε circular blend;
* :func:`fit_tolerance` — assemble, measure the cut-part deviation, tighten the transition nearest
  the worst probe, and again (a few rounds), until the whole path is within the tolerance.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line, Poly, hermite_curve
from trcopt.modes import TransitionKind
from trcopt.optimize.corners.chain import ChainSite, ChainSolution, solve_chain
from trcopt.optimize.corners.circular import circular_blend
from trcopt.optimize.corners.curves import joint_turn
from trcopt.optimize.corners.deviation import cut_deviation
from trcopt.optimize.corners.qp import CornerSolution
from trcopt.optimize.corners.records import JUMP_SMOOTHED, CornerRecord, CornerResult
from trcopt.optimize.corners.sites import TANGENT_TOL_RAD, CornerSite
from trcopt.path import Role, Segment

__all__ = ["FIT_ROUNDS", "TARGET_MARGIN", "Spline", "TransitionPlan", "assemble", "fit_tolerance", "kept_jump"]

TARGET_MARGIN = 2e-3  # the transitions aim this fraction inside ε: per-corner vs global sampling
FIT_ROUNDS = 4  # assemble-measure-tighten rounds

Spline = tuple[ChainSite, ChainSolution, float]  # a G2 spline across a run of joints, and its ε (mm)


@dataclass
class TransitionPlan:
    """The transitions of one tool path while they are fitted to the tolerance.

    Attributes
    ----------
    segments:
        The exact tool-centre path.
    sites:
        The corner sites, by joint index.
    eps:
        Tolerance of each site's transition, mm (tightened where the measured deviation needs it).
    solved:
        G2 quintic solutions by (joint index, tolerance).
    splines:
        G2 splines across runs of joints (they take the place of those joints' sites).
    kept:
        Records of the curvature jumps whose spline was given up (the exact path stays there).
    circles:
        The circular blends of the sites by (joint index, tolerance) (:meth:`circle`).
    """

    segments: list[Segment]
    sites: list[tuple[int, CornerSite]]
    eps: dict[int, float]
    solved: dict[tuple[int, float], CornerSolution] = field(default_factory=dict)
    splines: list[Spline] = field(default_factory=list)
    kept: list[CornerRecord] = field(default_factory=list)
    circles: dict[tuple[int, float], Any] = field(default_factory=dict)

    def circle(self, k: int, site: CornerSite) -> tuple[Arc, float, float] | None:
        """The largest circular blend at site ``k`` within its tolerance
        (:func:`~trcopt.optimize.corners.circular.circular_blend`), computed once."""
        return circle_of(self.circles, k, site, self.eps[k])

    @property
    def single(self) -> list[tuple[int, CornerSite]]:
        """The sites that get a transition of their own (not on a spline)."""
        on_spline = {k for chain, _, _ in self.splines for k in chain.joints}
        return [(k, site) for k, site in self.sites if k not in on_spline]


def kept_jump(segs: Sequence[Segment], chain: ChainSite, why: str) -> CornerRecord:
    """Record of a curvature jump whose spline was not used (the exact path stays there)."""
    k = chain.joints[0]
    turn = math.degrees(joint_turn(segs[k].geometry, segs[k + 1].geometry))  # type: ignore[arg-type]
    return CornerRecord(k, turn, False, False, 0.0, reason=f"curvature jump kept: {why}")


def fit_tolerance(
    plan: TransitionPlan,
    programmed: Sequence[Segment],
    tolerance_mm: float,
    mode: str,
    solve: Callable[[TransitionPlan], None] | None = None,
) -> CornerResult:
    """The new path of ``plan`` within ``tolerance_mm`` of material left (mm), as far as a few
    rounds of tightening get it; ``solve`` fills ``plan.solved`` at the start of each round (the
    sites without a solution at their current tolerance), ``mode`` names the strategy."""
    segs = plan.segments
    result = CornerResult(segs, [], 0.0, mode)
    for _round in range(FIT_ROUNDS):
        if solve is not None:
            solve(plan)
        result = assemble(segs, plan.single, plan.eps, plan.solved, mode, chains=plan.splines, circles=plan.circles)
        dev, where = cut_deviation(programmed, segs, result.segments, locate=True)
        result.max_deviation_mm = dev
        if dev <= tolerance_mm or where is None:
            break
        # tighten the corner (or the run of corners, or the curvature jump) closest to the worst
        # probe and try again
        near = [(k, site.joint) for k, site in plan.sites]
        near += [
            (k, np.array(segs[k].geometry.end[:2])) for c, _, _ in plan.splines for k in c.joints if k not in plan.eps
        ]
        k_bad = min(near, key=lambda kp: float(np.hypot(*(kp[1] - where))))[0]
        factor = 0.98 * tolerance_mm / max(dev, tolerance_mm)
        i = next((i for i, (c, _, _) in enumerate(plan.splines) if k_bad in c.joints), None)
        if i is None:
            plan.eps[k_bad] *= factor
            continue
        chain, _, eps_c = plan.splines[i]
        sol = solve_chain(chain, eps_c * factor)
        if sol.ok:
            plan.splines[i] = (chain, sol, eps_c * factor)
            continue
        # the joints of a given-up spline fall back to their own transitions (a curvature jump
        # has none: the exact path stays)
        plan.splines.pop(i)
        if chain.max_turn <= TANGENT_TOL_RAD and len(chain.joints) == 1:
            why = f"spline infeasible at ε {eps_c * factor:.6g} mm ({sol.message})"
            plan.kept.append(kept_jump(segs, chain, why))
    return result


def circle_of(
    circles: dict[tuple[int, float], Any] | None, k: int, site: CornerSite, eps: float
) -> tuple[Arc, float, float] | None:
    """:func:`~trcopt.optimize.corners.circular.circular_blend` of site ``k`` at ``eps``, kept in
    ``circles`` by (k, eps) when given; the site's probes are released once it is measured (a
    plan of many corners would hold them all)."""
    if circles is not None and (k, eps) in circles:
        return circles[(k, eps)]
    built = circular_blend(site, eps)
    site.release()
    if circles is not None:
        circles[(k, eps)] = built
    return built


def _trim(g: Line | Arc, lam0: float, lam1: float) -> Line | Arc:
    return g.sub(lam0, lam1, g.start[2], g.end[2])


def assemble(
    segs: list[Segment],
    sites: Sequence[tuple[int, CornerSite]],
    eps_of: Mapping[int, float],
    solved: Mapping[tuple[int, float], CornerSolution],
    mode: str,
    choice: Mapping[int, TransitionKind] | None = None,
    chains: Sequence[Spline] = (),
    circles: dict[tuple[int, float], Any] | None = None,
) -> CornerResult:
    """The new path with a transition at every site of ``sites`` and along every spline of
    ``chains``, and the records.

    A site gets its G2 quintic from ``solved`` (at its tolerance ``eps_of[k]``, mm) where one is
    solved and ``choice`` (by joint index) does not say :attr:`TransitionKind.ARC`; else the
    largest same-ε circular blend, or — at a G450 transition circle, or where no circular blend
    fits — the exact path (``circles``: the circular blends by (joint, tolerance), filled as they
    are computed). ``mode`` names the strategy in the result.
    """
    lam0 = [0.0] * len(segs)
    lam1 = [1.0] * len(segs)
    inserts: dict[int, list[Segment]] = {}
    records = []
    for chain, csol, ceps in chains:
        # the spline replaces the run: the end elements are trimmed, the chords between dropped,
        # and each piece keeps the block of the element it follows
        lam1[chain.first] = min(lam1[chain.first], chain.lam_a)
        lam0[chain.last] = max(lam0[chain.last], chain.lam_b)
        for i in range(chain.first + 1, chain.last):
            lam0[i], lam1[i] = 1.0, 0.0
        for j, piece in enumerate(csol.pieces):
            seg = replace(segs[chain.first + j], geometry=piece, role=Role.CORNER, t_start_s=None, t_end_s=None)
            inserts.setdefault(chain.first + max(j - 1, 0), []).append(seg)
        jump = chain.max_turn <= TANGENT_TOL_RAD
        for k in chain.joints:
            turn = math.degrees(joint_turn(segs[k].geometry, segs[k + 1].geometry))  # type: ignore[arg-type]
            if not jump and abs(math.radians(turn)) <= TANGENT_TOL_RAD:
                continue  # a tangent joint of an arc inside the run: not a corner
            inside = not jump and turn * chain.material_sign < 0
            why = JUMP_SMOOTHED if jump else ""
            records.append(
                CornerRecord(k, turn, inside, True, ceps, csol.max_curvature, None, None, why, TransitionKind.SPLINE)
            )
    for k, site in sites:
        eps = eps_of[k]
        turn = math.degrees(site.turn)
        a, b = segs[k].geometry, segs[k + 1].geometry
        sol = solved.get((k, eps))
        chosen = TransitionKind.QUINTIC if choice is None else choice.get(k, TransitionKind.QUINTIC)
        use_quintic = sol is not None and sol.ok and chosen is TransitionKind.QUINTIC
        geom: Line | Arc | Poly
        if use_quintic:
            assert sol is not None
            gm = sol.geometry
            sa, sb, w = gm.sa, gm.sb, site.w
            geom = hermite_curve(
                (gm.p0[0], gm.p0[1], w),
                (gm.d0[0], gm.d0[1], 0.0),
                (gm.p1[0], gm.p1[1], w),
                (gm.d1[0], gm.d1[1], 0.0),
                (gm.a0[0], gm.a0[1], 0.0),
                (gm.a1[0], gm.a1[1], 0.0),
                label="corner-quintic",
            )
            kmax, kind, why = gm.max_curvature, TransitionKind.QUINTIC, ""
        elif site.min_cut > 0.0:  # a transition circle stays unless a G2 transition replaces it
            why = "transition circle kept"
            if sol is not None and not sol.ok:
                why = f"G2 transition infeasible ({sol.message}); transition circle kept"
            records.append(CornerRecord(k, turn, site.inside, False, eps, solution=sol, reason=why))
            continue
        else:
            built = circle_of(circles, k, site, eps)
            if built is None:
                why = "no circular blend (arc neighbours)"
                if sol is not None and not sol.ok:
                    why = f"G2 transition infeasible ({sol.message}); {why}"
                records.append(CornerRecord(k, turn, site.inside, False, eps, solution=sol, reason=why))
                continue
            circle, sa, sb = built
            geom = circle
            kmax, kind = 1.0 / circle.radius, TransitionKind.ARC
            why = ""
            if sol is not None and not sol.ok:
                why = f"G2 transition infeasible ({sol.message}): circular blend"
            elif sol is not None:
                why = "circular blend is faster here"
        if site.min_cut > 0.0:
            # the circle at k + 1 is replaced whole; the lines lose what lies beyond the circle
            b = segs[k + 2].geometry
            lam1[k] = min(lam1[k], 1.0 - (sa - site.min_cut) / a.plane_length)
            lam0[k + 1], lam1[k + 1] = 1.0, 0.0
            lam0[k + 2] = max(lam0[k + 2], (sb - site.min_cut) / b.plane_length)
        else:
            lam1[k] = min(lam1[k], 1.0 - sa / a.plane_length)
            lam0[k + 1] = max(lam0[k + 1], sb / b.plane_length)
        inserts[k] = [replace(segs[k + 1], geometry=geom, role=Role.CORNER, t_start_s=None, t_end_s=None)]
        records.append(CornerRecord(k, turn, site.inside, True, eps, kmax, sa + sb, sol, why, kind))
    out: list[Segment] = []
    origin: list[int] = []  # per new segment, the old one it comes from (a transition: the one before)
    for i, s in enumerate(segs):
        if lam0[i] != 0.0 or lam1[i] != 1.0:
            g = s.geometry
            if (lam1[i] - lam0[i]) * g.plane_length > 1e-7:
                out.append(s.with_geometry(_trim(g, lam0[i], lam1[i])))  # type: ignore[arg-type]
                origin.append(i)
        else:
            out.append(s)
            origin.append(i)
        out.extend(inserts.get(i, ()))
        origin.extend([i] * len(inserts.get(i, ())))
    records.sort(key=lambda r: r.index)
    return CornerResult(out, records, 0.0, mode, origin=origin)
