"""Continuous-path machining benchmark: the program's path-control mode against exact stop, blends
on uncompensated (G40) CAM paths, and the round trip of trcopt's own G-code.

Run:  python benchmarks/bench_path_control.py [--moves 2500] [--eps 0.05] [--skip-roundtrip]

Three tables, every time from trcopt's acceleration-limited timing stage on the default machine in
the same run:

1. **Path-control modes.** One 3D surfacing zig-zag (z = 2·sin(x/8)·cos(y/6), 0.5 mm moves,
   passes 1 mm apart) written for LinuxCNC with ``G64 P0.01`` (Q defaults to P: collinear moves
   are merged) and ``G64 P0.01 Q0``, for SINUMERIK with ``CYCLE832(0.01,_FINISH,1)`` and for
   Heidenhain with ``CYCL DEF 32.1 T0.01``: the default plan (``--corners program``) against
   ``--corners exact``; the deviation as the blends report it (closed form) and as
   :func:`trcopt.verify.deviation.measure_transitions` measures it by sampling.
2. **G40 CAM polylines.** The corner problems' CAM contours without compensation and a 200-point
   butterfly outline of our own, ε = ``--eps`` (contour distance): exact stop, ``arc``, ``optimal``.
3. **Round trip.** Each corner problem planned with ``--corners optimal``, written as G-code,
   and the G-code planned again: reported against re-planned cycle time.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from trcopt import controllers  # noqa: E402
from trcopt.io.gcode import toolpath_to_gcode  # noqa: E402
from trcopt.optimize.corners.fillet import fillet_path  # noqa: E402
from trcopt.optimize.corners.program import merge_collinear, path_control_plan  # noqa: E402
from trcopt.pipeline import PlanOptions, plan, plan_file  # noqa: E402
from trcopt.verify.deviation import measure_transitions  # noqa: E402

CORNERS = ROOT / "problems" / "corners"


def surface(x: float, y: float) -> float:
    return 2.0 * math.sin(x / 8.0) * math.cos(y / 6.0)


def zigzag_points(moves: int) -> list[tuple[float, float, float]]:
    """The surfacing raster: passes of 100 moves of 0.5 mm along x, 1 mm apart in y."""
    pts = [(0.0, 0.0, surface(0.0, 0.0))]
    y = 0.0
    passes = max(1, moves // 101)
    for p in range(passes):
        xs = [i * 0.5 for i in range(101)]
        if p % 2:
            xs.reverse()
        pts += [(x, y, surface(x, y)) for x in xs[1:]]
        y += 1.0
        pts.append((xs[-1], y, surface(xs[-1], y)))
    return pts


def programs(moves: int) -> dict[str, tuple[str, str]]:
    """(file name, text) of the surfacing program per controller and mode."""
    pts = zigzag_points(moves)
    xyz = [f"X{x:.4f} Y{y:.4f} Z{z:.4f}" for x, y, z in pts]
    ngc = ["G21 G17 G90 G40 {mode}", "G0 X0 Y0 Z5", f"G1 Z{pts[0][2]:.4f} F3000", *(f"G1 {w}" for w in xyz[1:]),
           "G0 Z5", "M2"]  # fmt: skip
    mpf = ["N10 G0 X0 Y0 Z5", "N20 CYCLE832(0.01,_FINISH,1)", f"N30 G1 Z{pts[0][2]:.4f} F3000",
           *(f"G1 {w}" for w in xyz[1:]), "G0 Z5", "M30"]  # fmt: skip
    hh = ["0 BEGIN PGM SURF MM", "1 TOOL DEF 1 L+0 R+3", "2 TOOL CALL 1 Z S8000", "3 L X+0 Y+0 Z+5 R0 FMAX",
          "4 CYCL DEF 32.0 TOLERANCE", "5 CYCL DEF 32.1 T0.01", f"6 L Z{pts[0][2]:+.4f} F3000"]  # fmt: skip
    for n, (x, y, z) in enumerate(pts[1:], start=7):
        hh.append(f"{n} L X{x:+.4f} Y{y:+.4f} Z{z:+.4f}")
    hh += [f"{len(pts) + 7} L Z+5 FMAX", f"{len(pts) + 8} END PGM SURF MM"]
    return {
        "LinuxCNC G64 P0.01": ("surf.ngc", "\n".join(ngc).format(mode="G64 P0.01") + "\n"),
        "LinuxCNC G64 P0.01 Q0": ("surf.ngc", "\n".join(ngc).format(mode="G64 P0.01 Q0") + "\n"),
        "SINUMERIK CYCLE832(0.01)": ("surf.mpf", "\n".join(mpf) + "\n"),
        "Heidenhain CYCL DEF 32 T0.01": ("surf.h", "\n".join(hh) + "\n"),
    }


def measured(text: str, file: str) -> tuple[float, float]:
    """Largest (contour, vertex) distance of the program's blends, measured by sampling."""
    exact = plan(text, file=file, options=PlanOptions(corners="exact", timing=False, verify=False))
    nc = controllers.read_program(text, file=file, dialect=exact.dialect)
    path = merge_collinear(exact.toolpath, nc.moves)
    control = path_control_plan(path, nc.moves)
    result = fillet_path(path, control.blends)
    devs = measure_transitions(path, result.segments, result.origin or [])
    return max((d.contour_mm for d in devs), default=0.0), max((d.vertex_mm for d in devs), default=0.0)


def table_modes(moves: int) -> None:
    print(f"\n## 1. Path-control modes: 3D surfacing zig-zag, {moves} moves of 0.5 mm, F3000\n")
    print("| program | blocks | exact stop s | program mode s | ratio | blended | kind | max (closed form) mm "
          "| measured contour / vertex mm | plan wall s |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, (file, text) in programs(moves).items():
        exact = plan(text, file=file, options=PlanOptions(corners="exact"))
        t0 = time.perf_counter()
        prog = plan(text, file=file)
        wall = time.perf_counter() - t0
        c = prog.extra.get("corners", {})
        contour, vertex = measured(text, file)
        print(
            f"| {name} | {prog.nc.blocks} | {exact.timing.duration:.3f} | {prog.timing.duration:.3f} | "
            f"{prog.timing.duration / exact.timing.duration:.3f} | {c.get('blended', 0)} | "
            f"{c.get('tolerance_kind', '-')} | {c.get('max_deviation_mm', 0.0):.5f} | {contour:.5f} / {vertex:.5f} | "
            f"{wall:.2f} |"
        )


def butterfly(points: int = 200) -> str:
    """A closed butterfly-like outline r(t) = e^sin t − 2 cos 4t + sin⁵((2t − π)/24), ~50 mm, as
    G40 chords (LinuxCNC)."""
    out = ["G21 G17 G90 G40", "G0 X0 Y0 Z1", "G1 Z0 F6000"]
    for i in range(points + 1):
        t = 2 * math.pi * i / points
        r = math.exp(math.sin(t)) - 2 * math.cos(4 * t) + math.sin((2 * t - math.pi) / 24) ** 5
        out.append(f"G1 X{6 * r * math.sin(t):.4f} Y{6 * r * math.cos(t):.4f}")
    return "\n".join([*out, "G0 Z5", "M2"]) + "\n"


def without_compensation(path: Path) -> str:
    """A corner problem's program with its compensation words removed (a G40 CAM path)."""
    return re.sub(r"\bG4[12]\b", "", path.read_text())


def table_g40(eps: float) -> None:
    print(f"\n## 2. G40 CAM polylines, ε = {eps} mm (contour distance)\n")
    print("| path | corners | exact s | arc s | optimal s | exact/optimal | optimal plan wall s | max deviation mm |")
    print("|---|---|---|---|---|---|---|---|")
    cases = {p.stem + " (G40)": (p.name, without_compensation(p)) for p in sorted(CORNERS.glob("cam_*.mpf"))}
    cases["butterfly 200 points"] = ("butterfly.ngc", butterfly())
    for name, (file, text) in cases.items():
        times = {}
        for mode in ("exact", "arc", "optimal"):
            t0 = time.perf_counter()
            r = plan(text, file=file, options=PlanOptions(corners=mode, tolerance_mm=eps))
            times[mode] = (r.timing.duration, time.perf_counter() - t0, r.extra.get("corners", {}))
        c = times["optimal"][2]
        print(
            f"| {name} | {c.get('blended', 0)} | {times['exact'][0]:.3f} | {times['arc'][0]:.3f} | "
            f"{times['optimal'][0]:.3f} | {times['exact'][0] / times['optimal'][0]:.2f} | {times['optimal'][1]:.2f} | "
            f"{c.get('max_deviation_mm', 0.0):.4f} |"
        )


def table_roundtrip() -> None:
    print("\n## 3. Round trip: --corners optimal, its G-code planned again\n")
    print("| problem | reported s | re-planned s | difference |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for p in sorted(CORNERS.glob("*.mpf")):
            r = plan_file(p, PlanOptions(corners="optimal"))
            out = Path(tmp) / p.name
            out.write_text(toolpath_to_gcode(r.toolpath, flavor=controllers.get("siemens").gcode, program_name=p.name))
            again = plan_file(out, PlanOptions())
            diff = again.timing.duration / r.timing.duration - 1.0
            print(f"| {p.stem} | {r.timing.duration:.3f} | {again.timing.duration:.3f} | {100 * diff:+.2f} % |")


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--moves", type=int, default=2500, help="moves of the surfacing program (default 2500)")
    parser.add_argument("--eps", type=float, default=0.05, help="ε of the G40 table, mm (default 0.05)")
    parser.add_argument("--skip-roundtrip", action="store_true", help="leave out table 3 (slow: optimal)")
    args = parser.parse_args(argv)
    table_modes(args.moves)
    table_g40(args.eps)
    if not args.skip_roundtrip:
        table_roundtrip()


if __name__ == "__main__":
    main(sys.argv[1:])
