"""Jerk-limited feed with ``engine="fir"``: the filtered acceleration-limited profile.

Validity on every benchmark family (B1–B9 of ``benchmarks/timing_cases.py``), the cycle time against
the NLP on cases where the measured gap is small, the moving-average filter itself, the engine
option and the fallback to the NLP.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from trcopt.timing import time_parameterize
from trcopt.timing.doubles import double_s_time
from trcopt.timing.jerk import jerk_limited
from trcopt.timing.jerk_fir import SOLVER
from trcopt.timing.jerk_fir_profile import Pieces, box_filter, filter_groups

ROOT = Path(__file__).resolve().parents[2]


def _cases():
    name = "timing_cases_for_fir_tests"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / "timing_cases.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


TC = _cases()
CASES = {f"{fam} {case}": path for fam, case, path, _ in TC.families()}
MACHINES = {"iso": TC.ISO, "aniso": TC.ANISO}

# one case per family (B9: the 50-segment program), both machines on the curved ones
FAMILY_CASES = [
    ("B1 line 30deg L=2.0", "aniso"),
    ("B2 R=5.0 F=80.0", "iso"),
    ("B2 R=5.0 F=80.0", "aniso"),
    ("B3 R=1.0 F=250", "iso"),
    ("B4 circle R=10 F=250", "aniso"),
    ("B5 helix R=10 pitch 2 x3", "iso"),
    ("B6 G41 outside contour F=250.0", "iso"),
    ("B7 square 40 sharp", "iso"),
    ("B8 square blend d=0.05", "iso"),
    ("B9 random 50 (LP subsample)", "iso"),
    ("B9 random 50 (LP subsample)", "aniso"),
]


@pytest.mark.parametrize(("case", "limits"), FAMILY_CASES)
def test_fir_profile_keeps_every_limit_on_every_family(case, limits):
    path, machine = CASES[case], MACHINES[limits]
    base = time_parameterize(path, machine)
    traj = jerk_limited(path, machine, base=base, engine="fir")
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, rep
    assert max(rep.jerk_ratio) <= 1.0 + 1e-6  # the engine's own check is stricter than the acceptance
    assert max(rep.v_ratio) <= 1.0 + 1e-6 and max(rep.a_ratio) <= 1.0 + 1e-6
    assert traj.duration >= base.duration
    solvers = {sol.solver for sol in traj.solutions}
    assert "ipopt" not in solvers  # every curved section of the benchmark is made valid without the NLP
    if not case.startswith(("B1", "B7")):
        assert SOLVER in solvers


@pytest.mark.parametrize(
    ("case", "limits", "bound"),
    [
        # measured ratios T_fir/T_nlp (benchmarks/JERK.md, "FIR engine"): 1.0009, 1.0012, 1.0065, 1.0122
        ("B2 R=50.0 F=150.0", "iso", 1.002),
        ("B4 circle R=10 F=50", "iso", 1.002),
        ("B3 R=50.0 F=250", "iso", 1.008),
        ("B8 square blend d=0.05", "iso", 1.015),
    ],
)
def test_fir_cycle_time_against_the_nlp(case, limits, bound):
    path, machine = CASES[case], MACHINES[limits]
    base = time_parameterize(path, machine)
    fir = jerk_limited(path, machine, base=base, engine="fir")
    nlp = jerk_limited(path, machine, base=base)
    assert fir.duration <= bound * nlp.duration
    assert fir.duration >= 0.999 * nlp.duration  # the NLP is the reference optimum


def test_fir_on_a_long_line_is_the_double_s():
    # closed_form=False sends the line to the FIR engine: T = a/J gives the double-S (T_acc + T)
    path = CASES["B1 line 0deg L=50.0"]
    traj = jerk_limited(path, TC.ISO, closed_form=False, engine="fir")
    assert traj.solutions[0].solver == SOLVER
    exact = double_s_time(50.0, 200.0, 2000.0, 5e4)
    assert traj.duration == pytest.approx(exact, rel=2e-3)  # the bounds use 0.999 of the limits
    assert traj.duration >= exact
    assert traj.check_limits(dt=1e-4).ok


def test_box_filter_of_a_trapezoid_is_the_double_s():
    # trapezoid 0 → 100 mm/s at 1000 mm/s², cruise 0.5 s, back to rest; T = 0.02 s (J = 5e4)
    a, v, cruise, T = 1000.0, 100.0, 0.5, 0.02
    ramp = v * v / (2 * a)
    s = np.array([0.0, ramp, ramp + v * cruise, 2 * ramp + v * cruise])
    p = Pieces(s, np.array([0.0, v, v, 0.0]), np.array([a, 0.0, -a]))
    t0, s0, v0, a0, j, h = box_filter(p, T)
    assert float(h.sum()) == pytest.approx(p.duration + T, rel=1e-12)
    assert v0[0] == 0.0 and a0[0] == 0.0
    assert np.abs(j).max() == pytest.approx(a / T)
    assert np.abs(a0).max() <= a * (1 + 1e-12)
    # the end state: the full length at rest
    end = s0[-1] + v0[-1] * h[-1] + a0[-1] * h[-1] ** 2 / 2 + j[-1] * h[-1] ** 3 / 6
    assert end == pytest.approx(s[-1], abs=1e-9)
    assert v0[-1] + a0[-1] * h[-1] + j[-1] * h[-1] ** 2 / 2 == pytest.approx(0.0, abs=1e-9)
    assert float(h.sum()) == pytest.approx(double_s_time(float(s[-1]), v, a, a / T), rel=1e-9)


def test_groups_with_their_own_lengths_join_on_the_flat_between():
    # up to 100 mm/s (filtered with T = 0.04), a long flat, down to rest (T = 0.01)
    a = 1000.0
    ramp = 100.0**2 / (2 * a)
    s = np.array([0.0, ramp, ramp + 20.0, 2 * ramp + 20.0])
    p = Pieces(s, np.array([0.0, 100.0, 100.0, 0.0]), np.array([a, 0.0, -a]))
    t0, s0, v0, a0, j, h = filter_groups(p, [(0, 0), (2, 2)], [0.04, 0.01])
    # continuous in s, v and a from interval to interval; the total length is kept
    s1 = s0 + v0 * h + a0 * h**2 / 2 + j * h**3 / 6
    v1 = v0 + a0 * h + j * h**2 / 2
    a1 = a0 + j * h
    assert np.allclose(s1[:-1], s0[1:], atol=1e-9)
    assert np.allclose(v1[:-1], v0[1:], atol=1e-9)
    assert np.allclose(a1[:-1], a0[1:], atol=1e-9)
    assert s1[-1] == pytest.approx(s[-1], abs=1e-9)
    # each ramp takes its own filter length: duration = unfiltered + (T₁ + T₂)/2
    assert float(h.sum()) == pytest.approx(p.duration + 0.5 * (0.04 + 0.01), rel=1e-9)
    assert np.abs(j).max() == pytest.approx(a / 0.01)


def test_fir_falls_back_to_the_nlp_where_it_has_no_valid_profile(monkeypatch):
    import trcopt.timing.jerk as jerk_module

    path = CASES["B2 R=5.0 F=80.0"]
    base = time_parameterize(path, TC.ISO)
    monkeypatch.setattr(jerk_module, "fir_section", lambda *args, **kwargs: None)
    traj = jerk_limited(path, TC.ISO, base=base, engine="fir")
    assert [sol.solver for sol in traj.solutions] == ["ipopt"]
    assert traj.duration == pytest.approx(jerk_limited(path, TC.ISO, base=base).duration, rel=1e-9)


def test_fir_sections_in_the_plan_json_and_unknown_engines():
    path = CASES["B2 R=50.0 F=150.0"]
    traj = jerk_limited(path, TC.ISO, engine="fir")
    doc = traj.to_json()
    assert [sec["engine"] for sec in doc["sections"]] == [SOLVER]
    assert doc["limits_ok"] is True
    assert traj.knot_s.shape == (2,)  # the line↔arc knots are found in the FIR profile too
    cap = math.sqrt(5e4 * 1e-3 * 50.0)
    assert np.all(traj.knot_v <= cap * (1 + 1e-6))
    with pytest.raises(ValueError, match="engine"):
        jerk_limited(path, TC.ISO, engine="toppra")


def test_the_engine_through_the_command_and_the_api(tmp_path) -> None:
    import json
    from pathlib import Path

    from trcopt.cli import main
    from trcopt.errors import TrcoptError
    from trcopt.pipeline import PlanOptions

    program = Path(__file__).resolve().parents[2] / "problems" / "siemens" / "ex02_square_g450.mpf"
    out = {e: tmp_path / f"{e}.json" for e in ("nlp", "fir")}
    for engine, path in out.items():
        assert main(["plan", str(program), "--jerk", "--jerk-engine", engine, "--json", str(path), "-q"]) == 0
    plans = {e: json.loads(p.read_text()) for e, p in out.items()}
    engines = {e: {s.get("engine") for s in p["timing"]["sections"]} for e, p in plans.items()}
    assert "fir" in engines["fir"] and "fir" not in engines["nlp"]
    # both checked against every limit (the NLP is a local optimum: on this program FIR is faster)
    assert plans["fir"]["timing"]["limits_ok"] and plans["nlp"]["timing"]["limits_ok"]
    with pytest.raises(TrcoptError, match="jerk-engine"):
        PlanOptions(jerk=True, jerk_engine="fast")
