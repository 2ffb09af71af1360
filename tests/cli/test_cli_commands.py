"""Subcommands registered by other modules are reachable through the main command line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from trcopt.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_orient_through_the_main_cli(tmp_path: Path) -> None:
    out = tmp_path / "o.json"
    carrier = ROOT / "problems" / "toolholder" / "e0_cutmod_mixed_head.toml"
    rc = main(["orient", "--carrier", str(carrier), "--direction", "0", "0.7071067811865476", "0.7071067811865476",
               "--json", str(out)])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["chosen"] == pytest.approx([45.0, -90.0], abs=1e-9)
    assert data["p_tcang"] == pytest.approx([45.0, -90.0, -45.0, 90.0], abs=1e-9)
    assert data["tool_vector"] == pytest.approx([100 / 2**0.5, 0.0, 100 / 2**0.5], abs=1e-9)


def test_plan_reports_the_toolholder(tmp_path: Path) -> None:
    prog = tmp_path / "th.mpf"
    prog.write_text(
        (ROOT / "problems" / "toolholder" / "ac_fork_head.mpf").read_text().replace("N90 ROT X30", "N90 ; no frame")
    )
    out = tmp_path / "p.json"
    assert main(["plan", str(prog), "--no-timing", "--json", str(out)]) == 0
    holder = json.loads(out.read_text())["toolholder"]
    assert holder["active"] == 1
    first = holder["activations"][0]
    assert first["word"] == "TCOABS" and first["angles_deg"] == pytest.approx([170.0, -20.0])


def test_missing_carrier_file_is_a_usage_error(tmp_path: Path, capsys) -> None:
    assert main(["orient", "--carrier", str(tmp_path / "none.toml"), "--direction", "0", "0", "1"]) == 2
    assert "Traceback" not in capsys.readouterr().err
