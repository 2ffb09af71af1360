"""Verify a planned tool-centre path against the constraint model (design.md §4).

``verify_plan(programmed, toolpath)`` evaluates every constraint family with the exact float
functions of :mod:`trcopt.verify.model` and reports, per family, the largest residual and where
it occurs:

``radius``
    a compensated contour element lies on the offset carrier of its programmed element, on the
    compensation side, at distance R (mm); a transition circle (corner, KONT arc) is centred on its
    programmed vertex with radius R; a SAR approach/retraction circle has tool-centre radius DISR.
``tangency``
    tangent joints stay tangent: transition circles with their neighbours, the lead contour at P4,
    offsets of tangent programmed joints; each contour offset runs parallel to and in the sense of
    its programmed element (a reversed CDOF offset is a violation). Dimensionless (|sin angle|,
    ≥ 1 for reversals).
``continuity``
    consecutive segments meet (mm).
``no_reversal``
    the applicate is monotonic over each run of approach (retraction) sub-movements (mm; spec R42).
``clearance``
    every compensated tool-centre contour, corner and SAR lead element keeps at least R from the
    whole part contour (:func:`trcopt.verify.contour.part_contour`): ``max(0, R − distance)`` (mm;
    a positive value is a gouge) — less than R only where the controller's own rule puts it
    (:mod:`trcopt.verify.joints`: a near-tangent joint left as it is, the closing joint of a closed
    contour), noted in ``notes``.
``lead_clearance`` (informational, not part of ``ok``)
    the same for NORM/KONT activation and deselection moves, which the controller builds towards
    the programmed start/end point and which overlap the contour when that point is close to it,
    the transitions around the contour's start (end) point between them and the contour (LinuxCNC's
    entry arc), and for the lead-in and lead-out blocks CAM posts write around a closed contour.

A line that starts where the tool is at a near-tangent joint (``near_tangent_rad``, the profile's
limit) is measured against that construction in ``radius`` and ``tangency``
(:func:`trcopt.verify.joints.continuation_residuals`).

A family over tolerance is a diagnostic (:meth:`VerificationReport.diagnostics`: ``VERIFY-…``, a
warning, an error under ``--strict``) at the block of its worst segment.

Closed forms and NumPy only. The clearance candidates come from a uniform grid over the part
contour's bounding boxes (:class:`trcopt.verify.index.BoxGrid`), so a plan verifies in O(n): the
same candidates, hence the same residuals, as filtering every box for every segment.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry import Arc, Line
from trcopt.path import Role, Segment
from trcopt.verify.clearance import clearance_distances
from trcopt.verify.contour import contour_blocks
from trcopt.verify.index import BoxGrid
from trcopt.verify.index import BoxGrid as _Grid
from trcopt.verify.joints import (
    NEAR_TANGENT,
    activation_corners,
    clearance_limits,
    continuation_residuals,
    continuations,
)
from trcopt.verify.model import bbox, carrier_residual, reversal_residual, tangency_residual

__all__ = ["FamilyResidual", "VerificationReport", "verify_plan", "FAMILIES", "FAMILY_CODES"]

FAMILIES = ("radius", "tangency", "continuity", "no_reversal", "clearance", "lead_clearance")
INFORMATIONAL = ("lead_clearance",)
_UNITS = {
    "radius": "mm",
    "tangency": "",
    "continuity": "mm",
    "no_reversal": "mm",
    "clearance": "mm",
    "lead_clearance": "mm",
}
FAMILY_CODES = {
    "radius": Code.VERIFY_RADIUS,
    "tangency": Code.VERIFY_TANGENCY,
    "continuity": Code.VERIFY_CONTINUITY,
    "no_reversal": Code.VERIFY_NO_REVERSAL,
    "clearance": Code.VERIFY_CLEARANCE,
}
_FAILURE = {
    "radius": "a compensated tool-centre element is not at the tool radius from its programmed element",
    "tangency": "a joint of the tool-centre path that must be tangent is not (or an offset element runs "
    "against its programmed element)",
    "continuity": "consecutive tool-centre segments do not meet",
    "no_reversal": "the infeed reverses its direction during an approach or retraction",
    "clearance": "the tool comes closer than its radius to the part contour (a gouge)",
}
_COMPENSATED_ROLES = (Role.CONTOUR, Role.CORNER, Role.APPROACH, Role.RETRACT)
_TANGENT_PROGRAMMED_RAD = 1e-7  # programmed joints tangent within this are verified as tangent
_OFFSET_POINT_TOL_MM = 1e-6  # a joint this close to the offset point is the tangent joint, mm


@dataclass(slots=True)
class FamilyResidual:
    """Largest residual of one constraint family and where it occurs."""

    name: str
    max_residual: float = 0.0
    checks: int = 0
    segment: int | None = None
    block: str | None = None
    line: int | None = None
    span: SourceSpan | None = None  # of the worst segment (for the diagnostic; not in the JSON)

    @property
    def unit(self) -> str:
        return _UNITS[self.name]

    def add(self, value: float, k: int, seg: Segment) -> None:
        self.checks += 1
        if value > self.max_residual or self.segment is None and value >= self.max_residual:
            self.max_residual = float(value)
            self.segment, self.block, self.line, self.span = k, seg.span.block, seg.span.line, seg.span

    def to_json(self) -> dict[str, Any]:
        return {
            "max_residual": self.max_residual,
            "unit": self.unit,
            "checks": self.checks,
            "segment": self.segment,
            "block": self.block,
            "line": self.line,
        }


@dataclass(slots=True)
class VerificationReport:
    """Per-family residuals of a tool-centre path; ``ok`` when all are within ``tolerance``."""

    families: dict[str, FamilyResidual]
    tolerance: float = 1e-6
    seconds: float = 0.0
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """All model families within tolerance (``lead_clearance`` is informational)."""
        return not self.failed

    @property
    def failed(self) -> list[FamilyResidual]:
        return [f for f in self.families.values() if f.max_residual > self.tolerance and f.name not in INFORMATIONAL]

    def max_residual(self, family: str) -> float:
        return self.families[family].max_residual

    def to_json(self) -> dict[str, Any]:
        """The plan JSON key ``"verification"``."""
        return {
            "ok": self.ok,
            "tolerance": self.tolerance,
            "families": {k: f.to_json() for k, f in self.families.items()},
            "notes": list(self.notes),
        }

    def summary_line(self) -> str:
        """One line for the CLI summary."""
        parts = [f"{f.name} {f.max_residual:.1e}" for f in self.families.values()]
        head = "verification: " + ", ".join(parts)
        if self.ok:
            return head + " — ok"
        bad = "; ".join(
            f"{f.name} violated by {f.max_residual:.6g}{' ' + f.unit if f.unit else ''} "
            f"at {f.block or f'line {f.line}'} (segment {f.segment})"
            for f in self.failed
        )
        return head + " — FAILED: " + bad

    def diagnostics(self, *, strict: bool = False) -> list[Diagnostic]:
        """One diagnostic per failed family (``VERIFY-CLEARANCE``, …) at the block and line of its
        worst segment: a warning, or an error when ``strict``."""
        severity = Severity.ERROR if strict else Severity.WARNING
        out = []
        for f in self.failed:
            unit = f" {f.unit}" if f.unit else ""
            out.append(
                Diagnostic(
                    severity,
                    FAMILY_CODES[f.name],
                    f"verification: {_FAILURE[f.name]}: {f.name} residual {f.max_residual:.6g}{unit} "
                    f"(tolerance {self.tolerance:g}) at tool-centre segment {f.segment}",
                    f.span or SourceSpan(),
                )
            )
        return out

    def lead_note(self) -> str | None:
        """A note when a NORM/KONT activation or deselection move or a lead block comes closer
        than R to the part contour (the controller's construction does that when the program's
        start or end point is close to the contour); None otherwise."""
        f = self.families["lead_clearance"]
        if f.max_residual <= self.tolerance:
            return None
        return (
            f"approach/retraction/lead move at {f.block or f'line {f.line}'} (segment {f.segment}) comes "
            f"{f.max_residual:.6g} mm closer than the tool radius to the contour"
        )


def _sar_specs(moves: Sequence[Any] | None) -> dict[int, Any]:
    out: dict[int, Any] = {}
    for m in moves or ():
        sar = getattr(m, "sar", None)
        if sar is not None:
            out[m.span.line] = sar
    return out


def _sar_for(line: int, specs: dict[int, Any], role: Role | None = None) -> Any:
    """The SAR words behind a lead segment: retraction in the SAR block itself; the approach
    contour in the SAR block or (P4 in a later block, R45) in one of the next few blocks."""
    if line in specs:
        return specs[line]
    if role is Role.APPROACH:
        for back in range(1, 8):
            sar = specs.get(line - back)
            if sar is not None:
                return sar if sar.contour.is_approach else None
    return None


def _signed_offset(tool: Segment, prog: Line | Arc) -> float:
    """Signed offset (left positive) of the tool element's start point from ``prog``'s carrier."""
    p = tool.geometry.point2(0.0)
    if isinstance(prog, Line):
        d = (prog.end[0] - prog.start[0], prog.end[1] - prog.start[1])
        n = math.hypot(*d)
        return ((p[1] - prog.start[1]) * d[0] - (p[0] - prog.start[0]) * d[1]) / n
    return prog.sense * (prog.radius - math.hypot(p[0] - prog.center[0], p[1] - prog.center[1]))


def _at_offset_point(seg: Segment, prog_by_line: dict[int, list[Segment]], *, start: bool) -> bool:
    """True if the contour segment starts (ends) at the offset of its programmed element's start
    (end) point, at R on its side — where a transition circle joins it tangentially."""
    progs = prog_by_line.get(seg.span.line, [])
    if not progs:
        return True
    pe = progs[0].geometry if start else progs[-1].geometry
    p = pe.start if start else pe.end
    t = pe.start_tangent() if start else pe.end_tangent()
    k = seg.side.sign * seg.radius
    offset = (p[0] - k * t[1], p[1] + k * t[0])
    joint = seg.geometry.start if start else seg.geometry.end
    return math.dist(offset, joint[:2]) <= _OFFSET_POINT_TOL_MM


def _programmed_tangent_at(prog: Line | Arc, p: tuple[float, float]) -> tuple[float, float]:
    if isinstance(prog, Line):
        return prog.direction2()
    ru, rv = p[0] - prog.center[0], p[1] - prog.center[1]
    n = math.hypot(ru, rv)
    return (-rv / n * prog.sense, ru / n * prog.sense)


def _allowed_note(kind: str, amount: float, seg: Segment, near_tangent_rad: float) -> str:
    where = seg.span.block or f"line {seg.span.line}"
    if kind == NEAR_TANGENT:
        return (
            f"near-tangent joints (turn ≤ {near_tangent_rad:g} rad) are left as they are by the compensation: "
            f"the tool comes up to {amount:.6g} mm closer than R to the contour there (largest at {where}), "
            "R·(1 − cos turn) at most — not counted as a gouge"
        )
    return (
        f"the closed contour is entered and left at its closing point: the first and last block's tool "
        f"paths come up to {amount:.6g} mm closer than R to the block across it (at {where}), as close as "
        "the entry or exit point itself (lead clearance) — not counted as a gouge"
    )


def verify_plan(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    moves: Sequence[Any] | None = None,
    settings: Any = None,
    *,
    tolerance: float = 1e-6,
    near_tangent_rad: float = 0.0,
) -> VerificationReport:
    """Evaluate the constraint model on a planned path.

    Parameters
    ----------
    programmed, toolpath:
        ``PlanResult.programmed`` and ``PlanResult.toolpath``.
    moves:
        ``PlanResult.nc.moves`` (optional): gives SAR DISR for the approach-circle radius check
        and DISRP for the no-reversal run.
    settings:
        :class:`~trcopt.config.TrcSettings` (optional): ``wab_clearance_tolerance_mm`` is noted.
    tolerance:
        Largest residual still reported as ok (mm, and dimensionless for tangency).
    near_tangent_rad:
        The compensation's near-tangent limit, rad: joints whose programmed turn is at most this
        are left as they are, the next line starting where the tool is (LinuxCNC 0.05; 0: none;
        :mod:`trcopt.verify.joints`).
    """
    import time

    t0 = time.perf_counter()
    fam = {name: FamilyResidual(name) for name in FAMILIES}
    notes: list[str] = []
    specs = _sar_specs(moves)

    blocks = contour_blocks(programmed, toolpath)
    part, lead_lines = blocks.part, blocks.lead_lines
    prog_by_line: dict[int, list[Segment]] = {}
    for p in blocks.compensated:
        prog_by_line.setdefault(p.span.line, []).append(p)
    # programmed vertices (the centres of transition circles) and the part's boxes, indexed
    vertices = BoxGrid(np.array([[*p.geometry.start[:2], *p.geometry.start[:2]] for p in blocks.compensated]))
    boxes = np.array([bbox(p.geometry) for p in part]) if part else np.zeros((0, 4))
    # cells fitted to the queries (an element and R around it); a reference filter put in the
    # grid's place (tests, benchmarks) takes the boxes alone
    margin = max((seg.radius for seg in toolpath if seg.radius > 0.0), default=0.0)
    grid = BoxGrid(boxes, margin=margin) if BoxGrid is _Grid else BoxGrid(boxes)
    conts = continuations(toolpath, programmed, near_tangent_rad, blocks.closings)

    # ---- radius (contact) and element direction -------------------------------------------
    for k, seg in enumerate(toolpath):
        g = seg.geometry
        if seg.radius <= 0.0 or g.plane_length <= 0.0 or seg.role not in _COMPENSATED_ROLES:
            continue
        R = seg.radius
        if k in conts:  # a near-tangent joint left as it is: the line starts where the tool is
            radius, tangency = continuation_residuals(seg, conts[k])
            fam["radius"].add(radius, k, seg)
            fam["tangency"].add(tangency, k, seg)
        elif seg.role is Role.CONTOUR and isinstance(g, (Line, Arc)):
            cands = [p.geometry for p in prog_by_line.get(seg.span.line, []) if isinstance(p.geometry, (Line, Arc))]
            if not cands:
                continue
            side = seg.side.sign
            # the distance error along the element and the side at its start: the larger of the
            # two (at the start they measure the same error; a sum would count it twice)
            resid = [max(carrier_residual(g, pg, R), abs(_signed_offset(seg, pg) - side * R)) for pg in cands]
            # a block run more than once (subprogram, repeat, transformed frames) has one element
            # per run: among the equally good, the run whose element starts nearest the tool
            least = min(resid)
            best = min(
                (pg for pg, r in zip(cands, resid, strict=True) if r <= least + 1e-9),
                key=lambda pg: math.dist(pg.start[:2], g.point2(0.0)),
            )
            fam["radius"].add(max(carrier_residual(g, best, R), abs(_signed_offset(seg, best) - side * R)), k, seg)
            p0 = g.point2(0.0)
            fam["tangency"].add(tangency_residual(g.start_tangent(), _programmed_tangent_at(best, p0)), k, seg)
        elif isinstance(g, Line) and seg.role in (Role.APPROACH, Role.RETRACT):
            # SAR G147/G148: the lead line touching the contour has plane length L = DISR + R
            sar = _sar_for(seg.span.line, specs, seg.role)
            nb = toolpath[k + 1] if seg.role is Role.APPROACH and k + 1 < len(toolpath) else None
            if seg.role is Role.RETRACT and k > 0:
                nb = toolpath[k - 1]
            if sar is not None and sar.disr is not None and sar.contour.value in ("G147", "G148"):
                if nb is not None and nb.role is Role.CONTOUR:
                    fam["radius"].add(abs(g.plane_length - (sar.disr + R)), k, seg)
        elif isinstance(g, Arc):
            dv = vertices.nearest_distance(g.center)
            sar = _sar_for(seg.span.line, specs) if seg.role in (Role.APPROACH, Role.RETRACT) else None
            if seg.role is Role.CORNER or dv <= 1e-6:
                fam["radius"].add(dv + abs(g.radius - R), k, seg)
            elif sar is not None and sar.disr is not None and not sar.contour.value.startswith("G14"):
                fam["radius"].add(abs(g.radius - sar.disr), k, seg)

    # ---- joints: continuity and tangency ---------------------------------------------------
    # a transition circle (corner, KONT arc) is tangent to the offset contour element it joins;
    # two circles meeting at an intersection (CDON omitted blocks) are not
    transition = (Role.CORNER, Role.APPROACH, Role.RETRACT)
    end_tangents: dict[int, Any] = {}  # line → end tangent of its last programmed element
    start_tangents: dict[int, Any] = {}  # line → start tangent of its first one
    for k in range(len(toolpath) - 1):
        a, b = toolpath[k], toolpath[k + 1]
        fam["continuity"].add(math.dist(a.geometry.end, b.geometry.start), k + 1, b)
        if a.radius <= 0.0 or b.radius <= 0.0:
            continue
        ga, gb = a.geometry, b.geometry
        if ga.plane_length <= 0.0 or gb.plane_length <= 0.0:
            continue
        # ... at the offset end (start) point of its programmed element; where the circle was cut
        # by the neighbouring offset (the end point behind the contour, R35) the joint is an
        # intersection by construction
        required = (
            isinstance(ga, Arc)
            and a.role in transition
            and b.role is Role.CONTOUR
            and _at_offset_point(b, prog_by_line, start=True)
        ) or (
            isinstance(gb, Arc)
            and b.role in transition
            and a.role is Role.CONTOUR
            and _at_offset_point(a, prog_by_line, start=False)
        )
        if not required and a.role is Role.APPROACH and b.role is Role.CONTOUR:
            sar = _sar_for(a.span.line, specs, Role.APPROACH)
            required = sar is not None and sar.contour.is_approach  # tangent entry at P4
        if not required and b.role is Role.RETRACT and a.role is Role.CONTOUR:
            sar = _sar_for(b.span.line, specs, Role.RETRACT)
            required = sar is not None and not sar.contour.is_approach
        if not required and a.role is Role.CONTOUR and b.role is Role.CONTOUR:
            la, lb = a.span.line, b.span.line
            if prog_by_line.get(la) and prog_by_line.get(lb):
                ta = end_tangents.get(la)
                if ta is None:
                    ta = end_tangents[la] = prog_by_line[la][-1].geometry.end_tangent()
                tb = start_tangents.get(lb)
                if tb is None:
                    tb = start_tangents[lb] = prog_by_line[lb][0].geometry.start_tangent()
                required = abs(math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])) <= (
                    _TANGENT_PROGRAMMED_RAD
                )
        if required:
            # a near-tangent line left as it is ends on its offset carrier, not parallel to it:
            # the transition circle after it is tangent to the carrier
            end_tangent = conts[k].programmed.geometry.end_tangent() if k in conts else ga.end_tangent()
            fam["tangency"].add(tangency_residual(end_tangent, gb.start_tangent()), k + 1, b)

    # ---- no reversal of the infeed axis -----------------------------------------------------
    # SAR blocks: w1 → w2 → w3 → w4 over the block's sub-movements (and, on approach, the lead
    # contour executed in the following block), P0 excluded (R42); other leads: each run of
    # approach (retraction) segments.
    used: set[int] = set()
    for line, sar in specs.items():
        idx = [k for k, sg in enumerate(toolpath) if sg.span.line == line]
        if not idx:
            continue
        if sar.contour.is_approach:
            j = idx[-1]
            while j + 1 < len(toolpath) and toolpath[j + 1].role is Role.APPROACH:
                j += 1
                idx.append(j)
            ws = [toolpath[i].geometry.end[2] for i in idx]  # from P1 on
        else:
            ws = [toolpath[idx[0]].geometry.start[2]] + [toolpath[i].geometry.end[2] for i in idx[:-1]]
        used.update(idx)
        fam["no_reversal"].add(reversal_residual(ws), idx[0], toolpath[idx[0]])
    k = 0
    while k < len(toolpath):
        role = toolpath[k].role
        if role not in (Role.APPROACH, Role.RETRACT) or k in used:
            k += 1
            continue
        j = k
        while j + 1 < len(toolpath) and toolpath[j + 1].role is role and j + 1 not in used:
            j += 1
        ws = [toolpath[k].geometry.start[2]] + [toolpath[i].geometry.end[2] for i in range(k, j + 1)]
        fam["no_reversal"].add(reversal_residual(ws), k, toolpath[k])
        k = j + 1

    # ---- clearance from the whole programmed contour (no gouge) ---------------------------
    # lead moves: approach and retraction (not SAR), the transitions around the contour's start
    # and end point, lead blocks; each part element is measured against R, or against the
    # limit of a near-tangent joint or of the closing joint (verify.joints)
    activation = activation_corners(toolpath)
    leads = {
        k
        for k, seg in enumerate(toolpath)
        if seg.span.line in lead_lines
        or k in activation
        or (seg.role in (Role.APPROACH, Role.RETRACT) and _sar_for(seg.span.line, specs, seg.role) is None)
    }
    limits = clearance_limits(toolpath, blocks, conts, leads)
    allowed: dict[str, tuple[float, int]] = {}  # kind → (largest R − distance within its limit, segment)
    measured, pk, pi, dist = clearance_distances(toolpath, part, grid, _COMPENSATED_ROLES)
    # the pairs without a limit of their own: R − distance, largest per tool segment, all at once
    radius_of = np.array([toolpath[k].radius for k in measured], float)
    slot = np.searchsorted(np.array(measured, dtype=np.intp), pk)
    width = max(len(part), 1)
    limit_keys = np.fromiter((k * width + i for k, own in limits.items() for i in own), np.int64)
    limited = np.isin(pk.astype(np.int64) * width + pi, limit_keys)  # the pairs with a limit of their own
    worst_of = np.zeros(len(measured))
    free = ~limited
    np.fmax.at(worst_of, slot[free], radius_of[slot[free]] - dist[free])  # NaN-free max, as max() over the pairs
    worst_by = dict(zip(measured, worst_of.tolist(), strict=True))
    for n in np.nonzero(limited)[0].tolist():
        k, i, d = int(pk[n]), int(pi[n]), float(dist[n])
        lim = limits[k][i]
        worst_by[k] = max(worst_by[k], lim.distance - d)
        excused = toolpath[k].radius - max(d, lim.distance)
        if excused > allowed.get(lim.kind, (0.0, -1))[0]:
            allowed[lim.kind] = (excused, k)
    for k in measured:
        fam["lead_clearance" if k in leads else "clearance"].add(max(0.0, worst_by[k]), k, toolpath[k])
    for kind, (amount, k) in allowed.items():
        if amount > tolerance:
            notes.append(_allowed_note(kind, amount, toolpath[k], near_tangent_rad))

    if settings is not None and getattr(settings, "wab_clearance_tolerance_mm", None) is not None:
        if fam["no_reversal"].max_residual > 0.0:
            notes.append(
                f"no_reversal {fam['no_reversal'].max_residual:.6g} mm "
                f"(controller snap tolerance MD20204 = {settings.wab_clearance_tolerance_mm} mm)"
            )
    return VerificationReport(fam, tolerance, time.perf_counter() - t0, notes)
