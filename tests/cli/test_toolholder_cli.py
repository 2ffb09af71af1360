"""``trcopt orient`` through a local argparse parser (the main CLI calls ``add_arguments``)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pytest

from trcopt.cli import orient as cli

PROBLEMS = Path(__file__).resolve().parents[2] / "problems" / "toolholder"


def run(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="trcopt")
    sub = parser.add_subparsers(dest="command")
    cli.add_arguments(sub.add_parser("orient"))
    args = parser.parse_args(["orient", *argv])
    return args.handler(args)


def test_orient_frame_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "o.json"
    rc = run(["--carrier", str(PROBLEMS / "e2_ac_fork_head.toml"), "--frame", "30", "0", "0",
              "--json", str(out)])
    assert rc == 0
    text = capsys.readouterr().out
    assert "chosen: (0.000000, 30.000000)" in text and "closest" in text
    data = json.loads(out.read_text())
    assert set(data) >= {"solutions", "chosen", "p_tcang", "tool_vector", "diagnostics"}
    np.testing.assert_allclose(data["solutions"], [[0, 30], [180, -30]], atol=1e-9)
    np.testing.assert_allclose(data["chosen"], [0, 30], atol=1e-9)
    np.testing.assert_allclose(data["p_tcang"], [0, 30, 180, -30], atol=1e-9)
    np.testing.assert_allclose(data["tool_vector"], [0, -125, 66.5064], atol=1e-4)
    assert data["diagnostics"] == []


def test_orient_limits_swap_and_plane(tmp_path: Path) -> None:
    out = tmp_path / "o.json"
    rc = run(["--carrier", str(PROBLEMS / "e8_trunnion_table_limits.toml"),
              "--frame", "0", "40", "30", "--plane", "G18", "--json", str(out)])
    assert rc == 0
    data = json.loads(out.read_text())
    np.testing.assert_allclose(data["chosen"], [40, 150], atol=1e-9)
    np.testing.assert_allclose(data["p_tcang"], [40, 150, -40, -30], atol=1e-9)
    np.testing.assert_allclose(data["tool_vector"], [0, 100, 0], atol=1e-9)  # G18: L1 -> Y
    np.testing.assert_allclose(data["table_offset"], [134.5937, -25.0, -46.55], atol=1e-4)


def test_orient_direction_hirth(tmp_path: Path) -> None:
    out = tmp_path / "o.json"
    rc = run(["--carrier", str(PROBLEMS / "e10_hirth_head.toml"), "--direction", "2", "0", "3",
              "--json", str(out)])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["chosen"][0] == pytest.approx(32.5)
    assert data["p_tcang"][2] is None


def test_orient_unreachable_exit_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "o.json"
    rc = run(["--carrier", str(PROBLEMS / "e4_nutating_head.toml"), "--frame", "0", "120",
              "--json", str(out)])
    assert rc == 1
    err = capsys.readouterr().err
    assert "TH-UNREACHABLE" in err and "Traceback" not in err
    data = json.loads(out.read_text())
    assert data["solutions"] == [] and data["chosen"] is None
    assert data["diagnostics"][0]["code"] == "TH-UNREACHABLE"


def test_orient_program_carrier_and_alarm_14153(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["--carrier", str(PROBLEMS / "ac_fork_head.mpf"), "--frame", "30"]) == 0
    assert "(180.000000, -30.000000)" in capsys.readouterr().out  # specified (170, -20)
    rc = run(["--carrier", str(PROBLEMS / "bad_kinematic_type.mpf"), "--direction", "0", "0", "1"])
    assert rc == 1
    err = capsys.readouterr().err
    assert "bad_kinematic_type.mpf: error 14153" in err and "toolholder 2" in err


def test_orient_file_errors_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    missing = tmp_path / "absent.toml"
    assert run(["--carrier", str(missing), "--direction", "0", "0", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{missing}: error ") and "Traceback" not in err
    bad = tmp_path / "bad.toml"
    bad.write_text("TC_CARR99 = 1\n")
    assert run(["--carrier", str(bad), "--direction", "0", "0", "1"]) == 2
    assert "TC_CARR99" in capsys.readouterr().err
    good = PROBLEMS / "e2_ac_fork_head.toml"
    assert run(["--carrier", str(good), "--direction", "0", "0", "0"]) == 2
    assert run(["--carrier", str(good), "--frame", "1", "2", "3", "4"]) == 2


def test_orient_usage_error_is_argparse_exit_2() -> None:
    with pytest.raises(SystemExit) as ei:
        run(["--carrier", "x.toml"])  # neither --direction nor --frame
    assert ei.value.code == 2


def test_add_arguments_sets_the_handler() -> None:
    parser = argparse.ArgumentParser(prog="trcopt")
    sub = parser.add_subparsers(dest="command")
    cli.add_arguments(sub.add_parser("orient"))
    args = parser.parse_args(["orient", "--carrier", "x.toml", "--direction", "0", "0", "1"])
    assert args.handler is cli.run_orient
