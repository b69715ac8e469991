"""The histogram TE's resolution rule: one continuous column of the pair is enough (review29).

Round 29 T1 (modalinfo/information/conditional.py:549, ``_judged_histogram_why``): the
rule applies "where a column of x or y is continuous (an all-discrete pair's table loses
nothing to bins)". Planted as "where every column is continuous", it passed every test,
whose source and target were both continuous. A source with four levels driving a
continuous target is such a pair: the target's bins still cut a continuous variable.
References, from outside the code: the rule as stated (at least 8 bins per axis), with
n and d counted by hand (n = T - max(lag, history) = 1998, d = 1 + 1 + history = 4),
numpy's ``np.unique`` (the source takes 4 values).
"""

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, transfer_entropy


def test_a_discrete_source_and_a_continuous_target_are_judged():
    rng = np.random.default_rng(29)
    n = 2000
    src = rng.integers(0, 4, n).astype(float)  # four levels: a discrete column
    tgt = np.zeros(n)
    noise = rng.standard_normal(n)
    for t in range(2, n):
        tgt[t] = 0.4 * tgt[t - 1] + 0.8 * src[t - 2] + noise[t]
    assert np.unique(src).size == 4 and np.unique(tgt[2:]).size == n - 2
    with pytest.warns(BiasRuleWarning) as record:
        transfer_entropy(src, tgt, lag=2, history=2, method="histogram")
    assert len(record) == 1
    text = str(record[0].message)
    assert "over 4 columns (n = 1998)" in text
    assert "resolution rule of at least 8 bins per axis" in text
