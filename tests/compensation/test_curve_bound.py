"""The adaptive curve sampler is bounded: an extreme curve raises SamplingError (an alarm with the
block's place in the engine, TRC-CURVE) instead of sampling without end."""

from __future__ import annotations

import math
import time

import pytest

from trcopt.compensation.elements import MIN_OFFSET_RADIUS_MM
from trcopt.geometry.poly import MAX_CURVE_SAMPLES, SamplingError, hermite_curve


def test_a_quintic_with_an_extreme_end_curvature_stops_at_the_sample_budget() -> None:
    start = time.perf_counter()
    with pytest.raises(SamplingError, match="MAX_CURVE_SAMPLES"):
        hermite_curve((0.0, 0.0, 0.0), (5.0, 0.0, 0.0), (5.0, 1.0, 0.0), (0.0, 5.0, 0.0),
                      (0.0, 0.0, 0.0), (1e17, 0.0, 0.0), label="KONTC")
    assert time.perf_counter() - start < 30.0
    assert MAX_CURVE_SAMPLES >= 10_000


def test_a_non_finite_curve_is_refused() -> None:
    with pytest.raises(SamplingError, match="non-finite"):
        hermite_curve((0.0, 0.0, 0.0), (math.inf, 0.0, 0.0), (5.0, 1.0, 0.0), (0.0, 5.0, 0.0))


def test_ordinary_curves_stay_far_below_the_budget() -> None:
    poly = hermite_curve((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (10.0, 10.0, 0.0), (0.0, 10.0, 0.0),
                         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert len(poly.points) < MAX_CURVE_SAMPLES / 10
    assert 0.0 < MIN_OFFSET_RADIUS_MM <= 1e-6
