"""Transfer entropy against Granger, and its variables not aliasing the caller's series.

References, from outside the code: for Gaussian processes the transfer entropy equals
half Granger's log ratio of residual variances (Barnett, Barrett & Seth 2009, PRL 103,
238701), computed here with statsmodels' OLS of the target on its own past without and
with the lagged source; numpy.shares_memory and copies of the inputs taken before the
call, and the lagged columns built by hand with numpy slicing.

Round 25 asserted that the histogram TE gave its documented -28 % to -41 % at history 2
without a word; fixes 45-c (round 44 PART a I32, the lead's decision) makes it warn
there, as the conditional MI of the same columns does (the resolution rule: 5 bins per
axis over 4 columns at n = 3998, below 8), keeping the histogram's value: the test now
asserts the low value AND the one warning.
"""

import warnings

import numpy as np
import pytest
import statsmodels.api as sm

from modalinfo.information import (
    BiasRuleWarning,
    transfer_entropy,
    transfer_entropy_variables,
)


def test_returned_columns_are_new_arrays():
    rng = np.random.default_rng(0)
    src, tgt = rng.standard_normal(200), rng.standard_normal(200)
    keep_src, keep_tgt = src.copy(), tgt.copy()
    for lag, history in [(0, 0), (1, 1), (3, 2)]:
        x, y, z = transfer_entropy_variables(src, tgt, lag=lag, history=history)
        t0 = max(lag, history)
        np.testing.assert_array_equal(x[:, 0], tgt[t0:])
        np.testing.assert_array_equal(y[:, 0], src[t0 - lag: 200 - lag])
        for a in (x, y, z):
            assert not np.shares_memory(a, src) and not np.shares_memory(a, tgt)
            assert a.flags.c_contiguous
            a -= 1.0  # standardising in place must not edit the caller's series
        np.testing.assert_array_equal(src, keep_src)
        np.testing.assert_array_equal(tgt, keep_tgt)


def _var_pair(n: int, c: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """x_t = 0.5 x_{t-1} + e, y_t = 0.4 y_{t-1} + c x_{t-1} + f; 200 frames of burn-in."""
    e = np.random.default_rng(seed).standard_normal((n + 200, 2))
    x, y = np.zeros(n + 200), np.zeros(n + 200)
    for t in range(1, n + 200):
        x[t] = 0.5 * x[t - 1] + e[t, 0]
        y[t] = 0.4 * y[t - 1] + c * x[t - 1] + e[t, 1]
    return x[200:], y[200:]


def _granger(src: np.ndarray, tgt: np.ndarray, history: int) -> float:
    t0, n = max(1, history), tgt.size
    past = sm.add_constant(np.column_stack([tgt[t0 - i: n - i] for i in range(1, history + 1)]))
    full = np.column_stack([past, src[t0 - 1: n - 1]])
    return 0.5 * np.log(sm.OLS(tgt[t0:], past).fit().ssr / sm.OLS(tgt[t0:], full).fit().ssr)


def test_histogram_reads_low_as_documented_where_ksg_does_not():
    # transfer_entropy's `method` documents -28 % to -41 % for the histogram at TE 0.83
    # nats with history 2; measured -33.6 % (sd 0.4 %) at n = 4000 here, KSG -1.5 %
    # (sd 1 %): bounds far outside both spreads
    hist, ksg = [], []
    for seed in range(3):
        x, y = _var_pair(4000, 2.0, 50 + seed)
        ref = _granger(x, y, 2)
        with pytest.warns(BiasRuleWarning) as record:  # said once, the value kept
            hist.append(transfer_entropy(x, y, history=2, method="histogram") / ref - 1)
        assert len(record) == 1
        assert "5 bins per axis over 4 columns (n = 3998)" in str(record[0].message)
        assert "method='ksg'" in str(record[0].message)
        ksg.append(transfer_entropy(x, y, history=2, method="ksg") / ref - 1)
    assert -0.41 <= np.mean(hist) <= -0.28
    assert abs(np.mean(ksg)) <= 0.05


@pytest.mark.parametrize("history", [1, 2])
def test_default_method_reads_granger(history):
    # the default (api.DEFAULT_METHOD, "ksg"; "histogram" before left25-api, which read
    # -12.5 % / -22 % here, sd 1 %) against half Granger's log-variance ratio, TE 0.38
    # nats, n = 4000: KSG's stated accuracy is 3 % (round 25), its measured sd 2.6 % per
    # seed (6 seeds: mean -0.1 % / +0.4 %), so 1.5 % for a mean of 3: bound 3 % + 3 sd
    errors = []
    for seed in range(3):
        x, y = _var_pair(4000, 1.0, 50 + seed)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # the default gives its value without a word
            errors.append(transfer_entropy(x, y, history=history) / _granger(x, y, history) - 1)
    assert abs(np.mean(errors)) <= 0.075
