"""``trcopt leadin --svg``: the picture names what it shows (legend, points, axes in mm)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from trcopt.cli import main

ROOT = Path(__file__).resolve().parents[2]
PLATE = ROOT / "problems" / "siemens" / "ex13_cam_plate_leads.mpf"
NS = {"s": "http://www.w3.org/2000/svg"}


def _texts(root: ET.Element, group: str) -> list[str]:
    return [t.text or "" for t in root.findall(f".//s:g[@class='{group}']/s:text", NS)]


def test_leadin_svg_has_labels(tmp_path: Path) -> None:
    out = tmp_path / "lead.svg"
    assert main(["leadin", str(PLATE), "--svg", str(out)]) == 0
    root = ET.fromstring(out.read_bytes())
    assert root.find("s:title", NS).text.startswith("optimal lead-in (green, ")
    legend = _texts(root, "legend")
    for code in ("G147", "G247", "G347"):
        assert any(t.startswith(f"{code} SAR default, DISR ") for t in legend), legend
    assert any("gouges by" in t for t in legend)  # G347 with default parameters cuts into the part
    assert "units: mm (axes and scale bar)" in legend
    assert _texts(root, "labels") == ["start", "P0 start point", "P4 contour start"]
    assert [t.text for t in root.findall(".//s:text[@class='axis-name']", NS)] == ["X [mm]", "Y [mm]"]
    # the three SAR leads are drawn as named overlays, the optimal lead as the tool path
    assert len(root.findall(".//s:g[@class='overlay']", NS)) == 3
    assert root.findall(".//s:g[@class='toolpath']/s:path", NS)


def test_leadout_svg_has_labels(tmp_path: Path) -> None:
    out = tmp_path / "leadout.svg"
    assert main(["leadin", str(PLATE), "--out", "--svg", str(out)]) == 0
    root = ET.fromstring(out.read_bytes())
    assert root.find("s:title", NS).text.startswith("optimal lead-out (green, ")
    assert _texts(root, "labels") == ["start", "end point of the deselection block"]
    # the contour is drawn solid (a feed move), not as a rapid
    assert all(p.get("stroke-dasharray") is None for p in root.findall(".//s:g[@class='programmed']/s:path", NS))
