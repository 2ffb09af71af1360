"""The plan JSON Schema (trcopt/io/plan.schema.json) against what the planner really writes.

Every golden problem (``problems/<dialect>/<name>.expected.json`` beside its program, found the way
``tests/test_golden_problems.py`` finds them) is planned with timing and its ``to_json()`` must
validate, as must the serialised file; a few are planned without timing (the untimed branch),
one with ``corners="arc"``, the toolholder programs and an RS274 program (linuxcnc profile).
Negative documents must fail with ``TrcoptError`` code ``SCHEMA``.
"""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import jsonschema
import pytest
from test_golden_problems import CASES, IDS, PROBLEMS, _program  # the golden suite, found one way

from trcopt.errors import TrcoptError
from trcopt.io import PLAN_SCHEMA, dumps_plan
from trcopt.io.schema import plan_schema, validate_plan
from trcopt.pipeline import PlanOptions, plan_file

UNTIMED = ["siemens/ex02_square_g450", "siemens/ex06_bottleneck_cdof", "heidenhain/h07_appr_dep_lct",
           "siemens/ex12a_sar_circle_radius_negative"]
TOOLHOLDER = sorted((PROBLEMS / "toolholder").glob("*.mpf"))


def _valid(doc: dict) -> None:
    validate_plan(doc)
    # the file a user reads: serialised by the writer, parsed back
    validate_plan(json.loads(dumps_plan(doc)))


def test_schema_is_a_valid_draft_2020_12_schema() -> None:
    schema = plan_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["$id"] == PLAN_SCHEMA == "trcopt.plan/1"
    assert schema["properties"]["schema"]["const"] == PLAN_SCHEMA
    assert schema["required"] == [
        "schema", "program", "dialect", "units", "ok", "diagnostics", "programmed", "toolpath", "timing"
    ]
    schema["title"] = "changed"
    assert plan_schema()["title"] != "changed"  # a fresh copy every call


def test_suite_is_found() -> None:
    assert len(CASES) >= 50
    assert {c.parent.name for c in CASES} >= {"siemens", "heidenhain"}


@pytest.mark.parametrize("stem", CASES, ids=IDS)
def test_golden_problem_plan_json_validates(stem: Path) -> None:
    expected = json.loads(stem.with_suffix(".expected.json").read_text())
    result = plan_file(_program(stem), PlanOptions(**expected.get("options", {})))
    doc = result.to_json()
    _valid(doc)
    assert doc["ok"] is expected["ok"]
    if doc["toolpath"]:
        assert doc["timing"] is not None
        assert all(s["t_start_s"] is not None for s in doc["toolpath"])


@pytest.mark.parametrize("name", UNTIMED)
def test_plan_without_timing_validates(name: str) -> None:
    doc = plan_file(_program(PROBLEMS / name), PlanOptions(timing=False)).to_json()
    assert doc["timing"] is None
    _valid(doc)


def test_corner_blends_validate() -> None:
    result = plan_file(PROBLEMS / "corners" / "corner_30deg.mpf", PlanOptions(corners="arc", tolerance_mm=0.01))
    doc = result.to_json()
    _valid(doc)
    corners = doc["corners"]
    assert corners["mode"] == "arc" and corners["blended"] == corners["arc"] >= 1
    assert corners["max_deviation_mm"] <= 0.01 + 1e-6


@pytest.mark.parametrize("program", TOOLHOLDER, ids=[p.name for p in TOOLHOLDER])
def test_toolholder_programs_validate(program: Path) -> None:
    doc = plan_file(program).to_json()
    _valid(doc)
    assert "toolholder" in doc


def test_rs274_program_validates(tmp_path: Path) -> None:
    prog = tmp_path / "square.ngc"
    prog.write_text(
        "(square, G41.1 with a 10 mm cutter)\nG21 G17 G90\nG0 X-20 Y-20\nG41.1 D10 G1 X0 Y0 F600\n"
        "G1 Y40\nX60\nY0\nX0\nG40 G0 X-20 Y-20\nM2\n"
    )
    doc = plan_file(prog).to_json()
    _valid(doc)
    assert doc["dialect"] == "rs274" and doc["profile"] == "linuxcnc" and doc["ok"] is True


# -- negative documents ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def good() -> dict:
    doc = plan_file(PROBLEMS / "siemens" / "ex02_square_g450.mpf").to_json()
    validate_plan(doc)
    return json.loads(dumps_plan(doc))


def _mutations() -> dict:
    def seg(k: int, key: str, value: object):
        return lambda d: d["toolpath"][k].__setitem__(key, value)

    return {
        "wrong kind": seg(2, "kind", "spline"),
        "wrong role": seg(2, "role", "lead"),
        "wrong plane": seg(2, "plane", "XY"),
        "wrong side": seg(2, "side", "G41"),
        "2-vector": seg(2, "start", [-5.0, 0.0]),
        "coordinate as string": seg(2, "end", [-5.0, "40", 0.0]),
        "negative radius": seg(2, "radius", -5.0),
        "line with a centre": seg(2, "center", [0.0, 0.0, 0.0]),
        "arc without centre": seg(2, "kind", "arc"),
        "rapid with a feed": seg(0, "feed_mm_min", 600.0),
        "side off with a radius": seg(0, "radius", 5.0),
        "timed plan, untimed segment": seg(3, "t_end_s", None),
        "missing toolpath": lambda d: d.pop("toolpath"),
        "missing segment key": lambda d: d["toolpath"][1].pop("feed_mm_min"),
        "missing diagnostic key": lambda d: d["diagnostics"].append(
            {"severity": "warning", "code": "10763", "alarm": 10763, "message": "m", "line": 6, "column": 1}
        ),
        "bad severity": lambda d: d["diagnostics"].append(
            {"severity": "fatal", "code": "X", "alarm": None, "message": "", "line": 1, "column": 1, "block": None}
        ),
        "alarm with a non-numeric code": lambda d: d["diagnostics"].append(
            {"severity": "warning", "code": "W", "alarm": 10763, "message": "", "line": 1, "column": 1, "block": None}
        ),
        "ok false without an error": lambda d: d.__setitem__("ok", False),
        "ok true with an error": lambda d: d["diagnostics"].append(
            {"severity": "error", "code": "10751", "alarm": 10751, "message": "", "line": 1, "column": 1,
             "block": "N10"}
        ),
        "ok as string": lambda d: d.__setitem__("ok", "true"),
        "other schema": lambda d: d.__setitem__("schema", "trcopt.plan/2"),
        "other units": lambda d: d.__setitem__("units", "inch"),
        "dialect not a name": lambda d: d.__setitem__("dialect", "Fanuc 0i"),
        "NaN written as a string": lambda d: d["timing"].__setitem__("duration_s", "NaN"),
        "Infinity written as a string": seg(1, "t_end_s", "Infinity"),
        "NaN number": lambda d: d["timing"].__setitem__("duration_s", math.nan),
        "infinite coordinate": seg(1, "end", [-5.0, math.inf, 0.0]),
        "timing without machine": lambda d: d["timing"].pop("machine"),
        "verification ok as number": lambda d: d["verification"].__setitem__("ok", 1),
        "profile not a name": lambda d: d.__setitem__("profile", "Fanuc 0i"),
        "corners without a strategy name": lambda d: d.__setitem__(
            "corners", {"mode": "", "tolerance_mm": 0.01, "blended": 0, "quintic": 0, "arc": 0,
                        "max_deviation_mm": 0.0}
        ),
    }


MUTATIONS = _mutations()


@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_invalid_document_is_rejected(good: dict, name: str) -> None:
    doc = copy.deepcopy(good)
    MUTATIONS[name](doc)
    with pytest.raises(TrcoptError) as info:
        validate_plan(doc)
    assert info.value.code == "SCHEMA"
    assert str(info.value)


def test_error_message_names_the_location(good: dict) -> None:
    doc = copy.deepcopy(good)
    doc["toolpath"][2]["kind"] = "spline"
    with pytest.raises(TrcoptError, match=r"toolpath\[2\]\.kind: 'spline' is not one of"):
        validate_plan(doc)
    doc = copy.deepcopy(good)
    doc["timing"]["duration_s"] = math.inf
    with pytest.raises(TrcoptError, match=r"non-finite number at timing\.duration_s"):
        validate_plan(doc)


def test_extension_keys_are_allowed(good: dict) -> None:
    doc = copy.deepcopy(good)
    doc["future_key"] = {"anything": [1, 2, 3]}
    doc["toolpath"][0]["future_segment_key"] = True
    doc["timing"]["future_timing_key"] = "x"
    doc["verification"]["future"] = None
    validate_plan(doc)
    for key in ("profile", "verification"):  # written by the pipeline, not part of the core contract
        doc.pop(key)
    validate_plan(doc)
