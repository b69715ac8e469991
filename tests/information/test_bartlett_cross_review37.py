"""``convergence.bartlett_cross_factor`` never narrows an interval (review37, issue 27).

Reference (outside the code under test): the documented clip, ``[1, BARTLETT_CROSS_MAX]``
(the factor only widens the closed form's floor), read on independent white pairs
(numpy draws, seeds 0-9), where Bartlett's full sum equals its floor in expectation and
an unclipped ratio falls below 1 on about half the seeds (all ten above 1 by chance:
about 1e-3).
"""

from __future__ import annotations

import numpy as np

from modalinfo.information.convergence import BARTLETT_CROSS_MAX, bartlett_cross_factor


def test_the_factor_stays_within_its_clip_on_white_pairs():
    got = []
    for seed in range(10):
        rng = np.random.default_rng(seed)
        x, y = rng.standard_normal((2, 2000))
        got.append(bartlett_cross_factor(x, y))
    assert all(1.0 <= g <= BARTLETT_CROSS_MAX for g in got)
