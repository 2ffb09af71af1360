"""`trcopt plan` end to end on programs of 10⁴–10⁶ blocks: wall time, blocks/s and peak memory.

Run:  python benchmarks/bench_plan_scale.py [--sizes 10000,100000] [--rs274 PATH]

The program is the compensated CAM contour of ``bench_cam_scale.py`` (LinuxCNC, ``G41.1 D2``, N
chords of ≥ 0.25 mm, F6000). Each row is one ``python -m trcopt plan`` process (peak resident
memory by ``/usr/bin/time``): without timing, with the acceleration-limited timing, and with
timing and ``--json``/``--gcode`` written. The baseline of the same run is LinuxCNC's own
interpreter ``rs274`` on the same file where it is available (built outside the project as
``../shared/peer_cases/linuxcnc/BUILD_RS274.md`` describes; ``--rs274``), else the rows stand alone.
Programs over 4 MiB (10⁶ blocks) are planned window by window (``--stream auto``), smaller ones
whole; the outputs rows run both ways: ``--stream on`` (window by window, bounded memory) and
``--stream off`` (the whole program, up to ``--whole-up-to``).

The row "API plan_file, in process" is the same ``--no-timing`` plan made by the Python API in a
process that has already imported the package (a batch worker, a notebook): its wall time is the
plan alone (after a first plan of a 200-chord contour), without the ~0.15–0.2 s a new process
spends starting the interpreter and importing NumPy and the package, which dominates the
command's rows at 10⁴ blocks. Up to ``--api-up-to``
blocks (the whole program is planned in memory).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))

from bench_cam_scale import contour  # noqa: E402

TIME = shutil.which("time") or "/usr/bin/time"
# the plan of the API timed after the imports and a first small plan (which loads the modules
# the stages import on first use); printed: wall seconds, ok
API = """
import sys, time
from trcopt.pipeline import PlanOptions, plan_file
plan_file(sys.argv[2], PlanOptions(timing=False))
t0 = time.perf_counter()
result = plan_file(sys.argv[1], PlanOptions(timing=False))
print(time.perf_counter() - t0, result.ok)
"""


def run(cmd: list[str]) -> tuple[float, float, int]:
    """(wall s, peak RSS MiB, exit status) of one process."""
    with tempfile.NamedTemporaryFile("r", suffix=".txt") as rss:
        t0 = time.perf_counter()
        done = subprocess.run([TIME, "-f", "%M", "-o", rss.name, *cmd], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        kb = rss.read().strip().splitlines()
    peak = float(kb[-1]) / 1024 if kb and kb[-1].isdigit() else float("nan")
    return wall, peak, done.returncode


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--sizes", default="10000,100000", help="chords (blocks, about) per program")
    parser.add_argument("--rs274", default=os.environ.get("RS274", "/tmp/lcnc/bin/rs274"))
    parser.add_argument(
        "--whole-up-to", type=int, default=100_000,
        help="also run the whole-program plan (--stream off) up to this size (about 3 KB per block)",
    )
    parser.add_argument("--api-up-to", type=int, default=100_000,
                        help="also time the API's plan in a process with the package imported, up to this size")
    args = parser.parse_args(argv)
    table = Path("/work/shared/peer_cases/linuxcnc/_default-tooltable/sim.tbl")
    rs274 = args.rs274 if Path(args.rs274).exists() and table.exists() else None
    # the package's modules compiled to bytecode first, as an installed package has them (each row
    # is a fresh process; with PYTHONDONTWRITEBYTECODE set they would be compiled again every time)
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(ROOT.parent / "trcopt")], check=False,
                   capture_output=True)
    print("| blocks | run | wall s | blocks/s | peak MiB | exit | vs rs274 |")
    print("|---|---|---|---|---|---|---|")
    py = [sys.executable, "-m", "trcopt", "plan"]
    with tempfile.TemporaryDirectory() as tmp:
        warm = Path(tmp) / "warm.ngc"
        warm.write_text(contour(200, compensated=True))
        for chords in (int(x) for x in args.sizes.split(",")):
            prog = Path(tmp) / f"cam{chords}.ngc"
            prog.write_text(contour(chords, compensated=True))
            blocks = sum(1 for line in prog.read_text().splitlines() if line.strip())
            base = None
            if rs274:
                wall, peak, code = run([rs274, "-t", str(table), "-g", str(prog)])
                base = wall
                print(f"| {blocks:,} | rs274 (baseline) | {wall:.2f} | {blocks / wall:,.0f} | {peak:.0f} | {code} "
                      "| 1.00 |")
            outputs = ["--json", f"{tmp}/o.json", "--gcode", f"{tmp}/o.ngc"]
            runs = [
                ("trcopt plan --no-timing", [*py, str(prog), "--no-timing"]),
                ("trcopt plan (timing)", [*py, str(prog)]),
                ("trcopt plan --json --gcode --stream on", [*py, str(prog), *outputs, "--stream", "on"]),
            ]
            if chords <= args.whole_up_to:
                # the whole-program plan (the default for programs under 4 MiB) at the same size
                runs.append(("trcopt plan --json --gcode --stream off", [*py, str(prog), *outputs, "--stream", "off"]))
            for name, cmd in runs:
                wall, peak, code = run(cmd)
                ratio = f"{wall / base:.1f}" if base else "–"
                print(f"| {blocks:,} | {name} | {wall:.2f} | {blocks / wall:,.0f} | {peak:.0f} | {code} | {ratio} |",
                      flush=True)
                if name.endswith("--no-timing") and chords <= args.api_up_to:
                    done = subprocess.run([sys.executable, "-c", API, str(prog), str(warm)], capture_output=True, text=True)
                    words = done.stdout.split()
                    if done.returncode == 0 and len(words) == 2 and words[1] == "True":
                        wall = float(words[0])
                        ratio = f"{wall / base:.1f}" if base else "–"
                        print(f"| {blocks:,} | API plan_file --no-timing, in process | {wall:.2f} | "
                              f"{blocks / wall:,.0f} | | 0 | {ratio} |", flush=True)
                    else:
                        print(f"| {blocks:,} | API plan_file --no-timing, in process | failed: {done.stderr.strip()[-200:]} "
                              "| | | | |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
