"""Heidenhain Klartext tool-centre output (``--gcode-flavor klartext``): a Heidenhain plan written
as a conversational program with R0 moves; planned again it gives the same tool-centre path and
the same words (tool calls, M functions) in the same order."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from trcopt import PlanOptions, plan
from trcopt.cli import main
from trcopt.io.gcode import GcodeError
from trcopt.io.gcode_program import kept_words
from trcopt.io.klartext import plan_to_klartext

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"

HELIX = """0 BEGIN PGM HX MM
1 TOOL DEF 1 L+0 R+2
2 TOOL CALL 1 Z S1000
3 L X+0 Y+0 Z+5 R0 FMAX M3
4 L Z-1 R0 F100
5 CC X+10 Y+0
6 C X+20 Y+0 DR- R0 F200 M8
7 CP IPA+180 IZ-1 DR- R0 F200
8 L Z+10 R0 FMAX M9
9 L X+30 R0 FMAX M5
10 END PGM HX MM
"""


def _points(toolpath, n: int = 30) -> np.ndarray:
    out = []
    for s in toolpath:
        g = s.geometry
        out += [s.plane.to_xyz(g.point(g.length * k / n)) for k in range(n + 1)]
    return np.array(out)


def _words(result) -> list[str]:
    blocks = [(m.span.line, m.actions) for m in result.nc.moves]
    blocks += [(span.line, actions) for span, actions in result.nc.extras.get("words", ())]
    return [w for _, a in sorted(blocks, key=lambda b: b[0]) for w in kept_words(a) if not w.startswith("T")]


@pytest.mark.parametrize(
    ("text", "name"),
    [
        (HELIX, "hx.h"),
        ((PROBLEMS / "heidenhain" / "h26_cam_post.h").read_text(), "h26_cam_post.h"),
        ((PROBLEMS / "heidenhain" / "h04_appr_dep_lt.h").read_text(), "h04.h"),
        ((PROBLEMS / "heidenhain" / "h22_frames.h").read_text(), "h22_frames.h"),
    ],
)
def test_klartext_output_replans_to_the_same_tool_centre_path(text: str, name: str, tmp_path: Path) -> None:
    here = tmp_path / name
    here.write_text(text)
    # the folder's tool table (TOOL CALL without TOOL DEF), for both plans
    (tmp_path / "tools.toml").write_text((PROBLEMS / "heidenhain" / "tools.toml").read_text())
    first = plan(text, file=str(here), options=PlanOptions(timing=False))
    assert first.ok
    out = plan_to_klartext(first, decimals=5, program_name=name)
    blocks = out.splitlines()
    assert blocks[0].startswith("0 BEGIN PGM") and re.match(r"\d+ END PGM", blocks[-1])
    assert [int(b.split()[0]) for b in blocks] == list(range(len(blocks)))
    body = [b.split(" ", 1)[1] for b in blocks]
    moves = [b for b in body if b.startswith(("L ", "C ", "CP "))]
    assert moves and all(" R0" in b for b in moves)
    assert not any(re.match(r"(APPR|DEP|LBL|CALL|FN|CYCL DEF|Q\d)", b) for b in body)
    again_path = tmp_path / ("again_" + name)
    again_path.write_text(out)
    again = plan(out, file=str(again_path), options=PlanOptions(timing=False, corners="exact"))
    assert again.ok, [d.format() for d in again.errors]
    a, b = _points(first.toolpath), _points(again.toolpath)
    d = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2))
    assert max(d.min(axis=1).max(), d.min(axis=0).max()) <= 2e-5
    assert again.path_length == pytest.approx(first.path_length, abs=1e-4)
    assert _words(again) == _words(first)


def test_klartext_is_for_heidenhain_programs_only() -> None:
    siemens = plan("N10 G0 X0 Y0\nN20 G1 X10 F100\nM30\n", file="p.mpf", options=PlanOptions(timing=False))
    with pytest.raises(GcodeError, match="Heidenhain programs only"):
        plan_to_klartext(siemens)


def test_an_alarmed_program_ends_with_the_alarm_and_a_stop(tmp_path: Path, capsys) -> None:
    out = tmp_path / "p.h"
    prog = PROBLEMS / "heidenhain" / "h02_pocket_r16_too_large.h"
    assert main(["plan", str(prog), "--no-timing", "-q", "--gcode", str(out), "--gcode-flavor", "klartext"]) == 1
    blocks = out.read_text().splitlines()
    assert "HH-TOOL-RADIUS-TOO-LARGE" in blocks[-4] and blocks[-2].endswith("STOP")
    assert not any(re.search(r"\bM(2|30)\b", b) for b in blocks if not b.split(" ", 1)[1].startswith(";"))


def test_every_klartext_move_that_starts_a_source_element_names_its_line(tmp_path: Path) -> None:
    prog = PROBLEMS / "heidenhain" / "h26_cam_post.h"
    (tmp_path / "tools.toml").write_text((PROBLEMS / "heidenhain" / "tools.toml").read_text())
    here = tmp_path / prog.name
    here.write_text(prog.read_text())
    first = plan(here.read_text(), file=str(here), options=PlanOptions(timing=False))
    out = plan_to_klartext(first, decimals=4, program_name=prog.name)
    source = prog.read_text().splitlines()
    body = [b.split(" ", 1)[1] for b in out.splitlines()]
    moves = [b for b in body if b.startswith(("L ", "C ", "CP ", "TOOL CALL"))]
    named = [re.search(r" ; (\d+) L(\d+) ?(\w*)$", b) for b in moves]
    assert all(named), [b for b, m in zip(moves, named, strict=True) if not m]  # each piece is one element here
    for m in named:
        block, line = m.group(1), int(m.group(2))
        assert source[line - 1].split()[0] == block  # the Klartext block number on that line
    assert "TOOL CALL 3 Z S8000 ; 4 L5" in body
    assert "L Z+50 R0 FMAX M3 ; 5 L6 rapid" in body  # the M function before the comment


def test_a_heidenhain_program_written_to_a_h_file_is_klartext_by_default(tmp_path: Path) -> None:
    heidenhain, siemens = PROBLEMS / "heidenhain" / "h04_appr_dep_lt.h", PROBLEMS / "siemens" / "ex02_square_g450.mpf"
    for prog, out in ((heidenhain, "a.h"), (heidenhain, "a.nc"), (siemens, "b.h")):
        assert main(["plan", str(prog), "--no-timing", "-q", "--gcode", str(tmp_path / out)]) == 0
    assert (tmp_path / "a.h").read_text().startswith("0 BEGIN PGM H04_APPR_DEP_LT MM\n")
    assert (tmp_path / "a.nc").read_text().startswith("; trcopt tool-centre path")  # ISO, as asked by the name
    assert (tmp_path / "b.h").read_text().startswith("; trcopt tool-centre path")  # not a Heidenhain program
    assert main(["plan", str(heidenhain), "--no-timing", "-q", "--gcode", str(tmp_path / "c.h"),
                 "--gcode-flavor", "heidenhain"]) == 0  # fmt: skip
    assert (tmp_path / "c.h").read_text().startswith("; trcopt tool-centre path")  # the flavour given wins
