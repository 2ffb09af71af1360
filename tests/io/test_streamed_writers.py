"""The streamed writers: the plan JSON, the G-code and the feed CSV written in pieces are
byte for byte the text written at once, the fast JSON writer is the standard library's text, and a
staged output is either complete in place or not there at all."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trcopt.io.feed_csv as feed_csv
import trcopt.io.gcode_program as gcode_program
from trcopt import controllers
from trcopt.io.atomic import OutputError, stage_chunks, write_chunks_atomic
from trcopt.io.json_text import encode
from trcopt.io.plan_json import PlanJsonError, _dumps_std, dumps_plan
from trcopt.pipeline import PlanOptions, plan, plan_file

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"
SAMPLES = [
    PROBLEMS / "rs274" / "cam_fusion_drill_profile.ngc",
    PROBLEMS / "heidenhain" / "h01_rectangle_rl.h",
    PROBLEMS / "corners" / "star_g451.mpf",
]


def _contour(n: int) -> str:
    out = ["G21 G17 G90 G40 F6000", "G0 X60 Y0 Z1", "G1 Z0", "G41.1 D2 G1 X40 Y0"]
    out += [f"G1 X{40 * math.cos(2 * math.pi * k / n):.5f} Y{40 * math.sin(2 * math.pi * k / n):.5f}"
            for k in range(1, n + 1)]  # fmt: skip
    return "\n".join([*out, "G40 G1 X60 Y0", "G0 Z5", "M2"]) + "\n"


@pytest.fixture(scope="module")
def results():
    out = [plan_file(p) for p in SAMPLES if p.exists()]
    out.append(plan(_contour(9000), file="contour.ngc"))  # more than one piece of every writer
    return out


def test_plan_json_streamed_is_the_json_written_at_once(results) -> None:
    for r in results:
        whole = _dumps_std(r.to_json(samples="x.csv"))
        assert dumps_plan(r.to_json(samples="x.csv")) == whole
        assert "".join(r.json_chunks(samples="x.csv")) == whole


def test_gcode_streamed_is_the_gcode_written_at_once(results, monkeypatch) -> None:
    for r in results:
        flavor = controllers.get(r.dialect).gcode
        whole = gcode_program.plan_to_gcode(r, flavor=flavor)
        monkeypatch.setattr(gcode_program, "GCODE_CHUNK_SEGMENTS", 7)
        pieces = list(gcode_program.plan_to_gcode_chunks(r, flavor=flavor))
        monkeypatch.undo()
        assert "".join(pieces) == whole
        assert all(pieces)


def test_feed_csv_streamed_is_the_csv_written_at_once(results, monkeypatch) -> None:
    r = results[-1]
    whole = feed_csv.render_feed_csv(r.timing, 0.01)
    monkeypatch.setattr(feed_csv, "CSV_CHUNK_ROWS", 5)
    assert "".join(feed_csv.feed_csv_chunks(r.timing, 0.01)) == whole


values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.text(),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=5), children, max_size=4),
    max_leaves=20,
)


@settings(max_examples=200, deadline=None)
@given(values)
def test_fast_json_text_is_the_standard_librarys(value) -> None:
    assert encode(value, 0) == json.dumps(value, indent=1, allow_nan=False, ensure_ascii=False)


def test_non_finite_numbers_are_named_as_before(results) -> None:
    d = results[0].to_json()
    d["toolpath"][1]["t_end_s"] = math.nan
    with pytest.raises(PlanJsonError, match=r"non-finite number in plan JSON at toolpath\[1\]\.t_end_s"):
        dumps_plan(d)
    d = results[0].to_json()
    d["extra_key"] = {"x": [1.0, np.float64(math.inf)]}
    with pytest.raises(PlanJsonError, match=r"at extra_key\.x\[1\]"):
        dumps_plan(d)


def test_a_streamed_json_with_a_non_finite_number_leaves_no_file(tmp_path, results) -> None:
    r = results[0]
    r.extra["bad"] = math.inf
    try:
        with pytest.raises(PlanJsonError, match="non-finite number in plan JSON at bad"):
            r.write_json(tmp_path / "p.json")
    finally:
        del r.extra["bad"]
    assert os.listdir(tmp_path) == []


def test_staged_outputs_are_all_or_nothing(tmp_path) -> None:
    a = stage_chunks(tmp_path / "a.txt", ["one ", b"two"])
    assert not (tmp_path / "a.txt").exists()
    a.commit()
    assert (tmp_path / "a.txt").read_text() == "one two"
    b = stage_chunks(tmp_path / "b.txt", ["x"])
    b.discard()
    assert sorted(os.listdir(tmp_path)) == ["a.txt"]

    def failing():
        yield "partial"
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_chunks_atomic(tmp_path / "a.txt", failing())
    assert (tmp_path / "a.txt").read_text() == "one two" and sorted(os.listdir(tmp_path)) == ["a.txt"]
    with pytest.raises(OutputError):
        write_chunks_atomic(tmp_path / "missing" / "c.txt", ["x"])


def test_json_written_streamed_equals_the_json_text(tmp_path, results) -> None:
    r = results[-1]
    path = r.write_json(tmp_path / "p.json", samples="p.csv")
    assert path.read_text(encoding="utf-8") == dumps_plan(r.to_json(samples="p.csv"))


def test_plan_options_default_still_plans() -> None:
    assert plan(_contour(8), options=PlanOptions(timing=False)).ok
