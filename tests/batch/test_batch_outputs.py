"""Each plan's outputs of ``trcopt batch``: every kind ``trcopt plan`` writes as text, the same
content as the plan command's, and no feed profile for a plan that was not timed."""

from __future__ import annotations

import csv
import json
from pathlib import Path

from trcopt.batch import load_sweep, run_batch
from trcopt.batch.sweep import OUTPUT_KINDS
from trcopt.cli import main

ROOT = Path(__file__).resolve().parents[2]
PROGRAM = ROOT / "problems" / "siemens" / "ex02_square_g450.mpf"


def _sweep(folder: Path, options: str = "") -> Path:
    path = folder / "sweep.toml"
    path.write_text(
        f"programs = [{json.dumps(str(PROGRAM))}]\n"
        f"outputs = {json.dumps(list(OUTPUT_KINDS))}\n[options]\n{options}\n"
    )
    return path


def test_every_output_kind_is_written_as_the_plan_command_writes_it(tmp_path: Path) -> None:
    assert set(OUTPUT_KINDS) == {"json", "gcode", "svg", "html", "csv"}
    out = tmp_path / "plans"
    report = run_batch(load_sweep(_sweep(tmp_path)), tmp_path / "r.csv", workers=1, out_dir=out)
    row = report.rows[0]
    assert row["ok"]
    stem = f"{PROGRAM.stem}.{row['key'][:10]}"
    files = {p.name for p in out.iterdir()}
    assert files == {f"{stem}{s}" for s in (".plan.json", ".nc", ".svg", ".html", ".feed.csv")}
    # the plan command on the same program writes the same pictures and feed profile
    single = tmp_path / "single"
    single.mkdir()
    assert main(["plan", str(PROGRAM), "--svg", str(single / "p.svg"), "--html", str(single / "p.html"),
                 "--csv", str(single / "p.csv"), "-q"]) == 0  # fmt: skip
    svg = (out / f"{stem}.svg").read_text()
    assert svg.startswith("<svg") or svg.startswith("<?xml")
    assert svg == (single / "p.svg").read_text()
    html = (out / f"{stem}.html").read_text()
    assert html.lstrip().lower().startswith("<!doctype html") and "</html>" in html
    rows = list(csv.reader((out / f"{stem}.feed.csv").read_text().splitlines()))
    assert rows == list(csv.reader((single / "p.csv").read_text().splitlines()))
    assert len(rows) > 100 and float(rows[-1][0]) == row["cycle_time_s"]
    plan = json.loads((out / f"{stem}.plan.json").read_text())
    assert abs(plan["timing"]["duration_s"] - row["cycle_time_s"]) < 1e-5


def test_no_feed_profile_without_timing(tmp_path: Path) -> None:
    out = tmp_path / "plans"
    report = run_batch(load_sweep(_sweep(tmp_path, "timing = false")), tmp_path / "r.csv", workers=1, out_dir=out)
    assert report.rows[0]["ok"] and report.rows[0]["cycle_time_s"] is None
    suffixes = sorted(p.name.split(".", 2)[-1] for p in out.iterdir())
    assert suffixes == ["html", "nc", "plan.json", "svg"]
