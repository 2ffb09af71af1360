"""Jerk-limited feed, FIR engine against the NLP: families B1–B9 (``benchmarks/JERK.md``, "FIR engine").

Run: ``python benchmarks/bench_jerk_fir.py`` (B1–B9 including B9 random 1000 on both machines, about
2 min; ``--quick`` leaves out B9 random 1000, ``--only TEXT`` runs the cases whose name contains TEXT).
Every case is timed with ``jerk_limited(engine="nlp")`` (the default) and ``jerk_limited(engine="fir")``
on the same acceleration-limited base, one process, CPU time (``time.process_time``); both profiles
are checked with ``check_limits(dt=1e-4)``. Prints the markdown table of JERK.md and per family the
largest ratio T_fir/T_nlp.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from timing_cases import ANISO, ISO, families  # noqa: E402

from trcopt.timing import time_parameterize  # noqa: E402
from trcopt.timing.jerk import jerk_limited  # noqa: E402


def _run(path, machine, base, engine: str) -> tuple[object, float]:
    t0 = time.process_time()
    traj = jerk_limited(path, machine, base=base, engine=engine)
    return traj, time.process_time() - t0


def run(big: bool = True, only: str | None = None) -> list[dict]:
    rows = []
    for fam, case, path, _cf in families():
        if case.endswith("10000") or (case.endswith("1000") and not big):
            continue
        if only and only not in f"{fam} {case}":
            continue
        for machine in (ISO, ANISO):
            base = time_parameterize(path, machine)
            nlp, cpu_nlp = _run(path, machine, base, "nlp")
            fir, cpu_fir = _run(path, machine, base, "fir")
            rep_n, rep_f = nlp.check_limits(dt=1e-4), fir.check_limits(dt=1e-4)
            solvers = [sol.solver for sol in fir.solutions]
            rows.append(
                {
                    "family": fam,
                    "case": case,
                    "limits": machine.name[:5],
                    "segments": len(path),
                    "sections": len(solvers),
                    "fir_sections": solvers.count("fir"),
                    "fallback": solvers.count("ipopt"),
                    "T_acc": base.duration,
                    "T_nlp": nlp.duration,
                    "T_fir": fir.duration,
                    "valid_nlp": rep_n.ok,
                    "valid_fir": rep_f.ok,
                    "jerk_fir": max(rep_f.jerk_ratio),
                    "cpu_nlp": cpu_nlp,
                    "cpu_fir": cpu_fir,
                }
            )
            print(row_text(rows[-1]), flush=True)
    return rows


HEADER = (
    "| family | case | limits | sections (FIR / NLP fallback) | T_acc s | T_nlp s | T_fir s | T_fir/T_nlp "
    "| FIR valid | FIR jerk ratio | CPU NLP s | CPU FIR s | seg/s NLP | seg/s FIR |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
)


def row_text(r: dict) -> str:
    return (
        f"| {r['family']} | {r['case']} | {r['limits']} | {r['sections']} ({r['fir_sections']} / {r['fallback']}) | "
        f"{r['T_acc']:.6f} | {r['T_nlp']:.6f} | {r['T_fir']:.6f} | {r['T_fir'] / r['T_nlp']:.4f} | "
        f"{'yes' if r['valid_fir'] else 'NO'} | {r['jerk_fir']:.4f} | {r['cpu_nlp']:.2f} | {r['cpu_fir']:.2f} | "
        f"{r['segments'] / max(r['cpu_nlp'], 1e-9):.0f} | {r['segments'] / max(r['cpu_fir'], 1e-9):.0f} |"
    )


def summary(rows: list[dict]) -> str:
    out = ["| family | largest T_fir/T_nlp | smallest | all FIR profiles valid |", "|---|---|---|---|"]
    for fam in dict.fromkeys(r["family"] for r in rows):
        rs = [r for r in rows if r["family"] == fam]
        ratios = [r["T_fir"] / r["T_nlp"] for r in rs]
        out.append(
            f"| {fam} | {max(ratios):.4f} | {min(ratios):.4f} | {'yes' if all(r['valid_fir'] for r in rs) else 'NO'} |"
        )
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="leave out B9 with 1 000 segments")
    ap.add_argument("--only", default=None, help="only the cases whose 'family case' contains this text")
    args = ap.parse_args(argv)
    print(HEADER, flush=True)
    rows = run(not args.quick, args.only)
    print()
    print(summary(rows))
    for r in rows:
        if r["case"].endswith("1000"):
            print(
                f"\nthroughput B9 random 1000 ({r['limits']}): NLP {r['segments'] / r['cpu_nlp']:.1f} seg/s, "
                f"FIR {r['segments'] / r['cpu_fir']:.1f} seg/s (CPU time, one process); "
                f"T_fir/T_nlp {r['T_fir'] / r['T_nlp']:.4f}"
            )


if __name__ == "__main__":
    main()
