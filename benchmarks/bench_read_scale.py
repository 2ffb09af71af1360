"""The SINUMERIK and Heidenhain readers on programs of 10⁴–10⁶ blocks: read time, blocks/s and peak
memory of the whole-program read and of the streamed plan.

Run:  python benchmarks/bench_read_scale.py [--sizes 10000,100000] [--dialects siemens,heidenhain]

The program is a compensated closed freeform contour (r(t) = c·(30 + 5·sin 5t + 2·cos 11t) mm,
chords of about 0.25 mm and more, every fifth element on a convex stretch an arc through the next
two points, F6000) with a tool of radius 2 mm on the outside: SINUMERIK ``G42`` with ``$TC_DP``
tool data and ``N`` block numbers, Heidenhain ``RR`` with ``TOOL DEF``/``TOOL CALL`` and ``CR … DR±``
arcs (at most 10⁶ executed blocks: ``HeidenhainOptions.max_blocks``). Each row is one fresh process
(peak resident memory by ``/usr/bin/time``): the whole-program read
(``controllers.read_program``, the baseline of the same run), the streamed read
(``controllers.stream_program`` consumed move by move, the cyclic garbage collector on), and
``python -m trcopt plan --stream on`` with ``--no-timing`` and with ``--json``/``--gcode``. The read
rows give the read's own time (without the interpreter's start and the imports), the plan rows the
command's wall time. ``--write DIR`` only writes the programs (``siemens<N>.mpf``, ``heidenhain<N>.h``).
"""

from __future__ import annotations

import argparse
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TIME = shutil.which("time") or "/usr/bin/time"
HEADER = {"siemens": 7, "heidenhain": 9}  # blocks besides the contour's chords


def _points(chords: int) -> tuple[float, list[tuple[float, float]]]:
    scale = max(1.0, chords * 0.25 / (2 * math.pi * 30))
    pts = []
    for i in range(chords + 1):
        t = 2 * math.pi * i / chords
        r = scale * (30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t))
        pts.append((r * math.cos(t), r * math.sin(t)))
    return scale, pts


def _arc(a: tuple[float, float], b: tuple[float, float], c: tuple[float, float]) -> tuple[float, float, bool] | None:
    """The centre of the circle through a, b, c and whether a→b→c runs counter-clockwise; None
    when they are about collinear."""
    d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
    if abs(d) < 1e-9:
        return None
    sa, sb, sc = a[0] ** 2 + a[1] ** 2, b[0] ** 2 + b[1] ** 2, c[0] ** 2 + c[1] ** 2
    ux = (sa * (b[1] - c[1]) + sb * (c[1] - a[1]) + sc * (a[1] - b[1])) / d
    uy = (sa * (c[0] - b[0]) + sb * (a[0] - c[0]) + sc * (b[0] - a[0])) / d
    if math.hypot(a[0] - ux, a[1] - uy) > 1e4:
        return None
    return ux, uy, d > 0


def _elements(blocks: int, header: int) -> tuple[float, list[tuple[float, float]], list[tuple]]:
    """The contour as elements ("L", end) and ("A", end, centre, ccw) for about ``blocks`` blocks."""
    chords = max(blocks - header, 8)
    # every fifth element an arc over two chords: chords + chords/10 more points give the block count
    scale, pts = _points(int(chords * 1.25) + 4)
    pts = [(round(x, 5), round(y, 5)) for x, y in pts]
    out: list[tuple] = []
    i = 0
    while len(out) < chords and i + 1 < len(pts):
        if len(out) % 5 == 4 and i + 2 < len(pts):
            arc = _arc(pts[i], pts[i + 1], pts[i + 2])
            if arc is not None and arc[2]:  # convex stretches only (the tool is outside)
                out.append(("A", pts[i + 2], (arc[0], arc[1]), arc[2]))
                i += 2
                continue
        out.append(("L", pts[i + 1]))
        i += 1
    return scale, pts, out


def siemens_program(blocks: int) -> str:
    """A SINUMERIK program of ``blocks`` blocks (see the module docstring)."""
    scale, pts, elems = _elements(blocks, HEADER["siemens"])
    x0 = 50 * scale
    lines = [
        "N10 $TC_DP1[1,1]=120 $TC_DP6[1,1]=2",
        f"N20 G17 G90 G71 T1 D1 G0 X{x0:.3f} Y0 Z1",
        "N30 G1 Z0 F6000",
        f"N40 G42 X{pts[0][0]:.5f} Y{pts[0][1]:.5f}",
    ]
    n = 40
    prev, g1 = pts[0], ""
    for e in elems:
        n += 10
        if e[0] == "L":
            lines.append(f"N{n} {g1}X{e[1][0]:.5f} Y{e[1][1]:.5f}")
            g1 = ""
        else:
            (x, y), (cx, cy), ccw = e[1], e[2], e[3]
            lines.append(f"N{n} G{3 if ccw else 2} X{x:.5f} Y{y:.5f} I{cx - prev[0]:.5f} J{cy - prev[1]:.5f}")
            g1 = "G1 "
        prev = e[1]
    lines += [f"N{n + 10} G1 G40 X{x0:.3f} Y0", f"N{n + 20} G0 Z5", f"N{n + 30} M30"]
    return "\n".join(lines) + "\n"


def heidenhain_program(blocks: int) -> str:
    """A Heidenhain Klartext program of ``blocks`` blocks (see the module docstring)."""
    scale, pts, elems = _elements(blocks, HEADER["heidenhain"])
    x0 = 50 * scale
    lines = [
        "BEGIN PGM BIG MM",
        "TOOL DEF 1 L+50 R+2",
        "TOOL CALL 1 Z S8000",
        f"L X{x0:+.3f} Y+0 Z+1 R0 FMAX",
        "L Z+0 F6000",
        f"L X{pts[0][0]:+.5f} Y{pts[0][1]:+.5f} RR",
    ]
    prev = pts[0]
    for e in elems:
        if e[0] == "L":
            lines.append(f"L X{e[1][0]:+.5f} Y{e[1][1]:+.5f}")
        else:
            (x, y), (cx, cy), ccw = e[1], e[2], e[3]
            r = math.hypot(prev[0] - cx, prev[1] - cy)
            lines.append(f"CR X{x:+.5f} Y{y:+.5f} R+{r:.5f} DR{'+' if ccw else '-'}")
        prev = e[1]
    lines += [f"L X{x0:+.3f} Y+0 R0", "L Z+5 FMAX", "END PGM BIG MM"]
    return "\n".join(f"{i} {line}" for i, line in enumerate(lines)) + "\n"


GENERATORS = {"siemens": (siemens_program, ".mpf"), "heidenhain": (heidenhain_program, ".h")}

_READ = """
import sys, time, resource
from trcopt import controllers
from trcopt.nc.collector import collector_paused
t0 = time.perf_counter()
if sys.argv[2] == "whole":
    p = controllers.read_program(__import__("pathlib").Path(sys.argv[1]))
    n, blocks, diags = len(p.moves), p.blocks, p.diagnostics
else:
    s = controllers.stream_program(__import__("pathlib").Path(sys.argv[1]))
    n = sum(1 for _ in s)
    blocks, diags = s.program.blocks, s.program.diagnostics
dt = time.perf_counter() - t0
errors = sum(1 for d in diags if d.severity.name == "ERROR")
print(f"{dt:.3f} {n} {blocks} {errors}")
"""


def run(cmd: list[str]) -> tuple[float, float, int, str]:
    """(wall s, peak RSS MiB, exit status, stdout) of one process."""
    with tempfile.NamedTemporaryFile("r", suffix=".txt") as rss:
        t0 = time.perf_counter()
        done = subprocess.run([TIME, "-f", "%M", "-o", rss.name, *cmd], capture_output=True, text=True, cwd=ROOT)
        wall = time.perf_counter() - t0
        kb = rss.read().strip().splitlines()
    peak = float(kb[-1]) / 1024 if kb and kb[-1].isdigit() else float("nan")
    return wall, peak, done.returncode, done.stdout


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--sizes", default="10000,100000", help="blocks per program")
    parser.add_argument("--dialects", default="siemens,heidenhain")
    parser.add_argument("--write", metavar="DIR", help="only write the programs into DIR")
    args = parser.parse_args(argv)
    sizes = [int(x) for x in args.sizes.split(",")]
    dialects = args.dialects.split(",")
    if args.write:
        for d in dialects:
            gen, suffix = GENERATORS[d]
            for n in sizes:
                Path(args.write, f"{d}{n}{suffix}").write_text(gen(n))
        return 0
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(ROOT / "trcopt")], check=False, capture_output=True)
    print("| dialect | blocks | run | time s | blocks/s | peak MiB | exit |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for d in dialects:
            gen, suffix = GENERATORS[d]
            for n in sizes:
                prog = Path(tmp) / f"big{suffix}"
                prog.write_text(gen(n))
                outputs = ["--json", f"{tmp}/o.json", "--gcode", f"{tmp}/o.nc"]
                py = [sys.executable, "-m", "trcopt", "plan", str(prog), "--stream", "on"]
                runs = [
                    ("read whole (baseline)", [sys.executable, "-c", _READ, str(prog), "whole"]),
                    ("read streamed", [sys.executable, "-c", _READ, str(prog), "stream"]),
                    ("plan --stream on --no-timing", [*py, "--no-timing"]),
                    ("plan --stream on --json --gcode", [*py, *outputs]),
                ]
                for name, cmd in runs:
                    wall, peak, code, out = run(cmd)
                    if name.startswith("read") and out.split():
                        wall = float(out.split()[0])  # the read alone, without the interpreter's start
                    print(f"| {d} | {n:,} | {name} | {wall:.2f} | {n / wall:,.0f} | {peak:.0f} | {code} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
