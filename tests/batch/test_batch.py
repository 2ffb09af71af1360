"""``trcopt batch``: sweeps, the results table, a Dask cluster, failing programs and resuming."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

import trcopt.batch.run as batch_run
from trcopt.batch import COLUMNS, job_key, load_sweep, read_rows, run_batch
from trcopt.cli import main
from trcopt.errors import ConfigError, TrcoptError

ROOT = Path(__file__).resolve().parents[2]
PROBLEMS = ROOT / "problems"
# three golden problems of three kinds: G450 square, a Heidenhain rectangle, a corner problem
GOLDEN = ["siemens/ex02_square_g450.mpf", "heidenhain/h01_rectangle_rl.h", "siemens/ex05_kont_g450.mpf"]
TOLERANCES = [0.005, 0.01, 0.05]


def _sweep(folder: Path, *, extra_programs: tuple[str, ...] = (), outputs: str = "") -> Path:
    programs = [str(PROBLEMS / g) for g in GOLDEN] + list(extra_programs)
    path = folder / "sweep.toml"
    path.write_text(
        f"programs = {json.dumps(programs)}\n{outputs}\n"
        "[options]\ncorners = \"arc\"\n\n"
        f"[axes]\ntolerance = {json.dumps(TOLERANCES)}\n"
    )
    return path


def test_a_toml_sweep_is_the_cross_product_with_stable_keys(tmp_path: Path) -> None:
    sweep = load_sweep(_sweep(tmp_path))
    assert len(sweep.jobs) == 9
    assert {(Path(j.program).name, dict(j.options)["tolerance"]) for j in sweep.jobs} == {
        (Path(g).name, t) for g in GOLDEN for t in TOLERANCES
    }
    assert all(j.plan_options.corners == "arc" and j.plan_options.workers == 1 for j in sweep.jobs)
    assert {j.plan_options.tolerance_mm for j in sweep.jobs} == set(TOLERANCES)
    # the key hashes the program and the option set, whatever their order
    j = sweep.jobs[0]
    assert j.key == job_key(j.program, dict(reversed(j.options)))
    assert len({j.key for j in sweep.jobs}) == 9
    assert [j.key for j in load_sweep(tmp_path / "sweep.toml").jobs] == [j.key for j in sweep.jobs]


def test_a_csv_sweep_has_one_option_set_a_row_and_globs_relative_to_it(tmp_path: Path) -> None:
    (tmp_path / "progs").mkdir()
    for g in GOLDEN[:2]:
        (tmp_path / "progs" / Path(g).name).write_text((PROBLEMS / g).read_text())
    machine = tmp_path / "slow.toml"
    machine.write_text(
        "name = 'slow'\n[axes.X]\nvmax_mm_s = 50\namax_mm_s2 = 500\n[axes.Y]\nvmax_mm_s = 50\namax_mm_s2 = 500\n"
        "[axes.Z]\nvmax_mm_s = 50\namax_mm_s2 = 500\n"
    )
    path = tmp_path / "sweep.csv"
    path.write_text("program,corners,tolerance,machine,jerk\nprogs/*,arc,0.02,slow.toml,no\nprogs/*.h,exact,,,\n")
    sweep = load_sweep(path)
    assert [(j.program, j.options_text) for j in sweep.jobs] == [
        ("progs/ex02_square_g450.mpf", "corners=arc jerk=false machine=slow.toml tolerance=0.02"),
        ("progs/h01_rectangle_rl.h", "corners=arc jerk=false machine=slow.toml tolerance=0.02"),
        ("progs/h01_rectangle_rl.h", "corners=exact"),
    ]
    assert sweep.jobs[0].plan_options.machine.name == "slow"
    assert sweep.jobs[2].plan_options.machine.name != "slow"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("programs = ['*.nothing']\n", "no program matches"),
        ("programs = ['{p}']\n[axes]\nfeedrate = [1, 2]\n", "unknown option 'feedrate'"),
        ("programs = ['{p}']\n[axes]\ncorners = ['round']\n", "--corners"),
        ("programs = ['{p}']\n[axes]\ntolerance = [-1]\n", "positive finite"),
        ("programs = ['{p}']\n[options]\njerk = 'maybe'\n", "jerk must be true or false"),
        ("programs = ['{p}']\n[axes]\nmachine = ['missing.toml']\n", "cannot read machine file"),
        ("programs = ['{p}', '{p}']\noutputs = ['pdf']\n", "unknown output 'pdf'"),
    ],
)
def test_a_bad_sweep_is_an_error_before_any_plan(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text.replace("{p}", str(PROBLEMS / GOLDEN[0])))
    with pytest.raises(TrcoptError, match=message):
        load_sweep(path)


def test_three_by_three_sweep_on_a_local_dask_cluster(tmp_path: Path, capsys) -> None:
    distributed = pytest.importorskip("distributed")
    sweep = _sweep(tmp_path, outputs='outputs = ["json", "gcode"]')
    results, out_dir = tmp_path / "results.csv", tmp_path / "plans"
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        with distributed.get_task_stream(client) as tasks:
            status = main([
                "batch", str(sweep), "--results", str(results), "--scheduler", cluster.scheduler_address,
                "--out-dir", str(out_dir),
            ])
        ran_on_dask = [t for t in tasks.data if str(t["key"]).startswith("trcopt-")]
        # interrupted after four rows, the fifth torn: the re-run on the cluster plans the five others
        full = results.read_text()
        lines = full.splitlines(keepends=True)
        results.write_text("".join(lines[:5]) + lines[5][:25])
        with distributed.get_task_stream(client) as again:
            resumed = main([
                "batch", str(sweep), "--results", str(results), "--scheduler", cluster.scheduler_address,
                "--out-dir", str(out_dir), "-q",
            ])
        rerun = sorted(str(t["key"]) for t in again.data if str(t["key"]).startswith("trcopt-"))
    assert resumed == 0 and rerun == sorted(f"trcopt-{ln.split(',')[0]}" for ln in lines[5:])
    wall = COLUMNS.index("wall_time_s")

    def rows_without_wall_time(text: str) -> list[list[str]]:
        return sorted(r[:wall] + r[wall + 1 :] for r in csv.reader(text.splitlines()))

    assert rows_without_wall_time(results.read_text()) == rows_without_wall_time(full)  # none twice, none lost
    assert status == 0, capsys.readouterr().err
    assert len(ran_on_dask) == 9  # every plan was a task of the cluster
    rows = json.loads(results.with_suffix(".json").read_text())["rows"]
    assert [r["key"] for r in rows] == [j.key for j in load_sweep(sweep).jobs]  # sweep order
    for row in rows:
        tol = float(row["options"].split("tolerance=")[1])
        assert row["ok"] and row["exit_status"] == 0 and row["alarms"] == 0 and row["error"] == ""
        assert row["cycle_time_s"] > 0 and row["path_length_mm"] > 0 and row["wall_time_s"] >= 0
        assert row["max_deviation_mm"] is None or row["max_deviation_mm"] <= tol + 1e-9
    # a looser tolerance never makes a plan slower (same program, arc blends)
    for g in GOLDEN:
        times = [r["cycle_time_s"] for r in rows if r["program"].endswith(Path(g).name)]
        assert times == sorted(times, reverse=True)
    # each plan's outputs, named by program and key, are complete JSON and G-code
    for row in rows:
        stem = Path(row["program"]).stem
        plan = json.loads((out_dir / f"{stem}.{row['key'][:10]}.plan.json").read_text())
        assert plan["ok"] and abs(plan["timing"]["duration_s"] - row["cycle_time_s"]) < 1e-5
        assert (out_dir / f"{stem}.{row['key'][:10]}.nc").read_text().strip()
    # the same sweep in this process gives the same numbers
    in_process = load_sweep(sweep)
    in_process.outputs = ()
    local = run_batch(in_process, tmp_path / "local.csv", workers=1)
    assert [r["cycle_time_s"] for r in local.rows] == [r["cycle_time_s"] for r in rows]
    assert "9 plan(s): 9 ok" in capsys.readouterr().out


def test_a_failing_program_is_a_row_not_the_end_of_the_batch(tmp_path: Path) -> None:
    binary = tmp_path / "binary.mpf"
    binary.write_bytes(b"N10 G1 X1\x00\x00\x00")
    sweep = _sweep(tmp_path, extra_programs=(str(binary), str(PROBLEMS / "siemens" / "ex01_seed_g460.mpf")))
    report = run_batch(load_sweep(sweep), tmp_path / "r.csv", workers=2)
    assert len(report.rows) == 15 and len(report.ran) == 15
    by_program = {}
    for r in report.rows:
        by_program.setdefault(Path(r["program"]).name, []).append(r)
    assert all(r["exit_status"] == 2 and not r["ok"] for r in by_program["binary.mpf"])
    assert all("error NC-NOT-TEXT" in r["error"] for r in by_program["binary.mpf"])
    alarmed = by_program["ex01_seed_g460.mpf"]
    assert all(r["exit_status"] == 1 and r["alarms"] == 1 and r["first_alarm"] == "10751" for r in alarmed)
    assert all(":7:5: error 10751 (N60):" in r["error"] for r in alarmed)
    assert sum(r["exit_status"] == 0 for r in report.rows) == 9
    assert report.failed == 3 and report.alarmed == 3


def test_a_rerun_plans_only_the_missing_rows(tmp_path: Path, monkeypatch) -> None:
    sweep = load_sweep(_sweep(tmp_path))
    full = run_batch(sweep, tmp_path / "full.csv", workers=1)
    assert len(full.ran) == 9
    # an interrupted run: 4 complete rows on disk and a fifth cut in the middle of its line
    lines = (tmp_path / "full.csv").read_text().splitlines(keepends=True)
    partial = tmp_path / "partial.csv"
    partial.write_text("".join(lines[:5]) + lines[5][:20])
    assert [r["key"] for r in read_rows(partial)] == [r["key"] for r in full.rows[:4]]
    planned: list[str] = []
    real_run_job = batch_run.run_job

    def counting(work):  # type: ignore[no-untyped-def]
        planned.append(work.job.key)
        return real_run_job(work)

    monkeypatch.setattr(batch_run, "run_job", counting)
    again = run_batch(sweep, partial, workers=1)
    missing = [r["key"] for r in full.rows[4:]]
    assert planned == missing and again.ran == missing
    assert again.skipped == [r["key"] for r in full.rows[:4]]
    with partial.open(newline="") as fh:
        table = list(csv.reader(fh))
    assert tuple(table[0]) == COLUMNS and len(table) == 10  # header and 9 rows: none twice, none torn
    assert sorted(r[0] for r in table[1:]) == sorted(r["key"] for r in full.rows)
    assert [r["cycle_time_s"] for r in again.rows] == [r["cycle_time_s"] for r in full.rows]
    # a third run has nothing to do
    planned.clear()
    assert run_batch(sweep, partial, workers=1).ran == [] and planned == []


def test_batch_command_resumes_and_reports(tmp_path: Path, capsys) -> None:
    sweep = _sweep(tmp_path)
    assert main(["batch", str(sweep), "--workers", "1"]) == 0
    first = capsys.readouterr().out
    assert "9 plan(s): 9 ok, 0 with an alarm, 0 failed; 9 planned now, 0 already in the table" in first
    assert (tmp_path / "sweep-results.csv").exists() and (tmp_path / "sweep-results.json").exists()
    assert main(["batch", str(sweep), "--workers", "1"]) == 0
    assert "0 planned now, 9 already in the table" in capsys.readouterr().out
    assert main(["batch", str(sweep), "--workers", "1", "--fresh", "-q"]) == 0
    assert capsys.readouterr().out == ""


def test_batch_command_usage_errors(tmp_path: Path, capsys) -> None:
    sweep = _sweep(tmp_path)
    (tmp_path / "dir.csv").mkdir()
    assert main(["batch", str(sweep), "--results", str(tmp_path / "dir.csv")]) == 2
    assert "error OUTPUT:" in capsys.readouterr().err
    other = tmp_path / "other.csv"
    other.write_text("a,b\n1,2\n")
    assert main(["batch", str(sweep), "--results", str(other)]) == 2
    assert "not a trcopt batch results table" in capsys.readouterr().err
    assert other.read_text() == "a,b\n1,2\n"  # untouched
    assert main(["batch", str(tmp_path / "missing.toml")]) == 2
    assert "trcopt: error IO: cannot read sweep file" in capsys.readouterr().err
    with_outputs = _sweep(tmp_path, outputs='outputs = ["json"]')
    assert main(["batch", str(with_outputs)]) == 2
    assert "--out-dir" in capsys.readouterr().err


def test_sweep_names_a_file_twice(tmp_path: Path) -> None:
    path = tmp_path / "twice.toml"
    p = PROBLEMS / GOLDEN[0]
    path.write_text(f"programs = ['{p}', '{p.parent}/ex02_*.mpf']\n")
    sweep = load_sweep(path)  # one file matched by two globs is planned once
    assert [Path(j.program).name for j in sweep.jobs] == ["ex02_square_g450.mpf", "ex02_square_g451.mpf"]
    with pytest.raises(ConfigError):
        (tmp_path / "empty.toml").write_text("programs = []\n")
        load_sweep(tmp_path / "empty.toml")


def test_a_fresh_run_that_cannot_reach_the_cluster_keeps_the_table(tmp_path: Path, monkeypatch, capsys) -> None:
    distributed = pytest.importorskip("distributed")
    sweep = _sweep(tmp_path)
    assert main(["batch", str(sweep), "--workers", "1", "-q"]) == 0
    table = tmp_path / "sweep-results.csv"
    before = table.read_text()

    class Unreachable:
        def __init__(self, address: str, timeout: float = 0.0) -> None:
            raise OSError(f"Timed out trying to connect to {address}")

    monkeypatch.setattr(distributed, "Client", Unreachable)
    assert main(["batch", str(sweep), "--fresh", "--scheduler", "tcp://127.0.0.1:1", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("trcopt: error IO: cannot reach the Dask scheduler") and "Traceback" not in err
    assert table.read_text() == before  # the nine finished rows are still there
