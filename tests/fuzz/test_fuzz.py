"""A seeded sample of mutated programs through ``trcopt plan``: no traceback, no hang, every error
located, no non-finite number and nothing half-written (``fuzzrun.py`` says what each class means).

The batch runs in a child process with an address-space limit, so a runaway allocation is a
``MemoryError`` there, and each program under a wall-clock limit (``signal.setitimer``). The long
run is ``benchmarks/fuzz.py``.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from fuzzgen import MUTATIONS, programs, seeds  # noqa: E402

COUNT, SEED = 300, 20261124
PER_PROGRAM_S = 20.0
BATCH_S = 240.0


def test_the_generator_is_deterministic_and_covers_every_dialect() -> None:
    a = [(p.name, p.data) for p in programs(60, SEED)]
    b = [(p.name, p.data) for p in programs(60, SEED)]
    assert a == b
    suffixes = {s.suffix for s in seeds()}
    assert suffixes == {".mpf", ".h", ".ngc"}
    used = {part for name, _ in a for part in name.split(":", 1)[1].split("+")}
    assert len(used & set(MUTATIONS)) >= len(MUTATIONS) - 2


def test_a_seeded_sample_neither_crashes_nor_hangs_nor_writes_garbage() -> None:
    cmd = [sys.executable, str(HERE / "fuzzrun.py"), "--count", str(COUNT), "--seed", str(SEED),
           "--timeout", str(PER_PROGRAM_S)]
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=BATCH_S, cwd=HERE.parents[1])
    except subprocess.TimeoutExpired:  # pragma: no cover - a failure, reported as such
        pytest.fail(f"the fuzz batch did not finish within {BATCH_S} s")
    records = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    assert done.returncode == 0 and records and "counts" in records[-1], done.stderr[-2000:]
    failures = [f"#{r['index']} {r['name']}: {r['failure']}: {r['detail']}" for r in records[:-1]]
    assert records[-1]["counts"]["programs"] == COUNT
    assert not failures, "\n".join(failures)
