"""The readers pause the cyclic garbage collector while reading and restore it as it was."""

from __future__ import annotations

import gc

import pytest

from trcopt.nc.collector import collector_paused


def test_the_collector_is_off_inside_and_restored_after_also_on_an_error() -> None:
    assert gc.isenabled()
    with collector_paused():
        assert not gc.isenabled()
    assert gc.isenabled()
    with pytest.raises(ValueError), collector_paused():
        raise ValueError("a reader bug")
    assert gc.isenabled()


def test_a_collector_switched_off_by_the_caller_stays_off() -> None:
    gc.disable()
    try:
        with collector_paused():
            assert not gc.isenabled()
        assert not gc.isenabled()
    finally:
        gc.enable()


@pytest.mark.parametrize(
    ("dialect", "text"),
    [("rs274", "G21 G17 G90\nG0 X0 Y0\nG1 X10 F600\nM2\n"), ("siemens", "N10 G0 X0 Y0\nN20 G1 X10 F600\nN30 M30\n")],
)
def test_reading_a_program_leaves_the_collector_on(dialect: str, text: str) -> None:
    from trcopt.pipeline import PlanOptions, plan

    assert plan(text, file="p", options=PlanOptions(dialect=dialect, timing=False)).ok
    assert gc.isenabled()
