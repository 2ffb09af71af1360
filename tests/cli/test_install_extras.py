"""What ``pip install trcopt`` brings: planning only; plotting, DXF, the preview's browser tests,
the notebooks and Dask are extras, and planning from the command line imports none of them."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
OPTIONAL = ("matplotlib", "ezdxf", "distributed", "selenium", "nbclient", "nbformat", "ipykernel", "pyarrow")


def _name(requirement: str) -> str:
    return requirement.split(";")[0].split("[")[0].split(">")[0].split("=")[0].split("<")[0].strip().lower()


def test_planning_needs_no_optional_package_and_each_has_an_extra() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    base = {_name(r) for r in project["dependencies"]}
    assert not base & set(OPTIONAL)
    extras = {k: {_name(r) for r in v} for k, v in project["optional-dependencies"].items()}
    assert "matplotlib" in extras["plot"] and "ezdxf" in extras["dxf"] and "distributed" in extras["dask"]
    assert "selenium" in extras["preview"]
    assert {"matplotlib", "ipykernel", "nbclient", "nbformat"} <= extras["notebooks"]


def test_a_plan_with_every_planning_output_imports_no_optional_package(tmp_path: Path) -> None:
    prog = ROOT / "problems" / "siemens" / "ex02_square_g450.mpf"
    outs = [f"--{k}={tmp_path / ('p.' + k)}" for k in ("json", "gcode", "svg", "html", "csv")]
    code = (
        "import sys\nfrom trcopt.cli import main\n"
        f"status = main(['plan', {str(prog)!r}, '-q', *{outs!r}])\n"
        f"print(status, [m for m in {OPTIONAL!r} if m in sys.modules])\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert done.stdout.strip().splitlines()[-1] == "0 []", done.stderr
