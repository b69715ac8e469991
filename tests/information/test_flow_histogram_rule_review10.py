"""The histogram transfer-entropy map judges each target on its strongest cell (review10).

Round 10 of planted bugs. Reference: the analytic transfer entropy of
``y[t] = 0.99 y[t-1] + 0.5 x[t-1] + e[t]`` (x, e independent standard normal),
``0.5 ln(1 + 0.5^2)`` = 0.1116 nats (Barnett, Barrett & Seth 2009: half the Granger
statistic for Gaussian variables), and 0 from a third, independent white series w. The
histogram map of such a persistent target is biased low (below half the truth), which
audit 11's rule (``flow._judge_histogram_map``, the conditioning rule of
``transfer_entropy`` on each target's largest cell) warns about. With three series the
target y has two cells, x -> y (0.11) and w -> y (0): planted bug R10-R5 (the rule
judged on the smallest cell, w -> y, whose CMI is below the rule's 0.01-nat floor)
escaped tests/information/test_flow_histogram_rule_audit11.py, whose two series give
each target a single cell: the biased map went unwarned.
"""

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information import BiasRuleWarning, transfer_entropy_map

TE_TRUE = 0.5 * math.log(1.25)


def test_a_persistent_target_with_an_unrelated_third_series_warns():
    rng = np.random.default_rng(10)
    n = 4000
    x = rng.standard_normal(n)
    y = lfilter([1.0], [1.0, -0.99], np.r_[0.0, 0.5 * x[:-1]] + rng.standard_normal(n))
    w = rng.standard_normal(n)
    with pytest.warns(BiasRuleWarning, match="1 of 3 target"):
        m = transfer_entropy_map(np.column_stack([x, y, w]), lags=1, history=1,
                                 method="histogram", n_surrogates=19, seed=0)
    te = m.te[:, :, 0] if m.te.ndim == 3 else m.te
    assert np.nanmax(te) < 0.5 * TE_TRUE  # the bias the warning names
