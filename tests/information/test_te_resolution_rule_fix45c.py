"""The histogram transfer entropy warns where its bins fail the resolution rule (fixes 45-c).

Round 44 PART a I32: ``transfer_entropy(method="histogram")`` at history 2 returned 0.147
(-22 %) without a word, where ``conditional_mutual_information`` of the same hand-lagged
columns warned (resolution rule) and switched to the KSG (0.188). The lead's decision:
the TE keeps one estimator, so it keeps the histogram and warns once (as it does for the
conditioning rule).

References, from outside the code: the lagged columns built by hand with numpy slicing
(x_t, y_{t-l}, x_{t-1}, x_{t-2}); the rule as stated ("at least 8 bins per axis"), with
n and d counted by hand (n = T - max(lag, history), d = 1 + 1 + history).
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    transfer_entropy,
)


def _pair(n: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """source s_t = 0.5 s_{t-1} + e, target x_t = 0.4 x_{t-1} + 0.8 s_{t-2} + f."""
    e = np.random.default_rng(seed).standard_normal((n + 200, 2))
    s, x = np.zeros(n + 200), np.zeros(n + 200)
    for t in range(2, n + 200):
        s[t] = 0.5 * s[t - 1] + e[t, 0]
        x[t] = 0.4 * x[t - 1] + 0.8 * s[t - 2] + e[t, 1]
    return s[200:], x[200:]


def test_histogram_te_warns_once_and_keeps_the_histogram_value():
    src, tgt = _pair(2000)
    with pytest.warns(BiasRuleWarning) as record:
        te = transfer_entropy(src, tgt, lag=2, history=2, method="histogram")
    assert len(record) == 1  # one warning per call
    text = str(record[0].message)
    # n and d counted by hand: T - max(lag, history) = 1998 rows, 1 + 1 + 2 columns
    assert "over 4 columns (n = 1998)" in text
    assert "resolution rule of at least 8 bins per axis" in text
    assert "method='ksg', the default" in text and "returned anyway" in text
    # the value kept is the histogram CMI of the hand-lagged columns (not the KSG switch)
    x, y, z = tgt[2:], src[:-2], np.column_stack([tgt[1:-1], tgt[:-2]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BiasRuleWarning)
        kept = conditional_mutual_information(x, y, z, method="histogram", fallback="none")
        switched = conditional_mutual_information(x, y, z, method="histogram")
    assert te == pytest.approx(kept, rel=1e-12)
    assert switched != pytest.approx(kept, rel=1e-3)  # the CMI's point estimate switches


def test_fallback_raise_refuses_and_rule_met_is_silent():
    src, tgt = _pair(2000)
    with pytest.raises(ValueError, match="resolution rule.*fallback='raise'"):
        transfer_entropy(src, tgt, lag=2, history=2, method="histogram", fallback="raise")
    # history 1 at n = 4000: 3 columns, the rule met (8 bins per axis from n = 3956 by
    # the rule's own table); an explicit bin number is the caller's and is not judged
    src, tgt = _pair(4000)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        transfer_entropy(src, tgt, lag=2, history=1, method="histogram")
        transfer_entropy(src, tgt, lag=2, history=2, method="histogram", bins=6)
