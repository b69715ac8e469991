"""The heavy-tail rule's stated false-alarm rate holds for multi-column pairs (review16).

Reference: the binomial law of the false alarms of seeded Gaussian records
(scipy.stats.binom). The rule judges every column of x and y; its threshold
(``heavy_tail_threshold``) sets the family-wise rate over all of them to
``HEAVY_TAIL_ALPHA``, so 400 white Gaussian pairs of a 4-column x and a 1-column y at a
stated 5 % raise about 20 warnings (99.9 % two-sided binomial range [8, 35]). A planted
bug that always shared the rate over 2 series (a single pair's count) made it ~2.5
times that (~48) and escaped every test before this file (R16-S6): the earlier tests
used one column on each side.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from modalinfo.information import resampling
from modalinfo.information.resampling import _heavy_tail_rule


def test_the_rate_is_shared_over_every_column_of_the_pair(monkeypatch):
    alpha, pairs, n = 5e-2, 400, 200
    monkeypatch.setattr(resampling, "HEAVY_TAIL_ALPHA", alpha)
    rng = np.random.default_rng(1616)
    hits = 0
    for _ in range(pairs):
        x = rng.standard_normal((n, 4))
        y = rng.standard_normal(n)
        hits += _heavy_tail_rule(x, y, "t") is not None
    lo, hi = stats.binom.ppf(5e-4, pairs, alpha), stats.binom.isf(5e-4, pairs, alpha)
    assert lo <= hits <= hi, (hits, lo, hi)
