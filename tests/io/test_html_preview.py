"""The HTML preview without a browser: the embedded data, self-containedness, escaping, the CLI.

What the page does with the data (views, hover, links) is tested in a real browser in
``test_html_preview_browser.py``.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import trcopt.io
from trcopt.cli import main
from trcopt.io.atomic import OutputError
from trcopt.io.html_preview import PREVIEW_SCHEMA, preview_data, render_html, write_html
from trcopt.pipeline import PlanOptions, plan, plan_file

ROOT = Path(__file__).resolve().parents[2]
BOTTLENECK = ROOT / "problems" / "siemens" / "ex06_bottleneck_cdon.mpf"
TOO_LARGE = ROOT / "problems" / "heidenhain" / "h02_pocket_r16_too_large.h"
DATA = re.compile(r'<script type="application/json" id="plan-data">(.*?)</script>', re.S)


def embedded(page: str) -> dict:
    found = DATA.findall(page)
    assert len(found) == 1
    return json.loads(found[0])


def page_of(result, **kw) -> str:
    return render_html(
        result.programmed, result.toolpath, result.diagnostics, result.timing, source=result.source, **kw
    )


@pytest.fixture(scope="module")
def bottleneck():
    return plan_file(BOTTLENECK, PlanOptions())


def test_the_page_embeds_both_paths_with_their_blocks_and_feeds(bottleneck) -> None:
    data = embedded(page_of(bottleneck, title="ex06"))
    assert data["schema"] == PREVIEW_SCHEMA and data["units"] == "mm" and data["title"] == "ex06"
    assert len(data["programmed"]) == len(bottleneck.programmed) == 8
    assert len(data["toolpath"]) == len(bottleneck.toolpath) == 7
    first, contour = data["toolpath"][0], data["toolpath"][2]
    assert first["rapid"] and first["feed"] is None and first["p"][0] == [0.0, 0.0, 0.0]
    assert contour["block"] == "N30" and contour["line"] == 5 and contour["p"] == [[0.0, 5.0, 0.0], [20.0, 5.0, 0.0]]
    assert contour["feed"] == pytest.approx(bottleneck.toolpath[2].feed_mm_s * 60.0)
    assert data["lines"]["5"].startswith("N30")  # the source line a hover shows
    # the corner arc is drawn through points on its circle (every 5° at most)
    arc = bottleneck.toolpath[3].geometry
    pts = data["toolpath"][3]["p"]
    assert len(pts) >= 3
    for p in pts:
        assert ((p[0] - arc.center[0]) ** 2 + (p[1] - arc.center[1]) ** 2) ** 0.5 == pytest.approx(arc.radius, abs=1e-3)


def test_omitted_blocks_are_marked_on_their_programmed_block(bottleneck) -> None:
    data = embedded(page_of(bottleneck))
    marks = data["diagnostics"]
    assert [(d["code"], d["block"], d["kind"], d["path"]) for d in marks] == [
        ("10763", "N50", "omitted", "programmed"),
        ("10763", "N60", "omitted", "programmed"),
    ]
    # N50 runs (20,-20) → (26,-20): the mark sits halfway
    assert marks[0]["at"] == [23.0, -20.0, 0.0]
    assert data["programmed"][marks[0]["index"]]["block"] == "N50"


def test_an_alarm_that_stopped_the_program_is_marked_where_the_path_ends() -> None:
    result = plan_file(TOO_LARGE, PlanOptions(timing=False))
    assert not result.ok
    data = embedded(page_of(result))
    (stop,) = data["diagnostics"]
    assert stop["severity"] == "error" and stop["kind"] == "stop"
    assert stop["at"] == data["toolpath"][-1]["p"][-1] == [50.0, 26.0, 0.0]
    assert data["timing"] is None and data["ok"] is False


def test_speed_along_the_path_and_the_plot_samples(bottleneck) -> None:
    timing = embedded(page_of(bottleneck))["timing"]
    assert timing["duration_s"] == pytest.approx(bottleneck.timing.duration, abs=1e-4)
    n = len(timing["t"])
    assert 100 < n <= 2000 and len(timing["v"]) == len(timing["seg"]) == len(timing["xyz"]) == n
    assert timing["t"] == sorted(timing["t"]) and timing["t"][-1] == pytest.approx(bottleneck.timing.duration, abs=1e-3)
    assert len(timing["t0"]) == len(timing["t1"]) == len(timing["along"]) == 7
    # the colour scale spans the cutting moves only: the rapid (N10) is much faster
    cutting_feed = max(s.feed_mm_s for s in bottleneck.toolpath if s.feed_mm_s) * 60.0
    assert timing["vmax"] <= cutting_feed * 1.001 < max(timing["v"])
    # the speed along a segment starts and ends at the timed speed of its ends (exact stops: 0)
    along = timing["along"][2]
    assert along[0][:3] == [0.0, 5.0, 0.0] and along[-1][:3] == [20.0, 5.0, 0.0]
    assert max(p[3] for p in along) == pytest.approx(cutting_feed, rel=1e-3)


def test_the_page_is_self_contained() -> None:
    result = plan("N10 G1 X10 Y0 F100\nN20 X20 Y5\nM30\n", file="p.mpf")
    page = page_of(result)
    assert "<script src" not in page and "<link rel=\"stylesheet\"" not in page and "@import" not in page
    # the only URL is the SVG namespace, which is a name, not a download
    assert set(re.findall(r"https?://[^\s\"'<>)]+", page)) == {"http://www.w3.org/2000/svg"}
    assert "function render()" in page and "#toolbar" in page  # script and style inlined


def test_program_text_cannot_end_the_data_block() -> None:
    source = "N10 G1 X10 Y0 F100 ; </script><script>alert(1)</script> \u2028\nN20 X20\nM30\n"
    result = plan(source, file="p.mpf", options=PlanOptions(timing=False))
    page = page_of(result, title="</title><b>x")
    assert page.count("</script>") == 2  # the data block's and the code's
    assert "<title>&lt;/title&gt;&lt;b&gt;x" in page
    data = embedded(page)
    assert data["lines"]["1"] == source.splitlines()[0].strip()
    assert data["title"] == "</title><b>x"


def test_an_empty_plan_still_renders() -> None:
    data = embedded(render_html([], []))
    assert data["programmed"] == data["toolpath"] == data["diagnostics"] == [] and data["timing"] is None


def test_write_html_is_atomic(tmp_path: Path, bottleneck) -> None:
    out = write_html(tmp_path / "p.html", bottleneck.programmed, bottleneck.toolpath, title="t")
    assert embedded(out.read_text(encoding="utf-8"))["title"] == "t"
    with pytest.raises(OutputError):
        write_html(tmp_path / "missing" / "p.html", bottleneck.programmed, bottleneck.toolpath)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.html"]


def test_preview_is_part_of_the_io_api() -> None:
    assert trcopt.io.render_html is render_html and "render_html" in trcopt.io.__all__
    assert "write_html" in trcopt.io.__all__ and trcopt.io.write_html is write_html
    assert preview_data([], [])["schema"] == PREVIEW_SCHEMA


def test_cli_plan_writes_the_preview(tmp_path: Path, capsys) -> None:
    out = tmp_path / "sub" / "p.html"
    assert main(["plan", str(BOTTLENECK), "-q", "--html", str(out)]) == 0
    data = embedded(out.read_text(encoding="utf-8"))
    assert data["title"] == str(BOTTLENECK) and "cycle time" in data["summary"]
    assert len(data["toolpath"]) == 7 and data["timing"] is not None
    # an output path that is a folder is refused before the work starts
    capsys.readouterr()
    assert main(["plan", str(BOTTLENECK), "-q", "--html", str(tmp_path)]) == 2
    assert "is a folder" in capsys.readouterr().err
