"""The batched line–line distance of the no-gouge check equals the scalar exact distance."""

from __future__ import annotations

import numpy as np

from trcopt.geometry import Line
from trcopt.verify.model import element_distance, line_pair_distances


def test_batched_distances_match_the_exact_pairwise_distance():
    rng = np.random.default_rng(7)
    n = 3000
    p0, p1 = rng.uniform(-5, 5, (n, 2)), rng.uniform(-5, 5, (n, 2))
    q0 = rng.uniform(-5, 5, (n, 2))
    q1 = q0 + rng.uniform(-3, 3, (n, 2))
    # special cases: shared end points, a T joint, collinear overlap, parallel at a distance
    p0[0], p1[0], q0[0], q1[0] = (0, 0), (1, 0), (1, 0), (2, 1)
    p0[1], p1[1], q0[1], q1[1] = (0, 0), (2, 0), (1, 0), (1, 3)
    p0[2], p1[2], q0[2], q1[2] = (0, 0), (2, 0), (1, 0), (3, 0)
    p0[3], p1[3], q0[3], q1[3] = (0, 0), (2, 0), (0, 1), (2, 1)
    got = line_pair_distances(p0, p1, q0, q1)
    want = np.array(
        [
            element_distance(Line((*a, 0.0), (*b, 0.0)), Line((*c, 0.0), (*d, 0.0)))[0]
            for a, b, c, d in zip(p0, p1, q0, q1, strict=True)
        ]
    )
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    assert got[0] == 0.0 and got[1] == 0.0 and got[2] == 0.0 and got[3] == 1.0
    assert (want == 0.0).sum() > 100  # crossings are among the random pairs
