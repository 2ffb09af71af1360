"""A plan's outputs are byte-identical on every rerun, with worker processes and the optimisation
on: JSON, G-code, SVG and CSV (the JSON names the CSV file, so both runs write the same names)."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.cli import main

ROOT = Path(__file__).resolve().parents[2]
OUTPUTS = ("plan.json", "plan.gcode", "plan.svg", "feed.csv")


def _run(program: Path, folder: Path, extra: list[str]) -> dict[str, bytes]:
    folder.mkdir()
    files = [folder / name for name in OUTPUTS]
    args = ["plan", str(program), "-q", "--json", str(files[0]), "--gcode", str(files[1]), "--svg", str(files[2])]
    assert main([*args, "--csv", str(files[3]), *extra]) == 0
    return {f.name: f.read_bytes() for f in files}


@pytest.mark.parametrize(
    ("program", "extra"),
    [
        ("siemens/ex06_bottleneck_cdon.mpf", []),
        ("corners/corner_30deg.mpf", ["--corners", "optimal", "--workers", "2"]),
        ("corners/corner_30deg.mpf", ["--corners", "optimal", "--jerk", "--workers", "2"]),
        ("heidenhain/h06_appr_dep_ct.h", []),
    ],
    ids=["siemens", "optimal-workers", "optimal-jerk", "heidenhain"],
)
def test_outputs_are_byte_identical_on_rerun(program, extra, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # relative output names: both runs write the same text
    source = ROOT / "problems" / program
    first = _run(source, Path("a"), extra)
    second = _run(source, Path("b"), extra)
    first_json = first.pop("plan.json").replace(b'"a/feed.csv"', b'"feed.csv"')
    second_json = second.pop("plan.json").replace(b'"b/feed.csv"', b'"feed.csv"')
    assert first_json == second_json and first == second
