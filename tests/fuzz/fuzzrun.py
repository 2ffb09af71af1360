"""Run mutated programs through ``trcopt plan`` in-process and classify what went wrong.

Each program (:mod:`fuzzgen`) is written to a fresh folder (with the Heidenhain ``tools.toml`` or
LinuxCNC ``tools.tbl`` beside it) and planned by :func:`trcopt.cli.main` with ``--json``,
``--gcode``, ``--svg`` and, with timing, ``--csv``; every fourth program runs ``--no-timing``, and
every fourth other one window by window with ``--json`` and ``--gcode`` (compared with the whole
plan). A
program fails in one of these classes:

=============  ====================================================================================
traceback      an exception escaped ``main`` (``MemoryError``, ``IndexError``, …)
internal       a reader's safety net caught a bug in a block (``NC-INTERNAL``): located, still a bug
hang           it ran longer than the wall-clock limit (``signal.alarm``)
exit           an exit status other than 0, 1, 2
unlocated      an error diagnostic without file, line ≥ 1, column ≥ 1, or without the block number
               of a line that has one; or a ``trcopt: error:`` line that does not name the program
nonfinite      ``nan``/``inf`` in the summary, the JSON (``parse_constant`` rejects them), the
               G-code, the SVG or the CSV
partial        an output that exists but is not complete and parseable, or a temporary file left
stream         planned window by window (``--stream on``, every fourth program, ``--json`` and
               ``--gcode`` only) it exits, prints or writes other than the whole plan
               (``--stream off``) does (:mod:`plancompare`)
=============  ====================================================================================

Run as a script (``python tests/fuzz/fuzzrun.py --count N --seed S``) it prints one JSON line per
failing program and a last line with the counts; it limits its address space (``--memory-gb``) so
a runaway allocation is a ``MemoryError`` rather than the machine's out-of-memory killer.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import math
import re
import shutil
import signal
import sys
import tempfile
import time
import traceback
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fuzzgen import ROOT, RS274_TOOL_TABLE, FuzzProgram, programs  # noqa: E402
from plancompare import disagreement  # noqa: E402

__all__ = ["CLASSES", "Outcome", "run_program", "run_batch", "main"]

CLASSES = ("traceback", "internal", "hang", "exit", "unlocated", "nonfinite", "partial", "stream")
_ERROR_LINE = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<col>\d+): error (?P<code>\S+)(?: \((?P<block>[^)]*)\))?: ")
_NONFINITE = re.compile(r"(?<![A-Za-z_])(?:nan|inf|infinity)(?![A-Za-z_])", re.IGNORECASE)
_QUOTED = re.compile(r"\([^)\n]*\)|;[^\n]*|<text[^>]*>.*?</text>|<title>[^<]*</title>|<!--.*?-->", re.S)
_FLOAT = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_BLOCK_NUMBER = {".mpf": re.compile(r"^\s*N[0-9]+(?=[ \t]|$)"), ".ngc": re.compile(r"^\s*N[0-9]+(?=[ \t]|$)", re.I),
                 ".h": re.compile(r"^\s*[0-9]+[ \t]")}


class Hang(BaseException):
    """Raised by the alarm signal: the program ran past its wall-clock limit."""


@dataclass(frozen=True, slots=True)
class Outcome:
    """What happened to one program: its name, the failure class ("" when fine), a detail, seconds."""

    name: str
    failure: str
    detail: str
    exit: int | None
    seconds: float


def _on_alarm(signum: int, frame: object) -> None:
    raise Hang


def _program_lines(data: bytes) -> list[str]:
    """The program's lines as an editor numbers them (LF, CR LF, CR), decoded as trcopt decodes
    (UTF-16 with its mark, UTF-8 with or without one, else Latin-1)."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        text = data.decode("utf-16", "replace")
    else:
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError:
            text = data.decode("latin-1")
    return re.split(r"\r\n|\r|\n", text)


def _check_errors(stderr: str, program: Path, data: bytes, suffix: str) -> str:
    """The first unlocated error line on standard error, or ""."""
    lines = _program_lines(data)
    has_number = _BLOCK_NUMBER.get(suffix)
    for text in stderr.splitlines():
        if not text.strip():
            continue
        if text.startswith("trcopt: error:"):
            if str(program) not in text and program.name not in text:
                return text
            continue
        m = _ERROR_LINE.match(text)
        if m is None:
            if ": error " in text or text.startswith(str(program)):
                return text
            continue
        if m["file"] != str(program) or int(m["line"]) < 1 or int(m["col"]) < 1:
            return text
        line_no = int(m["line"])
        source = lines[line_no - 1] if line_no <= len(lines) else ""
        if has_number is not None and has_number.match(source) and not m["block"]:
            return f"no block number: {text}"
    return ""


def _reject(name: str) -> float:
    raise ValueError(f"non-finite constant {name} in JSON")


def _check_outputs(folder: Path, outputs: dict[str, Path]) -> tuple[str, str]:
    """(class, detail) of the first bad output, or ("", "")."""
    for leftover in folder.glob(".*.tmp"):
        return "partial", f"temporary file left: {leftover.name}"
    for kind, path in outputs.items():
        if not path.exists():
            continue
        text = path.read_text(encoding="utf-8")
        try:
            if kind == "json":
                json.loads(text, parse_constant=_reject)
            elif kind == "svg":
                ET.fromstring(text)
            elif kind == "csv":
                rows = list(csv.reader(io.StringIO(text)))
                if not rows or not rows[0]:
                    raise ValueError("empty CSV")
                for row in rows[1:]:
                    if len(row) != len(rows[0]):
                        raise ValueError(f"CSV row of {len(row)} fields, header has {len(rows[0])}")
                    if any(_NONFINITE.fullmatch(v.strip()) for v in row):
                        return "nonfinite", f"{kind}: {row}"
                    if not any(math.isfinite(float(v)) for v in row if _FLOAT.fullmatch(v.strip())):
                        raise ValueError(f"CSV row without a number: {row}")
            elif kind == "gcode" and not text.rstrip().endswith(("M30", "M2", "M02", "%", "END PGM")):
                if not re.search(r"\b(M30|M2|M02)\b", text[-200:]):
                    raise ValueError("G-code without its end")
        except ValueError as exc:
            if "non-finite" in str(exc):
                return "nonfinite", f"{kind}: {exc}"
            return "partial", f"{kind}: {exc}"
        except ET.ParseError as exc:
            return "partial", f"{kind}: {exc}"
        # numbers only: comments and SVG text quote the program's words
        numbers = _QUOTED.sub("", text) if kind in ("gcode", "svg") else ""
        found = _NONFINITE.search(numbers)
        if found:
            return "nonfinite", f"{kind}: {numbers[max(0, found.start() - 60):found.end() + 20]!r}"
    return "", ""


def run_program(prog: FuzzProgram, index: int, *, timeout_s: float = 30.0, work: Path | None = None) -> Outcome:
    """Plan ``prog`` through the command line in-process and classify the result."""
    from trcopt.cli import main as cli_main

    folder = Path(tempfile.mkdtemp(prefix="fuzz-", dir=work))
    try:
        program = folder / f"prog{prog.suffix}"
        program.write_bytes(prog.data)
        if prog.suffix == ".h":
            shutil.copy(ROOT / "problems" / "heidenhain" / "tools.toml", folder / "tools.toml")
        elif prog.suffix == ".ngc":
            (folder / "tools.tbl").write_text(RS274_TOOL_TABLE)
        timing = index % 4 != 3
        streamed = index % 4 == 1
        out = folder / "out"
        outputs = {"json": out / "plan.json", "gcode": out / "plan.nc"}
        if not streamed:
            outputs["svg"] = out / "plan.svg"
        if timing and not streamed:
            outputs["csv"] = out / "feed.csv"
        argv = ["plan", str(program), *(["--stream", "on"] if streamed else [])]
        for kind, path in outputs.items():
            argv += [f"--{kind}", str(path)]
        if not timing:
            argv.append("--no-timing")
        stdout, stderr = io.StringIO(), io.StringIO()
        start = time.perf_counter()
        code: int | None = None
        failure, detail = "", ""
        old = signal.signal(signal.SIGALRM, _on_alarm)
        signal.setitimer(signal.ITIMER_REAL, timeout_s)
        try:
            with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
                code = cli_main(argv)
        except Hang:
            failure, detail = "hang", f"over {timeout_s:g} s"
        except SystemExit as exc:  # argparse
            code = exc.code if isinstance(exc.code, int) else 2
        except BaseException as exc:  # noqa: BLE001 — everything that escapes is the finding
            tb = traceback.extract_tb(exc.__traceback__)
            where = f"{Path(tb[-1].filename).name}:{tb[-1].lineno}" if tb else "?"
            failure, detail = "traceback", f"{type(exc).__name__} at {where}: {str(exc)[:200]}"
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)
        seconds = time.perf_counter() - start
        if not failure and code not in (0, 1, 2):
            failure, detail = "exit", f"exit status {code}"
        if not failure and " error NC-INTERNAL" in stderr.getvalue():
            failure, detail = "internal", stderr.getvalue().strip().splitlines()[-1][:300]
        if not failure:
            bad = _check_errors(stderr.getvalue(), program, prog.data, prog.suffix)
            if bad:
                failure, detail = "unlocated", bad[:300]
        if not failure:
            # the summary, not the diagnostics (they quote the program's words)
            summary = "\n".join(t for t in stdout.getvalue().splitlines() if not t.startswith(str(program)))
            m = _NONFINITE.search(summary)
            if m:
                failure, detail = "nonfinite", f"summary: {summary[max(0, m.start() - 80):m.end() + 20]!r}"
        if not failure:
            failure, detail = _check_outputs(out, outputs) if out.exists() else ("", "")
        if not failure and streamed:
            failure, detail = _compare_whole(program, outputs, code, stdout.getvalue(), stderr.getvalue())
        return Outcome(prog.name, failure, detail, code, seconds)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _compare_whole(program: Path, outputs: dict[str, Path], code: int | None, out: str, err: str) -> tuple[str, str]:
    """("stream", detail) when the whole plan (``--stream off``) exits, prints or writes otherwise."""
    from trcopt.cli import main as cli_main

    whole = {kind: path.with_name("whole-" + path.name) for kind, path in outputs.items()}
    argv = ["plan", str(program), "--stream", "off"]
    for kind, path in whole.items():
        argv += [f"--{kind}", str(path)]
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        whole_code = cli_main(argv)
    if whole_code != code:
        return "stream", f"exit {code} window by window, {whole_code} whole"
    if (stdout.getvalue(), stderr.getvalue()) != (out, err):
        return "stream", f"printed {out[-200:]!r} window by window, {stdout.getvalue()[-200:]!r} whole"
    for kind, path in outputs.items():
        if path.exists() != whole[kind].exists():
            return "stream", f"{kind} written only {'window by window' if path.exists() else 'whole'}"
        if not path.exists():
            continue
        if kind == "json":
            differs = disagreement(json.loads(whole[kind].read_text()), json.loads(path.read_text()))
        else:
            differs = None if path.read_text() == whole[kind].read_text() else "the G-code text differs"
        if differs:
            return "stream", f"{kind}: {differs[:250]}"
    return "", ""


def run_batch(count: int, seed: int, *, timeout_s: float = 30.0, start: int = 0) -> list[Outcome]:
    """Every program ``start … count-1`` of the seeded sequence, each run and classified."""
    results = []
    for i, prog in enumerate(programs(count, seed)):
        if i >= start:
            results.append(run_program(prog, i, timeout_s=timeout_s))
    return results


def _limit_memory(gigabytes: float) -> None:
    import resource

    limit = int(gigabytes * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def main(argv: list[str] | None = None) -> int:
    """Run a batch and print one JSON line per failing program, then a JSON line of counts."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--count", type=int, default=300)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--start", type=int, default=0, help="skip the first programs of the sequence")
    p.add_argument("--timeout", type=float, default=30.0, help="wall-clock limit per program, s")
    p.add_argument("--memory-gb", type=float, default=4.0, help="address-space limit of this process")
    args = p.parse_args(argv)
    _limit_memory(args.memory_gb)
    counts: Counter[str] = Counter()
    for i, prog in enumerate(programs(args.count, args.seed)):
        if i < args.start:
            continue
        outcome = run_program(prog, i, timeout_s=args.timeout)
        counts[outcome.failure or "ok"] += 1
        counts["programs"] += 1
        if outcome.failure:
            print(json.dumps({"index": i, **asdict(outcome)}), flush=True)
    print(json.dumps({"counts": dict(counts)}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
