"""The histogram entropy's wide-bins rule allows for sampling noise at small n (review12).

Reference (outside the code): the law of the data. A normal or a uniform sample has no
heavy tail and no far-apart modes, so a ``BiasRuleWarning`` from the wide-bins rule
(equal-width bins biased high against the Kozachenko-Leonenko estimate) is false. The
rule allows ``WIDE_BINS_NATS + 1 / sqrt(n)`` for the excess's sampling spread (its 90 %
point is 0.07-0.11 nats at n = 30-50 for these laws, measured over 300 seeds). Over 1200
draws (normal and uniform, n = 30 and 50) at most 0.5 % may warn: measured 2 (0.17 %);
with an allowance of ``1 / n`` instead, 21.
"""

from __future__ import annotations

import warnings

import numpy as np

from modalinfo.information.histogram import BiasRuleWarning, histogram_entropy


def test_light_tailed_small_samples_are_rarely_warned():
    warned = 0
    for n in (30, 50):
        for law in ("normal", "uniform"):
            for seed in range(300):
                rng = np.random.default_rng(seed)
                x = rng.standard_normal(n) if law == "normal" else rng.random(n)
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    histogram_entropy(x)
                # the wide-bins rule's warnings (n = 30 is also below the small-sample
                # rule n >= 50 of every entropy estimate, fixes 48-e: not this test's)
                warned += any(issubclass(w.category, BiasRuleWarning)
                              and "equal-width bins" in str(w.message) for w in caught)
    assert warned <= 6, warned
