"""Machine, tool-table and carrier files: every limit positive and finite, a number where a number
belongs, and a file that is not UTF-8 text a located ``ConfigError`` (no traceback)."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.config import load_machine
from trcopt.errors import ConfigError

ROOT = Path(__file__).resolve().parents[1]
POCKET = ROOT / "problems" / "corners" / "pocket_square.mpf"
BINARY = b"\xff\xfe\x00\x81garbage\x00"


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "mill.toml"
    p.write_text(text, encoding="utf-8")
    return p


@pytest.mark.parametrize("value", ["0", "-6000.0", "inf", "nan", "true", '"6000"'])
def test_rapid_feed_must_be_a_positive_finite_number(tmp_path: Path, value: str) -> None:
    p = _write(tmp_path, f"rapid_mm_min = {value}\n")
    with pytest.raises(ConfigError, match=r"rapid_mm_min must be a positive finite number") as exc:
        load_machine(p)
    assert str(p) in str(exc.value)


@pytest.mark.parametrize(
    ("key", "value"),
    [("vmax_mm_s", "0.0"), ("amax_mm_s2", "-1.0"), ("vmax_mm_s", "inf"), ("amax_mm_s2", "nan"),
     ("vmax_mm_s", '"500"'), ("amax_mm_s2", "true"), ("jmax_mm_s3", "-inf")],
)
def test_axis_limits_must_be_positive_finite_numbers(tmp_path: Path, key: str, value: str) -> None:
    limits = {"vmax_mm_s": "500.0", "amax_mm_s2": "3000.0", key: value}
    body = "\n".join(f"{k} = {v}" for k, v in limits.items())
    p = _write(tmp_path, f"[axes.Y]\n{body}\n")
    with pytest.raises(ConfigError, match=rf"axes\.Y\.{key} must be a positive finite number") as exc:
        load_machine(p)
    assert str(p) in str(exc.value)


def test_a_machine_file_that_is_not_text_is_an_error_naming_it(tmp_path: Path, capsys) -> None:
    p = tmp_path / "mill.toml"
    p.write_bytes(BINARY)
    assert main(["plan", str(POCKET), "--machine", str(p), "--no-timing"]) == 2
    err = capsys.readouterr().err
    assert f"trcopt: error CONFIG: {p}: not a text file" in err and "Traceback" not in err


@pytest.mark.parametrize("kind", ["heidenhain tool table", "carrier"])
def test_a_toml_file_that_is_not_text_is_an_error_naming_it(tmp_path: Path, kind: str) -> None:
    from trcopt.controllers.heidenhain.tooltable import load_tool_table
    from trcopt.kinematics.carrier_toml import load_carrier_toml

    load = load_tool_table if kind == "heidenhain tool table" else load_carrier_toml
    p = tmp_path / "file.toml"
    p.write_bytes(BINARY)
    with pytest.raises(ConfigError, match="not a text file") as exc:
        load(p)
    assert str(p) in str(exc.value)
