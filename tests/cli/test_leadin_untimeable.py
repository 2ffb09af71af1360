"""``trcopt leadin`` on a SAR example whose optimised (Poly) candidate the timing stage cannot
parameterise: that candidate is not a lead, the others are ranked, the command succeeds."""

from __future__ import annotations

from pathlib import Path

import trcopt.optimize.leads.leadin as leadin_module
from trcopt.cli import main
from trcopt.errors import TimingError

ROOT = Path(__file__).resolve().parents[2]
EX07 = ROOT / "problems" / "siemens" / "ex07_sar_line_g340.mpf"


def test_a_candidate_the_timing_stage_cannot_time_is_left_out(monkeypatch, capsys) -> None:
    real = leadin_module.lead_time
    calls: list[int] = []

    def flaky(elements, *args, **kwargs):
        calls.append(len(elements))
        if len(calls) == 1:  # the first candidate cannot be timed
            raise TimingError("toppra found no parameterisation (test)")
        return real(elements, *args, **kwargs)

    monkeypatch.setattr(leadin_module, "lead_time", flaky)
    assert main(["leadin", str(EX07)]) == 0
    out, err = capsys.readouterr()
    assert "optimal lead" in out and "Traceback" not in err
    assert len(calls) > 1


def test_leadin_plans_the_sar_line_example(capsys) -> None:
    assert main(["leadin", str(EX07)]) == 0
    out, err = capsys.readouterr()
    assert "optimal lead" in out and "G147" in out and "error" not in err
