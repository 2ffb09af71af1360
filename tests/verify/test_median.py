"""The grids' median equals ``np.median`` (it only avoids the ``numpy.ma`` import)."""

import numpy as np
import pytest

from trcopt.verify.index import median


@pytest.mark.parametrize("n", [1, 2, 3, 4, 7, 10, 101, 1000])
def test_median_equals_numpy(n):
    rng = np.random.default_rng(n)
    for scale in (1.0, 1e-9, 1e9):
        values = rng.random(n) * scale
        expected = float(np.median(values))
        assert median(values) == expected
        copy = values.copy()
        assert median(copy, overwrite=True) == expected
        assert sorted(copy) == sorted(values)  # only reordered


def test_median_of_repeated_values():
    assert median(np.array([2.0, 2.0, 5.0, 1.0])) == 2.0
