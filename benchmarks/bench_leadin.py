"""Optimal lead-in vs SINUMERIK SAR with default parameters on the problem suite.

For every golden problem that plans without alarm and has a compensated contour, the optimal lead
(trcopt.optimize.leads.optimal_lead: start point = tool position before TRC activation, the program's
R, side and feed, rho_min = 3 mm, safety = 1 mm, embedded machine) is compared with G147, G247
and G347 with default parameters (DISR = max(rho_min, R), DISCL = 0, G340, G140; see
trcopt/optimize/leads/report.py). Time = traverse time of lead + first contour element from the timing
stage (same objective for all). Ratios < 1 mean the optimum is faster / shorter. A SAR default
that gouges (clearance < R + safety away from P4, or < R anywhere) is marked with '!'.

    python benchmarks/bench_leadin.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from trcopt.cli.leadin import lead_inputs_from_plan
from trcopt.config import DEFAULT_MACHINE
from trcopt.errors import TrcoptError
from trcopt.optimize.leads.leadin import optimal_lead
from trcopt.optimize.leads.report import compare_with_sar
from trcopt.pipeline import PlanOptions, plan_file

ROOT = Path(__file__).resolve().parents[1] / "problems"
SUFFIXES = (".mpf", ".h", ".ngc", ".spf")
RHO_MIN, SAFETY = 3.0, 1.0


def suite(quick: bool = False) -> list[Path]:
    out = []
    for exp in sorted(ROOT.glob("*/*.expected.json")):
        stem = exp.with_suffix("").with_suffix("")
        prog = next((stem.with_suffix(s) for s in SUFFIXES if stem.with_suffix(s).exists()), None)
        if prog is not None:
            out.append(prog)
    return out[::4] if quick else out


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--quick", action="store_true", help="every fourth problem only")
    quick = parser.parse_args(argv).quick
    rows = []
    header = f"{'problem':38s} {'lead':9s} {'L_opt':>7s} {'T_opt':>7s} | " + " | ".join(
        f"{c}: {'L':>6s} {'T':>6s} {'T/T':>5s} {'L/L':>5s}" for c in ("G147", "G247", "G347")
    )
    print(header)
    print("-" * len(header))
    ratios: dict[str, list[tuple[float, float]]] = {"G147": [], "G247": [], "G347": []}
    t_all = time.perf_counter()
    for prog in suite(quick):
        try:
            res = plan_file(prog, PlanOptions(timing=False))
            if not res.ok:
                continue
            inp = lead_inputs_from_plan(res)
        except TrcoptError:
            continue
        name = f"{prog.parent.name}/{prog.stem}"[:38]
        try:
            lead = optimal_lead(
                inp["start"],
                inp["contour"],
                inp["radius"],
                inp["side"],
                rho_min=RHO_MIN,
                safety=SAFETY,
                feed_mm_s=inp["feed_mm_s"],
                plane=inp["plane"],
                machine=DEFAULT_MACHINE,
            )
        except TrcoptError as exc:
            print(f"{name:38s} no lead: {str(exc)[:110]}")
            continue
        try:
            base = compare_with_sar(lead, inp["contour"], DEFAULT_MACHINE)
        except (TrcoptError, ValueError) as exc:
            print(f"{name:38s} SAR defaults impossible: {str(exc)[:90]}")
            continue
        cells = []
        for b in base:
            rt, rl = lead.time_s / b.time_s, lead.length / b.length
            mark = "!" if b.gouge_mm > 1e-6 else " "
            cells.append(f"{b.code}:{mark}{b.length:6.1f} {b.time_s:6.3f} {rt:5.3f} {rl:5.3f}")
            if b.gouge_mm <= 1e-6:
                ratios[b.code].append((rt, rl))
        print(f"{name:38s} {lead.kind:9s} {lead.length:7.2f} {lead.time_s:7.3f} | " + " | ".join(cells))
        rows.append(name)
    print("-" * len(header))
    for code, rs in ratios.items():
        if rs:
            ts, ls = [r[0] for r in rs], [r[1] for r in rs]
            print(
                f"{code} (non-gouging, n={len(rs)}): time ratio mean {sum(ts) / len(ts):.3f} "
                f"[{min(ts):.3f}, {max(ts):.3f}], length ratio mean {sum(ls) / len(ls):.3f} "
                f"[{min(ls):.3f}, {max(ls):.3f}]"
            )
    print(f"{len(rows)} problems in {time.perf_counter() - t_all:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
