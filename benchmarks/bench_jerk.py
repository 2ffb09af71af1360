"""Jerk-limited feed benchmark: families B1–B9 and the corner comparison.

Run: ``python benchmarks/bench_jerk.py`` (B9 with 1 000 segments takes about 30 s per machine,
``--quick`` leaves it out; ``--workers N`` solves its sections on N processes, default 1 = throughput
of one core; ``--nlp`` adds two columns with every section solved by the NLP, ``closed_form=False``).
Prints two markdown tables (see ``benchmarks/JERK.md``):

1. per family: acceleration-limited optimum T_acc (``time_parameterize``), jerk-limited T_jerk
   (``jerk_limited``), CTR = T_jerk/T_acc, the closed-form double-S reference on B1/B7, the jerk ratio
   by the documented measure, the 1 kHz finite-difference jerk ratio, validity, wall time and
   throughput (segments per second of ``jerk_limited`` with a given base);
2. corner-dense parts: exact stop vs same-ε circular blends vs optimal transitions
   (``trcopt.optimize.corners.blend.optimize_corners`` when it is importable and blends the corners) under
   acceleration and jerk limits.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from timing_cases import ANISO, ISO, families  # noqa: E402

from trcopt import Arc, Line, Plane, Role, Segment, SourceSpan  # noqa: E402
from trcopt.config import Machine  # noqa: E402
from trcopt.modes import Side  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402
from trcopt.timing.doubles import double_s_polyline_time  # noqa: E402
from trcopt.timing.jerk import jerk_limited  # noqa: E402


# -- references ------------------------------------------------------------------------------------
def double_s_reference(fam: str, path: list[Segment], machine) -> float | None:
    """Σ double-S on B1 (one line) and B7 (sharp polyline), else None."""
    if fam not in ("B1", "B7"):
        return None
    pts = [path[0].geometry.start] + [s.geometry.end for s in path]
    return double_s_polyline_time(pts, machine, float(path[0].feed_mm_s))


def run_families(big: bool = True, workers: int = 1, nlp: bool = False) -> list[dict]:
    """Every family on both machines; the 1 000-segment B9 case (``big``) runs on ``workers`` processes;
    ``nlp`` also times every case with every section solved by the NLP (``closed_form=False``)."""
    rows = []
    for fam, case, path, _cf in families():
        if case.endswith("10000") or (case.endswith("1000") and not big):
            continue
        for machine in (ISO, ANISO):
            base = time_parameterize(path, machine)
            procs = workers if case.endswith("1000") else 1
            nlp_t = nlp_wall = None
            if nlp:
                t0 = time.perf_counter()
                nlp_t = jerk_limited(path, machine, base=base, workers=procs, closed_form=False).duration
                nlp_wall = time.perf_counter() - t0
            t0 = time.perf_counter()
            traj = jerk_limited(path, machine, base=base, workers=procs)
            wall = time.perf_counter() - t0
            rep = traj.check_limits(dt=1e-4)
            ref = double_s_reference(fam, path, machine)
            rows.append(
                {
                    "family": fam,
                    "case": case,
                    "limits": machine.name[:5],
                    "segments": len(path),
                    "sections": len(traj.sections),
                    "T_acc": base.duration,
                    "T_jerk": traj.duration,
                    "CTR": traj.duration / base.duration,
                    "ref": ref,
                    "vs_ref": None if ref is None else traj.duration / ref,
                    "jerk": max(rep.jerk_ratio),
                    "jerk_knot": max(rep.jerk_knot_ratio),
                    "fd1k": max(rep.jerk_fd_1khz_ratio),
                    "v": max(rep.v_ratio),
                    "a": max(rep.a_ratio),
                    "valid": rep.ok,
                    "wall": wall,
                    "iters": traj.iterations,
                    "procs": procs,
                    "closed": sum(sol.solver != "ipopt" for sol in traj.solutions),
                    "nlp_T": nlp_t,
                    "nlp_wall": nlp_wall,
                }
            )
    return rows


def families_table(rows: list[dict]) -> str:
    nlp = any(r["nlp_T"] is not None for r in rows)
    extra = " NLP-only T_jerk s | NLP-only wall s |" if nlp else ""
    out = [
        "| family | case | limits | sections (closed form) | T_acc s | T_jerk s | CTR T_jerk/T_acc | Σ double-S s "
        "| T_jerk/ref | jerk ratio | of which knots | FD 1 kHz | v ratio | a ratio | valid | wall s | seg/s (procs) |"
        + extra,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|" + ("---|---|" if nlp else ""),
    ]
    for r in rows:
        ref = "" if r["ref"] is None else f"{r['ref']:.6f}"
        vs = "" if r["vs_ref"] is None else f"{r['vs_ref']:.4f}"
        more = f" {r['nlp_T']:.6f} | {r['nlp_wall']:.2f} |" if nlp else ""
        out.append(
            f"| {r['family']} | {r['case']} | {r['limits']} | {r['sections']} ({r['closed']}) | {r['T_acc']:.6f} | "
            f"{r['T_jerk']:.6f} | {r['CTR']:.4f} | {ref} | {vs} | {r['jerk']:.4f} | {r['jerk_knot']:.4f} | "
            f"{r['fd1k']:.3f} | {r['v']:.4f} | {r['a']:.4f} | {'yes' if r['valid'] else 'NO'} | {r['wall']:.2f} | "
            f"{r['segments'] / r['wall']:.0f} ({r['procs']}) |" + more
        )
    return "\n".join(out)


# -- corner-dense parts: exact stop, circular blends, optimal transitions -------------------------------
def part_polygons() -> dict[str, list[tuple[float, float]]]:
    """Closed tool-centre polygons (start in the middle of a side so every corner is a corner)."""
    square = [(20.0, 0.0), (40.0, 0.0), (40.0, 40.0), (0.0, 40.0), (0.0, 0.0), (20.0, 0.0)]
    star = []
    for k in range(10):
        rad = 25.0 if k % 2 == 0 else 11.0
        ang = math.pi / 2 + k * math.pi / 5
        star.append((rad * math.cos(ang), rad * math.sin(ang)))
    mid = ((star[0][0] + star[1][0]) / 2, (star[0][1] + star[1][1]) / 2)
    star = [mid, *star[1:], star[0], mid]
    comb = [(24.0, -6.0), (48.0, -6.0), (48.0, 12.0)]
    for k in range(6):
        x0 = 48.0 - 8.0 * k
        comb += [(x0 - 4.0, 12.0), (x0 - 4.0, 0.0), (x0 - 8.0, 0.0)]
        if k < 5:
            comb.append((x0 - 8.0, 12.0))
    comb += [(0.0, -6.0), (24.0, -6.0)]
    return {"square 40": square, "star 10 corners": star, "comb 26 corners": _dedupe(comb)}


def _dedupe(pts: list[tuple[float, float]]) -> list[tuple[float, float]]:
    out = [pts[0]]
    for p in pts[1:]:
        if math.dist(p, out[-1]) > 1e-9:
            out.append(p)
    # drop collinear vertices
    res = [out[0]]
    for i in range(1, len(out) - 1):
        a, b, c = np.array(res[-1]), np.array(out[i]), np.array(out[i + 1])
        u, w = b - a, c - b
        if abs(u[0] * w[1] - u[1] * w[0]) > 1e-9:
            res.append(out[i])
    res.append(out[-1])
    return res


def _segment(g, n: int, feed: float, radius: float = 3.0) -> Segment:
    return Segment(
        g, Plane.G17, Role.CONTOUR, SourceSpan("part", n + 1, 1, f"N{10 * (n + 1)}"), feed, Side.LEFT, radius
    )


def polygon_path(pts: list[tuple[float, float]], feed: float) -> list[Segment]:
    """Exact stop: the sharp polygon."""
    return [_segment(Line((*a, 0.0), (*b, 0.0)), i, feed) for i, (a, b) in enumerate(zip(pts, pts[1:], strict=False))]


def arc_blend_path(pts: list[tuple[float, float]], eps: float, feed: float) -> list[Segment]:
    """Every corner replaced by the tangent arc whose deviation from the corner is ``eps`` (mm).

    Deflection φ: ``r = ε·cos(φ/2)/(1 − cos(φ/2))``, tangent points at ``r·tan(φ/2)`` from the corner
    (spec timing.md §4.5); ε is reduced where the neighbouring lines are too short.
    """
    P = [np.array(p, float) for p in pts]
    n = len(P)
    cut = [0.0] * n
    arcs: dict[int, tuple] = {}
    for i in range(1, n - 1):
        d0 = (P[i] - P[i - 1]) / np.linalg.norm(P[i] - P[i - 1])
        d1 = (P[i + 1] - P[i]) / np.linalg.norm(P[i + 1] - P[i])
        phi = math.acos(float(np.clip(d0 @ d1, -1.0, 1.0)))
        turn = 1.0 if d0[0] * d1[1] - d0[1] * d1[0] > 0 else -1.0
        room = 0.45 * min(np.linalg.norm(P[i] - P[i - 1]), np.linalg.norm(P[i + 1] - P[i]))
        r = eps * math.cos(phi / 2) / (1 - math.cos(phi / 2))
        d = r * math.tan(phi / 2)
        if d > room:
            r *= room / d
            d = room
        cut[i] = d
        a_pt = P[i] - d0 * d
        centre = a_pt + turn * r * np.array([-d0[1], d0[0]])
        a0 = math.atan2(a_pt[1] - centre[1], a_pt[0] - centre[0])
        arcs[i] = (float(centre[0]), float(centre[1]), r, a0, turn * phi)
    out: list[Segment] = []
    k = 0
    for i in range(n - 1):
        a, b = P[i], P[i + 1]
        d = (b - a) / np.linalg.norm(b - a)
        s, e = a + d * cut[i], b - d * cut[i + 1]
        out.append(_segment(Line((*s, 0.0), (*e, 0.0)), k, feed))
        k += 1
        if i + 1 in arcs:
            cx, cy, r, a0, sw = arcs[i + 1]
            out.append(_segment(Arc((cx, cy), r, a0, sw), k, feed))
            k += 1
    return out


def programmed_polygon(pts: list[tuple[float, float]], radius: float = 3.0) -> list[tuple[float, float]]:
    """The programmed contour whose G41/G451 tool-centre path is ``pts``: every edge moved ``radius`` to
    the right of travel (the contour side under G41), consecutive edges intersected."""
    P = [np.array(p, float) for p in pts]
    lines = []
    for a, b in zip(P, P[1:], strict=False):
        d = (b - a) / np.linalg.norm(b - a)
        right = np.array([d[1], -d[0]])
        lines.append((a + radius * right, d))
    out = []
    n = len(lines)
    closed = math.dist(pts[0], pts[-1]) < 1e-9
    for i in range(n):
        (p0, d0), (p1, d1) = lines[i - 1], lines[i]
        if i == 0 and not closed:
            out.append(tuple(p1))
            continue
        den = d0[0] * d1[1] - d0[1] * d1[0]
        if abs(den) < 1e-12:
            out.append(tuple(p1))
            continue
        t = ((p1 - p0)[0] * d1[1] - (p1 - p0)[1] * d1[0]) / den
        out.append(tuple(p0 + t * d0))
    out.append(out[0] if closed else tuple(lines[-1][0] + lines[-1][1] * np.linalg.norm(P[-1] - P[-2])))
    return [(float(x), float(y)) for x, y in out]


def module_path(
    pts: list[tuple[float, float]],
    eps: float,
    feed: float,
    mode: str = "optimal",
    objective: str = "curvature",
    machine: Machine = ISO,
) -> list[Segment] | None:
    """Transitions from ``trcopt.optimize.corners.blend.blend_corners`` (``mode="optimal"``: G2 quintics,
    least peak curvature or, with ``objective="jerk"``, least curvature-rate cost under ``machine``'s
    jerk limit; ``"arc"``: same-ε circular blends, ε measured on the cut part); None when no corner
    could be blended."""
    from trcopt.optimize.corners.blend import blend_corners

    prog_pts = programmed_polygon(pts)
    prog = [
        Segment(Line((*a, 0.0), (*b, 0.0)), Plane.G17, Role.CONTOUR, SourceSpan("part", i + 1, 1), feed)
        for i, (a, b) in enumerate(zip(prog_pts, prog_pts[1:], strict=False))
    ]
    # under jerk limits the G2 transitions are the point: no fall-back to circular blends chosen
    # by the acceleration-limited timing (select=False)
    res = blend_corners(
        polygon_path(pts, feed), prog, tolerance_mm=eps, mode=mode, select=False, objective=objective, machine=machine
    )
    return res.segments if res.blended else None


def optimal_path(pts: list[tuple[float, float]], eps: float, feed: float) -> list[Segment] | None:
    """Optimal (G2) transitions from ``trcopt.optimize.corners.blend`` or None."""
    return module_path(pts, eps, feed, "optimal")


def compare_parts(eps: float = 0.05, feed: float = 150.0, machine=ISO, with_optimal: bool = True) -> list[dict]:
    rows = []
    for name, pts in part_polygons().items():
        variants = {
            "exact stop": polygon_path(pts, feed),
            f"arc blend, tool-centre ε={eps}": arc_blend_path(pts, eps, feed),
        }
        if with_optimal:
            variants[f"circular blend, cut ε={eps} (corners, arc)"] = module_path(pts, eps, feed, "arc")
            variants[f"optimal transitions, cut ε={eps} (corners)"] = optimal_path(pts, eps, feed)
            variants[f"optimal transitions, jerk objective, cut ε={eps} (corners)"] = module_path(
                pts, eps, feed, "optimal", "jerk", machine
            )
        for label, path in variants.items():
            if path is None:
                rows.append(
                    {
                        "part": name,
                        "variant": label,
                        "T_acc": None,
                        "T_jerk": None,
                        "wall": None,
                        "path": None,
                        "blends": 0,
                    }
                )
                continue
            base = time_parameterize(path, machine)
            t0 = time.perf_counter()
            traj = jerk_limited(path, machine, base=base)
            wall = time.perf_counter() - t0
            rep = traj.check_limits(dt=2e-4)
            rows.append(
                {
                    "part": name,
                    "variant": label,
                    "T_acc": base.duration,
                    "T_jerk": traj.duration,
                    "valid": rep.ok,
                    "jerk": max(rep.jerk_ratio),
                    "wall": wall,
                    "path": path,
                    "traj": traj,
                    "base": base,
                    "corners": len(pts) - 2,
                    "blends": sum(sg.role is Role.CORNER or sg.kind != "line" for sg in path),
                }
            )
    return rows


def compare_table(rows: list[dict]) -> str:
    out = [
        "| part | variant | blended corners | T acceleration-limited s | T jerk-limited s | jerk ratio "
        "| valid | wall s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["T_acc"] is None:
            out.append(f"| {r['part']} | {r['variant']} | n/a | n/a | n/a | | | |")
            continue
        out.append(
            f"| {r['part']} | {r['variant']} | {r['blends']} | {r['T_acc']:.4f} | {r['T_jerk']:.4f} | "
            f"{r['jerk']:.4f} | {'yes' if r['valid'] else 'NO'} | {r['wall']:.2f} |"
        )
    return "\n".join(out)


PROGRAMS = ("pocket_square", "star_g451", "gear_12", "obround_pocket", "obround_boss", "cam_freeform", "cam_circle")


def compare_programs(eps: float = 0.01, names: tuple[str, ...] = PROGRAMS, workers: int = 2) -> str:
    """Part programs of ``problems/corners`` planned through the pipeline and timed jerk-limited:
    the controller's exact path, same-ε circular blends, and ``--corners optimal --jerk`` (G2
    transitions with the jerk objective, G450 circles between lines replaced as well)."""
    from trcopt.pipeline import PlanOptions, plan_file

    root = Path(__file__).resolve().parents[1] / "problems" / "corners"
    out = [
        f"| program | variant (ε = {eps} mm) | sites blended | T acceleration-limited s | T jerk-limited s "
        "| vs exact (jerk) | jerk ratio | valid | wall s |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    print("\n".join(out), flush=True)
    for name in names:
        ref = None
        variants = (("exact path", "exact"), ("circular blends", "arc"), ("optimal, jerk objective", "optimal"))
        for label, corners in variants:
            t0 = time.perf_counter()
            res = plan_file(
                root / f"{name}.mpf",
                PlanOptions(corners=corners, tolerance_mm=eps, jerk=True, workers=workers, verify=False),
            )
            wall = time.perf_counter() - t0
            traj = res.timing
            rep = traj.check_limits(dt=2e-4)
            ref = ref or traj.duration
            info = res.extra.get("corners") or {}
            blended = f"{info.get('blended', 0)}" if info else "0"
            if info.get("spline"):
                blended += f" ({info['spline']} on run splines)"
            out.append(
                f"| {name} | {label} | {blended} | {traj.base.duration:.4f} | {traj.duration:.4f} | "
                f"{traj.duration / ref:.3f} | {max(rep.jerk_ratio):.4f} | {'yes' if rep.ok else 'NO'} | {wall:.1f} |"
            )
            print(out[-1], flush=True)
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="leave out B9 with 1 000 segments")
    ap.add_argument("--nlp", action="store_true", help="also time every case with the NLP on every section")
    ap.add_argument("--no-families", action="store_true")
    ap.add_argument(
        "--programs", nargs="*", metavar="NAME", default=None,
        help="only part programs of problems/corners (all of PROGRAMS when no NAME is given)",
    )
    ap.add_argument(
        "--workers", type=int, default=None,
        help="processes for B9 with 1 000 segments (default 1: the throughput of one core) or for --programs "
        "(default 2)",
    )
    args = ap.parse_args(argv)
    if args.programs is not None:
        compare_programs(names=tuple(args.programs) or PROGRAMS, workers=args.workers or 2)  # prints each row
        return
    if not args.no_families:
        rows = run_families(not args.quick, args.workers or 1, args.nlp)
        print(families_table(rows))
        ok = all(r["valid"] for r in rows)
        b17 = [r["vs_ref"] for r in rows if r["vs_ref"] is not None]
        print(
            f"\nall valid: {ok}; B1/B7 T_jerk/Σdouble-S in [{min(b17):.4f}, {max(b17):.4f}]; "
            f"max jerk ratio {max(r['jerk'] for r in rows):.4f}; total wall {sum(r['wall'] for r in rows):.1f} s"
        )
        for r in rows:
            if r["case"].endswith("1000"):
                print(
                    f"throughput B9 random 1000 ({r['limits']}): {r['segments'] / r['wall']:.1f} seg/s on "
                    f"{r['procs']} process(es), {r['closed']} of {r['sections']} sections in closed form"
                    + (f"; NLP on every section: {r['segments'] / r['nlp_wall']:.1f} seg/s" if r["nlp_wall"] else "")
                )
        print()
    print(compare_table(compare_parts()))


if __name__ == "__main__":
    main()
