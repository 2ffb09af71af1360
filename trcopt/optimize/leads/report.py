"""Lead-in results as G-code and SVG, and the comparison with SINUMERIK SAR defaults.

``sar_baseline`` builds the tool-centre path of G147/G247/G347 with **default parameters** —
DISR = max(ρmin, R) (circle radius of the tool centre; line: cutter-edge distance), DISCL = 0
with G340 (the approach contour descends from the start height like the optimal lead), side G140
(from the compensation side) — with the analytic SAR construction ``trcopt.compensation.leads.sar_points``.
``compare_with_sar`` times them with the same objective as the optimal lead.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from trcopt.geometry import Arc, Line, Plane, Poly
from trcopt.modes import LeadObjective, LeadSegmentation, LeadSide, SarContour
from trcopt.nc.model import SarSpec
from trcopt.optimize.leads.context import LeadContext
from trcopt.optimize.leads.leadin import lead_time
from trcopt.optimize.leads.records import Element, LeadResult

__all__ = ["Baseline", "sar_baseline", "compare_with_sar", "leadin_gcode", "leadin_svg"]

SAR_CODES = ("G147", "G247", "G347")


@dataclass(frozen=True, slots=True)
class Baseline:
    """One SAR lead with default parameters, timed like the optimal lead."""

    code: str
    disr: float
    elements: tuple[Element, ...]
    length: float
    time_s: float
    gouge_mm: float  # exact clearance violation (0 when it keeps R (+ safety))


def sar_baseline(result: LeadResult, code: str, disr: float | None = None) -> tuple[Element, ...]:
    """Tool-centre elements P0 → P4c of a SAR approach with default parameters (module doc)."""
    from trcopt.compensation.leads import sar_points

    rho_min = result.rho_min
    disr_v = max(rho_min, result.radius) if disr is None else disr
    spec = SarSpec(
        SarContour(code),
        LeadSide.FROM_COMPENSATION,
        LeadSegmentation.SPATIAL,
        disr=disr_v,
        discl=None,
        end_programmed=(True, True, True),
    )
    g = sar_points(
        spec, p0=result.p0, p4=result.p4, tangent=result.tangent, comp_side=result.side.sign, radius=result.radius
    )
    c3 = (g.p3_centre[0], g.p3_centre[1])
    pts = [result.p0, (*c3, g.p1[2]), (*c3, g.p2[2]), (*c3, g.p3[2])]
    els: list[Element] = [Line(a, b) for a, b in zip(pts, pts[1:], strict=False) if math.dist(a, b) > 1e-12]
    p4c = (g.p4_centre[0], g.p4_centre[1], result.p4[2])
    if g.center is None:
        els.append(Line(pts[-1], p4c))
    else:
        els.append(Arc.from_points(pts[-1], p4c, g.center, ccw=bool(g.ccw), full_if_closed=False))
    return tuple(els)


def compare_with_sar(
    result: LeadResult,
    contour: Sequence[Element],
    machine: Any,
    disr: float | None = None,
) -> list[Baseline]:
    """G147/G247/G347 with default parameters, timed and clearance-checked like the optimum."""
    rho_min, safety = result.rho_min, result.safety
    ctx = LeadContext(result.p0, list(contour), result.radius, result.side, rho_min, safety, None)
    out = []
    for code in SAR_CODES:
        els = sar_baseline(result, code, disr)
        t, _ = lead_time(els, result.first_contour, machine, result.feed_mm_s, result.plane, rho_min)
        viol = ctx.exact_check(els)
        out.append(
            Baseline(
                code,
                max(rho_min, result.radius) if disr is None else disr,
                els,
                sum(e.length for e in els),
                t,
                viol["clearance"],
            )
        )
    return out


# --------------------------------------------------------------------------------------------


def _fmt(x: float) -> str:
    s = f"{x:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _words(plane: Plane, p: Sequence[float]) -> str:
    xyz = plane.to_xyz((p[0], p[1], p[2]))
    return " ".join(f"{n}{_fmt(v)}" for n, v in zip("XYZ", xyz, strict=True))


def leadin_gcode(result: LeadResult, program: str = "") -> str:
    """SINUMERIK G-code of the lead.

    A SAR shape is written as the SAR block (``G41/G42 G247 G340 G141 DISR=… DISCL=…`` with the
    contour start P4 as end point), to be followed by the first contour block. Any other lead is
    written as explicit tool-centre moves under G40 (G1, G2/G3 helices, polynomial curves as G1
    chords ≤ 1 µm) ending at the tool-centre contour start P4c.
    """
    plane = result.plane
    f_mm_min = result.feed_mm_s * 60.0
    lines = [f"; optimal lead-in ({result.kind}, objective {result.objective.value}) {program}".rstrip()]
    lines.append(
        f"; length {result.length:.3f} mm, {result.objective.value} "
        f"{result.time_s:.4f}{' s' if result.objective is LeadObjective.TIME else ' mm'}"
    )
    lines.append(f"{plane.value} G90 G0 {_words(plane, result.p0)}")
    trc = "G41" if result.side.sign > 0 else "G42"
    if result.sar is not None:
        sar = result.sar
        lines.append(f"; SAR shape: {sar.contour}")
        side = "" if sar.contour == "G147" else f" {sar.side}"
        lines.append(
            f"{trc} {sar.contour} G340{side} DISR={_fmt(sar.disr)} DISCL={_fmt(sar.discl)} "
            f"{_words(plane, result.p4)} F{_fmt(f_mm_min)}"
        )
        lines.append("; ... the first contour block follows (it defines the approach tangent)")
        return "\n".join(lines) + "\n"
    lines.append("; explicit tool-centre moves (G40); the contour continues from P4c with TRC active")
    first = True
    for e in result.elements:
        feed = f" F{_fmt(f_mm_min)}" if first else ""
        if isinstance(e, Line):
            lines.append(f"G1 {_words(plane, e.end)}{feed}")
        elif isinstance(e, Arc):
            code = "G3" if e.sweep > 0 else "G2"
            ij = (e.center[0] - e.start[0], e.center[1] - e.start[1])
            names = plane.axis_names
            ipar = {"X": "I", "Y": "J", "Z": "K"}
            lines.append(
                f"{code} {_words(plane, e.end)} {ipar[names[0]]}{_fmt(ij[0])} {ipar[names[1]]}{_fmt(ij[1])}{feed}"
            )
        elif isinstance(e, Poly):
            for k, p in enumerate(e.points[1:]):
                lines.append(f"G1 {_words(plane, p)}{feed if k == 0 else ''}")
        first = False
    return "\n".join(lines) + "\n"


def leadin_svg(result: LeadResult, contour: Sequence[Element], baselines: Sequence[Baseline] = ()) -> str:
    """A small SVG: the part contour (black), its start P4, SAR defaults (grey) and the optimum (red)."""
    polys: list[tuple[list[tuple[float, float]], str, str]] = []

    def pts(el: Element) -> list[tuple[float, float]]:
        n = 2 if isinstance(el, Line) else 64
        return [el.point2(u) for u in [i / (n - 1) for i in range(n)]]

    for el in contour:
        polys.append((pts(el), "#000", "1.2"))
    colours = {"G147": "#1f77b4", "G247": "#2ca02c", "G347": "#9467bd"}
    for b in baselines:
        for el in b.elements:
            if el.plane_length > 0:
                polys.append((pts(el), colours.get(b.code, "#888"), "0.8"))
    for el in result.elements:
        if el.plane_length > 0:
            polys.append((pts(el), "#d62728", "1.6"))
    allp = [p for ps, _, _ in polys for p in ps]
    u0, u1 = min(p[0] for p in allp), max(p[0] for p in allp)
    v0, v1 = min(p[1] for p in allp), max(p[1] for p in allp)
    pad = 0.05 * max(u1 - u0, v1 - v0, 1.0)
    w, h = u1 - u0 + 2 * pad, v1 - v0 + 2 * pad
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w:.3f} {h:.3f}" width="600" height="{600 * h / w:.0f}">'
    ]
    for ps, col, sw in polys:
        d = " ".join(f"{p[0] - u0 + pad:.4f},{v1 + pad - p[1]:.4f}" for p in ps)
        out.append(f'<polyline points="{d}" fill="none" stroke="{col}" stroke-width="{float(sw) * w / 300:.4f}"/>')
    legend = "optimal lead (red), G147 blue, G247 green, G347 purple, contour black"
    out.append(f"<title>{legend}</title></svg>")
    return "\n".join(out) + "\n"
