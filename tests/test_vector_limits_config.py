"""The ``[path]`` table of a machine file: vector limits on the tool-centre motion (docs/machine.md)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.config import DEFAULT_MACHINE, Machine, PathLimits, load_machine, machine_from_dict
from trcopt.errors import ConfigError
from trcopt.io.schema import validate_plan

ROOT = Path(__file__).resolve().parents[1]
POCKET = ROOT / "problems" / "corners" / "pocket_square.mpf"

FULL = """
name = "vector mill"

[axes.X]
vmax_mm_s = 250.0
amax_mm_s2 = 2000.0

[path]
vmax_mm_s = 100.0      # tool-centre speed
amax_mm_s2 = 3000.0    # |acceleration vector|
jmax_mm_s3 = 60000.0   # |jerk vector|
"""


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "mill.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_path_table_parses_beside_the_axis_limits(tmp_path: Path) -> None:
    m = load_machine(_write(tmp_path, FULL))
    assert m.path == PathLimits(100.0, 3000.0, 60000.0)
    assert m.path.given
    assert m.axis("X").amax_mm_s2 == 2000.0 and m.axis("Z") == DEFAULT_MACHINE.axis("Z")
    assert m.to_json()["path"] == {"vmax_mm_s": 100.0, "amax_mm_s2": 3000.0, "jmax_mm_s3": 60000.0}


def test_each_path_key_is_optional_and_integers_are_numbers() -> None:
    m = machine_from_dict({"path": {"amax_mm_s2": 3000}})
    assert m.path == PathLimits(amax_mm_s2=3000.0)
    assert isinstance(m.path.amax_mm_s2, float)
    assert m.path.vmax_mm_s is None and m.path.jmax_mm_s3 is None
    assert m.to_json()["path"] == {"vmax_mm_s": None, "amax_mm_s2": 3000.0, "jmax_mm_s3": None}
    empty = machine_from_dict({"path": {}})
    assert not empty.path.given and "path" not in empty.to_json()


def test_without_path_table_there_are_no_vector_limits() -> None:
    assert not DEFAULT_MACHINE.path.given
    assert machine_from_dict({}).path == PathLimits()
    assert "path" not in DEFAULT_MACHINE.to_json()  # the plan JSON stays as it was
    assert Machine(path=None).path == PathLimits()  # type: ignore[arg-type]


def test_unknown_path_key_is_an_error_naming_key_and_file(tmp_path: Path) -> None:
    p = _write(tmp_path, "[path]\nvmax_mm_s = 100.0\nomega_max = 3.0\n")
    with pytest.raises(ConfigError, match=r"unknown key path\.omega_max") as exc:
        load_machine(p)
    assert str(p) in str(exc.value)


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("vmax_mm_s", "0.0"),
        ("amax_mm_s2", "-3000.0"),
        ("jmax_mm_s3", "inf"),
        ("vmax_mm_s", "nan"),
        ("amax_mm_s2", '"3000"'),
        ("jmax_mm_s3", "true"),
        ("vmax_mm_s", "[100.0]"),
    ],
)
def test_bad_path_value_is_an_error_naming_the_key(tmp_path: Path, key: str, value: str) -> None:
    with pytest.raises(ConfigError, match=rf"path\.{key} must be a positive finite number"):
        load_machine(_write(tmp_path, f"[path]\n{key} = {value}\n"))


def test_path_must_be_a_table() -> None:
    with pytest.raises(ConfigError, match="'path' must be a table"):
        machine_from_dict({"path": 100.0})


def test_path_limits_validate_when_built_in_python() -> None:
    with pytest.raises(ConfigError, match="amax_mm_s2"):
        PathLimits(amax_mm_s2=0.0)
    with pytest.raises(ConfigError, match="vmax_mm_s"):
        PathLimits(vmax_mm_s=math.inf)
    with pytest.raises(ConfigError, match="PathLimits"):
        Machine(path={"vmax_mm_s": 1.0})  # type: ignore[arg-type]


def test_cli_reports_a_bad_path_key_with_exit_status_2(tmp_path: Path, capsys) -> None:
    p = _write(tmp_path, "[path]\nvmax = 100.0\n")
    rc = main(["plan", str(POCKET), "--machine", str(p), "--no-timing"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "unknown key path.vmax" in err and str(p) in err


def test_cli_plan_json_carries_the_vector_limits(tmp_path: Path) -> None:
    p = _write(tmp_path, "[path]\nvmax_mm_s = 80.0\namax_mm_s2 = 1500.0\n")
    out = tmp_path / "plan.json"
    assert main(["plan", str(POCKET), "--machine", str(p), "--json", str(out), "--quiet"]) == 0
    doc = json.loads(out.read_text())
    validate_plan(doc)  # the new keys fit the plan schema
    timing = doc["timing"]
    assert timing["machine"]["path"] == {"vmax_mm_s": 80.0, "amax_mm_s2": 1500.0, "jmax_mm_s3": None}
    assert timing["limits_ok"] is True
    assert timing["max_ratios"]["path"]["v"] <= 1.001 and timing["max_ratios"]["path"]["a"] <= 1.001
    assert timing["max_ratios"]["path"]["j"] is None
    assert {s["binding"] for s in timing["sections"]} & {"path velocity", "path acceleration"}
