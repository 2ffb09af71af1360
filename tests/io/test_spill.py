"""``SpilledSegments`` gives back the segments appended to it: equal, in order, by index too."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from trcopt import plan
from trcopt.io.spill import SpilledSegments
from trcopt.pipeline import PlanOptions

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("name", ["siemens/ex05_kont_g451.mpf", "heidenhain/h14_circle_cc.h"])
def test_segments_come_back_equal(name: str) -> None:
    path = ROOT / "problems" / name
    res = plan(path.read_text(), file=str(path), options=PlanOptions())
    segs = res.timing.segments_with_times() if res.timing is not None else res.toolpath
    spill = SpilledSegments()
    try:
        for k in range(0, len(segs), 3):
            spill.append(segs[k : k + 3])
        spill.append([])
        assert len(spill) == len(segs)
        assert list(spill) == list(segs) and list(spill) == list(segs)  # twice: re-iterable
        assert [spill[i] for i in (0, -1, len(segs) // 2)] == [segs[0], segs[-1], segs[len(segs) // 2]]
        assert spill[1:4] == list(segs[1:4])
        with pytest.raises(IndexError):
            spill[len(segs)]
        # the spans' every field survives (machine coordinates, run, end column)
        assert [s.span for s in spill] == [s.span for s in segs]
    finally:
        spill.close()


def test_a_cam_path() -> None:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_cam_scale import contour

    res = plan(contour(500, compensated=True), file="cam.ngc", options=PlanOptions(timing=False, verify=False))
    spill = SpilledSegments()
    spill.append(res.toolpath[:250])
    spill.append(res.toolpath[250:])
    assert list(spill) == res.toolpath
    spill.close()
