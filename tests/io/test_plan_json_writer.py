"""Plan JSON (design.md §3.1): contract keys and order, ok semantics, extra keys, no NaN."""

from __future__ import annotations

import json
import math

import pytest

from trcopt.errors import Diagnostic, Severity, SourceSpan, TrcoptError
from trcopt.geometry import Arc, Line, Plane
from trcopt.io.plan_json import CONTRACT_KEYS, PlanJsonError, dumps_plan, plan_json, write_plan_json
from trcopt.modes import Side
from trcopt.path import Role, Segment

SPAN = SourceSpan("problems/siemens/seed_g461.mpf", 6, 1, "N60")
WARN = Diagnostic(Severity.WARNING, "10763", "path shortened", SPAN, 10763)
ERR = Diagnostic(Severity.ERROR, "10751", "collision", SPAN, 10751)


def toolpath():
    return [
        Segment(Line((-5, 0, 0), (-5, 40, 0)), Plane.G17, Role.CONTOUR, SPAN, 10.0, Side.LEFT, 5.0),
        Segment(
            Arc((0, 40), 5.0, math.pi, -math.pi / 2),
            Plane.G17,
            Role.CORNER,
            SPAN,
            10.0,
            Side.LEFT,
            5.0,
        ),
    ]


def make(diags, **kw):
    return plan_json(
        program="problems/siemens/seed_g461.mpf",
        dialect="siemens",
        diagnostics=diags,
        programmed=[Segment(Line((0, 0, 0), (0, 40, 0)), Plane.G17, Role.CONTOUR, SPAN, 10.0)],
        toolpath=toolpath(),
        **kw,
    )


def test_contract_keys_in_order_and_values():
    d = make([WARN])
    assert tuple(d) == CONTRACT_KEYS
    assert d["schema"] == "trcopt.plan/1" and d["units"] == "mm" and d["dialect"] == "siemens"
    assert d["ok"] is True
    assert d["diagnostics"] == [
        {
            "severity": "warning",
            "code": "10763",
            "alarm": 10763,
            "message": "path shortened",
            "line": 6,
            "column": 1,
            "block": "N60",
        }
    ]
    arc = d["toolpath"][1]
    assert arc["kind"] == "arc" and arc["ccw"] is False and arc["center"] == [0.0, 40.0, 0.0]
    assert arc["end"] == [0.0, 45.0, 0.0] and arc["side"] == "left" and arc["feed_mm_min"] == 600.0
    assert d["timing"] is None
    assert d["programmed"][0]["radius"] == 0.0


def test_ok_is_false_iff_an_error_diagnostic():
    assert make([])["ok"] is True
    assert make([WARN, ERR])["ok"] is False
    assert make([ERR.to_json()])["ok"] is False  # dicts accepted too


def test_extra_keys_never_override_the_contract():
    d = make(
        [],
        timing={"duration_s": 1.25, "machine": {}, "samples": None},
        extra={"ok": "nope", "schema": "x", "trcopt_version": "0.1.0"},
    )
    assert d["ok"] is True and d["schema"] == "trcopt.plan/1"
    assert list(d)[-1] == "trcopt_version"
    assert d["timing"]["duration_s"] == 1.25


def test_dumps_round_trips_with_indent_one():
    d = make([WARN])
    text = dumps_plan(d)
    assert text.startswith('{\n "schema": "trcopt.plan/1",\n "program": ')
    assert json.loads(text) == d
    assert text.endswith("}\n")


def test_dumps_refuses_non_finite_numbers_and_names_the_place():
    d = make([])
    d["toolpath"][1]["t_end_s"] = math.nan
    with pytest.raises(PlanJsonError, match=r"toolpath\[1\]\.t_end_s"):
        dumps_plan(d)
    d = make([], timing={"duration_s": math.inf})
    with pytest.raises(TrcoptError, match="timing.duration_s"):
        dumps_plan(d)


def test_numpy_values_are_serialised():
    np = pytest.importorskip("numpy")
    d = make([], timing={"duration_s": np.float32(2.5), "v": np.array([1.0, 2.0])})
    assert json.loads(dumps_plan(d))["timing"] == {"duration_s": 2.5, "v": [1.0, 2.0]}
    d = make([], timing={"v": np.array([1.0, np.nan])})
    with pytest.raises(PlanJsonError, match=r"timing.v\[1\]"):
        dumps_plan(d)


def test_write_plan_json(tmp_path):
    out = write_plan_json(tmp_path / "plan.json", make([ERR]))
    assert json.loads(out.read_text())["ok"] is False
