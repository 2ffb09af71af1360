"""The backward-pass bound of curved intervals from the ± row pairs equals the one from every pair of rows."""

from __future__ import annotations

import numpy as np

from trcopt.timing.reach import interval_rows, pass_coefficients


def test_paired_rows_give_the_bound_of_all_row_pairs():
    rng = np.random.default_rng(11)
    n = 5000
    # arc-like derivatives: unit tangents and normals of random size, some axes not moving
    ang = rng.uniform(0, 2 * np.pi, (n, 2))
    d1l = np.column_stack((np.cos(ang[:, 0]), np.sin(ang[:, 0]), rng.choice([0.0, 0.1], n)))
    d1r = np.column_stack((np.cos(ang[:, 1]), np.sin(ang[:, 1]), d1l[:, 2]))
    kappa = rng.uniform(0.01, 5.0, (n, 1))
    d2l = kappa * np.column_stack((-d1l[:, 1], d1l[:, 0], np.zeros(n)))
    d2r = kappa * np.column_stack((-d1r[:, 1], d1r[:, 0], np.zeros(n)))
    d1l[: n // 10, 0] = 0.0  # an axis standing still at the interval's start
    delta = rng.uniform(1e-4, 0.5, n)
    amax = np.tile([2000.0, 1500.0, 1000.0], (n, 1))
    alpha, beta, gamma = interval_rows(d1l, d2l, d1r, d2r, delta, amax)
    curved = np.ones(n, dtype=bool)
    q, *_ = pass_coefficients(alpha, beta, gamma, curved)
    # the same rows in another column order: not in ± pairs, every pair of rows is formed
    perm = rng.permutation(12)
    assert not np.array_equal(beta[:, perm][:, 3:6], -beta[:, perm][:, 0:3])
    q_all, *_ = pass_coefficients(alpha[:, perm], beta[:, perm], gamma[:, perm], curved)
    np.testing.assert_array_equal(q, q_all)
    assert np.isfinite(q).mean() > 0.5
