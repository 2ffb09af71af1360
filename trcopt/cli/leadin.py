"""``trcopt leadin PROGRAM``: the optimal lead-in of a program's compensated contour.

The program is planned (SAR and compensation as the controller would); the start point is the
tool position before the TRC activation move, the contour is the programmed contour of the
compensated blocks, R and the side are the ones in force (``--side`` overrides). Prints the
optimal lead and the comparison with G147/G247/G347 defaults; exit 0 ok, 1 no feasible lead
(the binding constraint is named), 2 usage or I/O error.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from trcopt import controllers
from trcopt.cli.common import check_outputs, err, err_exc
from trcopt.codes import Code
from trcopt.modes import LeadObjective

__all__ = ["add_arguments", "run_leadin", "lead_inputs_from_plan", "read_region"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The arguments of ``trcopt leadin``."""
    p.description = __doc__
    p.add_argument("program", help="part program (SINUMERIK .mpf/.spf, Heidenhain .h, RS274 .ngc)")
    p.add_argument("--side", choices=("left", "right"), help="compensation side (default: the program's)")
    p.add_argument("--rho-min", type=float, default=2.0, help="smallest lead curvature radius, mm (default 2)")
    p.add_argument("--safety", type=float, default=1.0, help="extra clearance beyond R, mm (default 1)")
    p.add_argument("--region", help="allowed region: convex polygon, JSON [[u,v],...] or 'u v' per line")
    p.add_argument("--machine", help="machine TOML (default: the embedded machine)")
    p.add_argument("--dialect", default="auto", choices=["auto", *controllers.dialects()])
    p.add_argument("--json", dest="json_out", help="write the result as JSON")
    p.add_argument("--gcode", dest="gcode_out", help="write the lead as G-code")
    p.add_argument("--svg", dest="svg_out", help="write a picture of the lead and the SAR defaults")
    p.add_argument(
        "--out", action="store_true",
        help="plan the lead-out instead: from the contour end to the end point of the deselection block",
    )
    p.add_argument("--quiet", "-q", action="store_true", help="no progress display")
    p.set_defaults(handler=run_leadin)


def read_region(path: str) -> list[tuple[float, float]]:
    """A polygon from JSON ``[[u, v], ...]`` or from lines ``u v`` / ``u,v`` (plane coords, mm)."""
    text = Path(path).read_text()
    try:
        data = json.loads(text)
        return [(float(p[0]), float(p[1])) for p in data]
    except (ValueError, TypeError, IndexError):
        pts = []
        for line in text.splitlines():
            line = line.split("#")[0].replace(",", " ").strip()
            if line:
                u, v = line.split()[:2]
                pts.append((float(u), float(v)))
        return pts


def lead_inputs_from_plan(result: Any) -> dict[str, Any]:
    """Start point, contour, radius, side, feed and plane of a planned program's first
    compensated contour (plane coordinates)."""
    from trcopt.errors import TrcoptError
    from trcopt.path import Role

    tp = result.toolpath
    k = next((i for i, s in enumerate(tp) if s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER)), None)
    if k is None:
        raise TrcoptError("the program has no compensated contour (G41/G42 with a tool radius)", code=Code.USAGE)
    first = tp[k]
    j = k
    while j > 0 and tp[j - 1].radius > 0.0:
        j -= 1
    start = tp[j].geometry.start
    lines = [s.span.line for s in tp[k:] if s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER)]
    end_line = lines[-1]
    # the contour's first block may be executed partly by the lead (SAR); start from its element
    contour = [
        p.geometry
        for p in result.programmed
        if first.span.line <= p.span.line <= end_line
        and p.role in (Role.CONTOUR, Role.RAPID)
        and p.geometry.plane_length > 0.0
    ]
    feed = next((s.feed_mm_s for s in tp[k:] if s.feed_mm_s), None) or 10.0
    last = max(i for i, s in enumerate(tp) if s.radius > 0.0)
    return {
        "dialect": result.dialect,
        "start": start,
        "end": tp[last].geometry.end,
        "contour": contour,
        "radius": first.radius,
        "side": first.side,
        "feed_mm_s": feed,
        "plane": first.plane,
    }


def run_leadin(args: argparse.Namespace) -> int:
    """Run ``trcopt leadin``; returns the exit code (no tracebacks for user errors)."""
    from trcopt.progress import reporting, stage, terminal_reporter

    problem = check_outputs([args.json_out, args.gcode_out, args.svg_out], inputs=[args.program])
    if problem:
        err(problem, code="OUTPUT")
        return 2
    with reporting(terminal_reporter(quiet=getattr(args, "quiet", False))), stage(f"lead for {args.program}"):
        return _run_leadin(args)


def _run_leadin(args: argparse.Namespace) -> int:
    from trcopt.config import DEFAULT_MACHINE, load_machine
    from trcopt.errors import SolverError, TrcoptError
    from trcopt.optimize.leads.leadin import optimal_lead
    from trcopt.optimize.leads.report import compare_with_sar, leadin_gcode
    from trcopt.pipeline import PlanOptions, plan_file
    from trcopt.progress import stage

    try:
        machine = load_machine(args.machine) if getattr(args, "machine", None) else DEFAULT_MACHINE
        region = read_region(args.region) if getattr(args, "region", None) else None
        res = plan_file(args.program, PlanOptions(dialect=getattr(args, "dialect", "auto"), timing=False))
        if not res.ok:
            for d in res.errors:
                print(d.format(), file=sys.stderr)
            code = res.errors[0].code
            err("the program raised an alarm before the lead could be planned", file=args.program, code=code)
            return 1
        inputs = lead_inputs_from_plan(res)
        side = args.side or inputs["side"]
        if getattr(args, "out", False):
            return _run_leadout(args, inputs, side, region, machine)
        with stage("lead-in optimisation"):
            lead = optimal_lead(
                inputs["start"],
                inputs["contour"],
                inputs["radius"],
                side,
                rho_min=args.rho_min,
                safety=args.safety,
                region=region,
                machine=machine,
                feed_mm_s=inputs["feed_mm_s"],
                plane=inputs["plane"],
            )
    except SolverError as exc:
        err_exc(exc, args.program)
        return 1
    except TrcoptError as exc:
        err_exc(exc)
        return 2
    except (OSError, ValueError) as exc:  # the region file
        err(str(exc), file=getattr(args, "region", None), code="IO" if isinstance(exc, OSError) else "USAGE")
        return 2
    try:
        baselines = compare_with_sar(lead, inputs["contour"], machine)
    except (TrcoptError, ValueError) as exc:  # a default SAR may be impossible (alarm)
        print(f"note: SAR defaults not comparable: {exc}", file=sys.stderr)
        baselines = []
    unit = "s" if lead.objective is LeadObjective.TIME else "mm (surrogate)"
    print(
        f"{args.program}: optimal lead {lead.kind}, length {lead.length:.3f} mm, "
        f"{lead.objective.value} {lead.time_s:.4f} {unit}, min clearance {lead.best.min_clearance:.3f} mm"
        + (f", SAR shape {lead.sar.contour} DISR={lead.sar.disr:.3f}" if lead.sar else "")
    )
    for b in baselines:
        flag = f"  GOUGES by {b.gouge_mm:.3f} mm" if b.gouge_mm > 1e-6 else ""
        print(
            f"  {b.code} DISR={b.disr:g}: length {b.length:.3f} mm, {lead.objective.value} {b.time_s:.4f} {unit}; "
            f"optimal/SAR time {lead.time_s / b.time_s:.3f}, length {lead.length / b.length:.3f}{flag}"
        )
    rendered: list[tuple[str, str]] = []  # rendered first, then written atomically
    try:
        if args.json_out:
            out = lead.to_json()
            out["program"] = args.program
            out["baselines"] = [
                {"code": b.code, "disr": b.disr, "length_mm": b.length, "time_s": b.time_s, "gouge_mm": b.gouge_mm}
                for b in baselines
            ]
            rendered.append((args.json_out, json.dumps(out, indent=1)))
        if args.gcode_out:
            rendered.append((args.gcode_out, leadin_gcode(lead, args.program)))
        if args.svg_out:
            rendered.append((args.svg_out, _lead_svg(args.program, inputs, lead, baselines)))
    except TrcoptError as exc:
        err_exc(exc, args.program)
        return 2
    return _write_all(rendered)


_SAR_COLOURS = {"G147": "#1f77b4", "G247": "#9467bd", "G347": "#8c564b"}


def _lead_svg(program: str, inputs: dict, lead: Any, baselines: list) -> str:
    """The lead-in picture: the contour, the optimal lead (green, with direction), the SAR defaults
    (named in the legend with their length and time), the start point P0 and the contour start P4,
    axes in mm."""
    from trcopt.errors import SourceSpan
    from trcopt.io.svg import render_svg
    from trcopt.path import Role, Segment

    plane, feed = inputs["plane"], inputs["feed_mm_s"]
    contour = [Segment(e, plane, Role.CONTOUR, SourceSpan(), feed) for e in inputs["contour"]]
    overlays = [
        (
            f"{b.code} SAR default, DISR {b.disr:g} mm: {b.length:.3f} mm, {b.time_s:.4f}"
            + (f", gouges by {b.gouge_mm:.3f} mm" if b.gouge_mm > 1e-6 else ""),
            _SAR_COLOURS.get(b.code, "#888888"),
            [Segment(e, plane, Role.APPROACH, SourceSpan(), feed) for e in b.elements if e.plane_length > 0],
        )
        for b in baselines
    ]
    markers = [(lead.p0[0], lead.p0[1], "P0 start point"), (lead.p4[0], lead.p4[1], "P4 contour start")]
    title = f"optimal lead-in (green, {lead.kind}, {lead.length:.3f} mm, {lead.time_s:.4f}) of {program}"
    return render_svg(contour, lead.segments, title=title, markers=markers, overlays=overlays)


def _run_leadout(args: argparse.Namespace, inputs: dict, side: object, region: object, machine: object) -> int:
    """``trcopt leadin --out``: the optimal lead-out, written as explicit tool-centre moves."""
    from trcopt.errors import SolverError, TrcoptError
    from trcopt.io import toolpath_to_gcode
    from trcopt.io.svg import render_svg
    from trcopt.optimize.leads.leadout import optimal_lead_out

    try:
        lead = optimal_lead_out(
            inputs["end"],
            inputs["contour"],
            inputs["radius"],
            side,  # type: ignore[arg-type]
            rho_min=args.rho_min,
            safety=args.safety,
            region=region,  # type: ignore[arg-type]
            machine=machine,  # type: ignore[arg-type]
            feed_mm_s=inputs["feed_mm_s"],
            plane=inputs["plane"],
        )
    except SolverError as exc:
        err_exc(exc, args.program)
        return 1
    except TrcoptError as exc:
        err_exc(exc)
        return 2
    except ValueError as exc:
        err(str(exc), file=args.program)
        return 2
    print(
        f"{args.program}: optimal lead-out {lead.kind}, length {lead.length:.3f} mm, "
        f"{lead.objective.value} {lead.time_s:.4f}, min clearance {lead.mirrored.best.min_clearance:.3f} mm"
    )
    rendered: list[tuple[str, str]] = []  # rendered first, then written atomically
    try:
        if args.json_out:
            out = lead.to_json()
            out["program"] = args.program
            rendered.append((args.json_out, json.dumps(out, indent=1)))
        if args.gcode_out:
            gcode = toolpath_to_gcode(
                lead.segments,
                flavor=controllers.get(inputs["dialect"]).gcode,
                program_name=f"lead-out of {args.program}",
            )
            rendered.append((args.gcode_out, gcode))
        if args.svg_out:
            from trcopt.errors import SourceSpan
            from trcopt.path import Role, Segment

            feed = inputs["feed_mm_s"]
            contour = [Segment(e, inputs["plane"], Role.CONTOUR, SourceSpan(), feed) for e in inputs["contour"]]
            end = inputs["end"]
            title = f"optimal lead-out (green, {lead.length:.3f} mm) of {args.program}"
            markers = [(end[0], end[1], "end point of the deselection block")]
            rendered.append((args.svg_out, render_svg(contour, lead.segments, title=title, markers=markers)))
    except TrcoptError as exc:
        err_exc(exc, args.program)
        return 2
    return _write_all(rendered)


def _write_all(rendered: list[tuple[str, str]]) -> int:
    """Write the rendered outputs atomically (their folders created); 0, or 2 on a failure."""
    from trcopt.io import write_text_atomic

    try:
        for path, text in rendered:
            Path(path).parent.mkdir(parents=True, exist_ok=True)
            write_text_atomic(path, text)
    except OSError as exc:  # OutputError: the file is untouched, no temporary is left
        err(str(exc).removeprefix("cannot write "), file=None, code="OUTPUT")
        return 2
    return 0
