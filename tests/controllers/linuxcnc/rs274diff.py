"""Differential comparison of trcopt's rs274 reader and linuxcnc profile with LinuxCNC's own
``rs274``.

``rs274`` prints the canonical machine calls of a program: moves in the *active* work system
(program units) and the offsets apart (``SET_G5X_OFFSET``, ``SET_G92_OFFSET``). :func:`canon`
turns that output into moves in the G54 system as it stood at the start, in mm — what trcopt's
plan holds — and the error ``rs274`` stopped with (its message, and the ``N`` number of the block
it names). :func:`compare` plans the same program with trcopt and says whether the two agree:
the same moves within 2e-4 program units (a move that goes nowhere is left out on both sides),
or the same error message at the same block.

Run ``python tests/controllers/linuxcnc/rs274diff.py --count 2000 --seed 100000`` (needs
``/tmp/lcnc/bin/rs274``, see ``../shared/peer_cases/linuxcnc/BUILD_RS274.md``) to compare fresh
programs of :mod:`rs274gen`; ``--save FILE`` stores the programs with rs274's output (the
corpus ``tests/data/rs274_corpus.json``, compared without rs274 by ``test_rs274_corpus.py``).
"""

from __future__ import annotations

import argparse
import collections
import json
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

RS274 = Path("/tmp/lcnc/bin/rs274")
PEER = Path(__file__).resolve().parents[3] / ".." / "shared" / "peer_cases" / "linuxcnc"
SIM_TBL = PEER / "_default-tooltable" / "sim.tbl"
TOL = 2e-4  # program units
# rs274 (standalone) uses 1 program unit as peck clearance: its canon reports mm as the machine unit
SETTINGS = "[rs274ngc]\ng73_peck_clearance = 1.0\ng83_peck_clearance = 1.0\n"
_CALL = re.compile(r"^\s*\d+\s+N[\d.]+\s+([A-Z_0-9]+)\((.*)\)\s*$")
_N = re.compile(r"^\s*N(\d+)", re.I)
# the canon calls the comparison reads (a stored corpus keeps only these)
_KEPT = {
    "USE_LENGTH_UNITS",
    "USE_TOOL_LENGTH_OFFSET",
    "SET_G5X_OFFSET",
    "SET_G92_OFFSET",
    "SELECT_PLANE",
    "STRAIGHT_TRAVERSE",
    "STRAIGHT_FEED",
    "ARC_FEED",
    "SET_FEED_RATE",
    "SET_FEED_MODE",
    "SET_SPINDLE_SPEED",
}
FEED_TOL = 2e-4  # relative: rs274 prints feeds and speeds to 4 decimals


def run_rs274(text: str, tbl: Path = SIM_TBL) -> dict:
    """rs274's output for a program: ``{"out": [lines], "err": [lines], "rc": code}``."""
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "p.ngc"
        src.write_text(text)
        proc = subprocess.run(
            [str(RS274), "-t", str(tbl), "-g", str(src)], capture_output=True, text=True, timeout=60, cwd=tmp
        )
    return {"out": proc.stdout.splitlines(), "err": proc.stderr.splitlines(), "rc": proc.returncode}


def _floats(args: str) -> list[float]:
    return [float(v) for v in re.split(r"[,\s]+", args.strip()) if v and re.match(r"^-?[\d.]", v)]


def canon(run: dict) -> tuple[list[dict], tuple[str, int | None] | None]:
    """Moves (type, end, centre, rotation, plane — mm in the starting G54 system) and the error
    (message, N number of its block) of an rs274 run."""
    unit = 1.0
    g5x = g92 = (0.0, 0.0, 0.0)
    base: tuple[float, float, float] | None = None
    plane = "XY"
    pos = (0.0, 0.0, 0.0)
    tlo = (0.0, 0.0, 0.0)
    moves: list[dict] = []
    rate, per_rev, speed = 0.0, False, 0.0  # SET_FEED_RATE, SET_FEED_MODE(…, 1), SET_SPINDLE_SPEED

    def feed() -> float:  # mm/min of a feed move: the rate (per revolution: times the speed)
        return rate * (speed if per_rev else 1.0) * unit

    def fix(p: tuple[float, float, float]) -> tuple[float, float, float]:
        b = base or (0.0, 0.0, 0.0)
        return tuple(p[i] * unit + g5x[i] + g92[i] - b[i] for i in range(3))  # type: ignore[return-value]

    for line in run["out"]:
        m = _CALL.match(line)
        if not m:
            continue
        name, args = m.groups()
        if name == "USE_LENGTH_UNITS":
            unit = 25.4 if "INCHES" in args else 1.0
        elif name == "SET_G5X_OFFSET":
            v = _floats(args)
            g5x = (v[1] * unit, v[2] * unit, v[3] * unit)
            if base is None:  # the start: the machine origin, in the G54 system
                base = g5x
                pos = (-base[0], -base[1], -base[2])
        elif name == "SET_G92_OFFSET":
            v = _floats(args)
            g92 = (v[0] * unit, v[1] * unit, v[2] * unit)
        elif name == "USE_TOOL_LENGTH_OFFSET":  # the controlled point moves by the change
            v = _floats(args)[:3]
            new = (v[0] * unit, v[1] * unit, v[2] * unit)
            pos = (pos[0] + tlo[0] - new[0], pos[1] + tlo[1] - new[1], pos[2] + tlo[2] - new[2])
            tlo = new
        elif name == "SET_FEED_RATE":
            rate = _floats(args)[0]
        elif name == "SET_FEED_MODE":
            per_rev = _floats(args)[1] == 1.0
        elif name == "SET_SPINDLE_SPEED":
            speed = _floats(args)[1]
        elif name == "SELECT_PLANE":
            plane = "XY" if "XY" in args else "XZ" if "XZ" in args else "YZ"
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            v = _floats(args)
            end = fix((v[0], v[1], v[2]))
            moves.append(
                {
                    "type": "rapid" if name == "STRAIGHT_TRAVERSE" else "line", "start": pos, "end": end,
                    "unit": unit, "feed": None if name == "STRAIGHT_TRAVERSE" else feed(),
                }
            )
            pos = end
        elif name == "ARC_FEED":
            v = _floats(args)
            fe, se, fc, sc, rot, ae = v[:6]
            if plane == "XY":
                e, c = (fe, se, ae), (fc, sc, 0.0)
            elif plane == "XZ":
                e, c = (se, ae, fe), (sc, 0.0, fc)
            else:
                e, c = (ae, fe, se), (0.0, fc, sc)
            end, centre = fix(e), fix(c)  # type: ignore[arg-type]
            moves.append(
                {
                    "type": "arc",
                    "start": pos,
                    "end": end,
                    "center": centre,
                    "rotation": int(rot),
                    "plane": plane,
                    "unit": unit,
                    "feed": feed(),
                }
            )
            pos = end
    error = None
    err = [e for e in run["err"] if e.strip() and e.strip() != "executing"]
    if run["rc"] != 0 and err:
        block = err[1] if len(err) > 1 else ""
        n = _N.match(block)
        error = (err[0].strip(), int(n.group(1)) if n else None)
    return moves, error


def _trcopt(text: str, tbl: Path):  # type: ignore[no-untyped-def]
    from trcopt.pipeline import PlanOptions, plan

    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "rs274ngc.toml").write_text(SETTINGS)
        table = Path(tmp) / "sim.tbl"
        table.write_text(tbl.read_text())
        opts = PlanOptions(
            dialect="rs274", timing=False, verify=False, corners="exact", tool_table=str(table), tool_unit="inch"
        )
        return plan(text, file=str(Path(tmp) / "p.ngc"), options=opts)


def _moving(m: dict) -> bool:
    return m["type"] == "arc" or max(abs(a - b) for a, b in zip(m["start"], m["end"], strict=True)) > 1e-9


def compare(text: str, run: dict, tbl: Path = SIM_TBL) -> tuple[bool, str]:
    """(agree, cause of a disagreement) of trcopt and one rs274 run of ``text``."""
    moves, error = canon(run)
    try:
        result = _trcopt(text, tbl)
    except Exception as exc:  # noqa: BLE001 - a traceback is a finding, not a crash of the harness
        return False, f"trcopt raised {type(exc).__name__}: {exc}"
    errors = [d for d in result.diagnostics if d.severity.value == "error"]
    if error is not None:
        if not errors:
            return False, f"rs274 error not raised: {error[0]}"
        ours = errors[0]
        if ours.message != error[0]:
            return False, f"message: rs274 {error[0]!r} / trcopt {ours.message!r} ({ours.code})"
        if error[1] is not None and ours.span.block != f"N{error[1]}":
            return False, f"error block: rs274 N{error[1]} / trcopt {ours.span.block}"
        return True, ""
    if errors:
        return False, f"trcopt error only: {errors[0].code} {errors[0].message}"
    # a move counts when it ends elsewhere than the move before it (trcopt's path is continuous:
    # a tool length offset change moves the controlled point, and trcopt's next move starts there)
    theirs, last = [], moves[0]["start"] if moves else None
    for m in moves:
        if m["type"] == "arc" or last is None or max(abs(a - b) for a, b in zip(m["end"], last, strict=True)) > 1e-9:
            theirs.append(m)
        last = m["end"]
    ours = [
        s
        for s in result.toolpath
        if s.kind == "arc" or max(abs(a - b) for a, b in zip(s.start_xyz, s.end_xyz, strict=True)) > 1e-9
    ]
    if len(ours) != len(theirs):
        return False, f"move count: rs274 {len(theirs)} / trcopt {len(ours)}"
    for i, (s, m) in enumerate(zip(ours, theirs, strict=True)):
        tol = TOL * m["unit"] * 1.5
        kind = "arc" if s.kind == "arc" else ("rapid" if s.is_rapid else "line")
        if kind != m["type"]:
            return False, f"move {i}: kind rs274 {m['type']} / trcopt {kind} (line {s.span.line})"
        dev = max(abs(a - b) for a, b in zip(s.end_xyz, m["end"], strict=True))
        if kind == "arc":
            u, v, _ = s.plane.axes
            c = s.center_xyz
            dev = max(dev, abs(c[u] - m["center"][u]), abs(c[v] - m["center"][v]))
            if (s.geometry.sweep > 0) != (m["rotation"] > 0):
                return False, f"move {i}: arc direction (line {s.span.line})"
        if dev > tol:
            return False, f"move {i}: off by {dev:.4g} mm (line {s.span.line})"
        if m.get("feed") is not None and s.feed_mm_s is not None:
            ours_f = s.feed_mm_s * 60.0
            if abs(ours_f - m["feed"]) > FEED_TOL * max(m["feed"], 1.0) + 1e-4 * m["unit"]:
                return False, f"move {i}: feed rs274 {m['feed']:.6g} / trcopt {ours_f:.6g} mm/min (line {s.span.line})"
    return True, ""


def _cause_class(cause: str) -> str:
    return re.sub(r"\d+(\.\d+)?(e-?\d+)?", "#", cause)[:110]


def main(argv: list[str] | None = None) -> int:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from rs274gen import program

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0, help="first seed")
    ap.add_argument("--save", metavar="FILE", help="store programs and rs274 outputs as a JSON corpus")
    ap.add_argument("--show", type=int, default=3, help="examples shown per cause")
    args = ap.parse_args(argv)
    causes: collections.Counter[str] = collections.Counter()
    examples: dict[str, list[int]] = collections.defaultdict(list)
    corpus = []
    agree = 0
    errors = 0
    for seed in range(args.seed, args.seed + args.count):
        text = program(seed)
        run = run_rs274(text)
        ok, cause = compare(text, run)
        errors += canon(run)[1] is not None
        if ok:
            agree += 1
        else:
            key = _cause_class(cause)
            causes[key] += 1
            examples[key].append(seed)
        if args.save:
            kept = [line for line in run["out"] if _CALL.match(line) and _CALL.match(line).group(1) in _KEPT]  # type: ignore[union-attr]
            corpus.append({"seed": seed, "program": text, "rs274": {"out": kept, "err": run["err"], "rc": run["rc"]}})
    print(f"{agree}/{args.count} agree ({100.0 * agree / args.count:.2f} %); {errors} programs end in an rs274 error")
    for key, n in causes.most_common():
        print(f"{n:5d}  {key}   e.g. seeds {examples[key][: args.show]}")
    if args.save:
        Path(args.save).write_text(json.dumps({"tool_table": "sim.tbl", "programs": corpus}, indent=0))
    return 0 if math.isclose(agree, args.count) else 1


if __name__ == "__main__":
    raise SystemExit(main())
