"""Long fuzz run: mutated golden problems through ``trcopt plan``, failures counted by class.

Run: ``python benchmarks/fuzz.py [--count 10000] [--seed 0] [--timeout 60] [--jobs 1]``. Not a
test; ``tests/fuzz/test_fuzz.py`` runs a small seeded sample of the same sequence. The programs
come from ``tests/fuzz/fuzzgen.py`` and are run and classified by ``tests/fuzz/fuzzrun.py`` in
child processes (``--jobs`` of them, each over a slice of the sequence, with an address-space
limit), so a hang or a runaway allocation is counted instead of stopping the run. Prints the
failing programs (``--show N`` per class) and a table of counts per class.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RUNNER = ROOT / "tests" / "fuzz" / "fuzzrun.py"
CLASSES = ("traceback", "internal", "hang", "exit", "unlocated", "nonfinite", "partial", "stream")


def _slice(count: int, seed: int, start: int, stop: int, timeout: float, memory_gb: float) -> list[dict]:
    """Run programs ``start … stop-1`` of the sequence in a child process; its JSON lines."""
    cmd = [sys.executable, str(RUNNER), "--count", str(stop), "--start", str(start), "--seed", str(seed),
           "--timeout", str(timeout), "--memory-gb", str(memory_gb)]
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    records = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode != 0 or not records or "counts" not in records[-1]:
        # the child itself died (killed, crashed): its slice counts as one traceback
        records.append({"index": start, "name": f"slice {start}-{stop}", "failure": "traceback",
                        "detail": done.stderr[-300:], "exit": done.returncode, "seconds": 0.0})
        records.append({"counts": {"programs": stop - start, "traceback": 1}})
    return records


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--count", type=int, default=10_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--timeout", type=float, default=60.0, help="wall-clock limit per program, s")
    p.add_argument("--memory-gb", type=float, default=4.0, help="address-space limit per child process")
    p.add_argument("--jobs", type=int, default=1, help="child processes")
    p.add_argument("--chunk", type=int, default=500, help="programs per child process")
    p.add_argument("--show", type=int, default=5, help="failing programs printed per class")
    args = p.parse_args(argv)
    bounds = [(a, min(a + args.chunk, args.count)) for a in range(0, args.count, args.chunk)]
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        parts = list(pool.map(lambda b: _slice(args.count, args.seed, *b, args.timeout, args.memory_gb), bounds))
    counts: Counter[str] = Counter()
    examples: dict[str, list[dict]] = defaultdict(list)
    for records in parts:
        for rec in records:
            if "counts" in rec:
                counts.update(rec["counts"])
            else:
                examples[rec["failure"]].append(rec)
    for cls in CLASSES:
        for rec in examples[cls][: args.show]:
            print(f"{cls:10s} #{rec['index']} {rec['name']}: {rec['detail'][:200]}")
    print()
    print(f"fuzz run: {counts['programs']} programs, seed {args.seed}, limit {args.timeout:g} s per program")
    print(f"{'class':12s}{'programs':>10s}")
    for cls in ("ok", *CLASSES):
        print(f"{cls:12s}{counts[cls]:>10d}")
    return 0 if all(counts[c] == 0 for c in CLASSES) else 1


if __name__ == "__main__":
    sys.exit(main())
