"""The effective-sample warning of a line at half the frame rate (round 41 PART a V10).

Reference: ``x_t = cos(pi t + 0.4)`` alternates between +-cos(0.4): its lag-1
autocorrelation is -1 (numpy) and ``I(x_t; x_t+1) = H(x_t) = ln 2``. The warning called
it "a persistent series ... biased low" and advised differencing the series, which
alternates just the same; the KSG estimate (6.2) is far above ln 2.
"""

import math
import warnings

import numpy as np

from modalinfo.information import BiasRuleWarning, mutual_information


def test_alternating_pair_is_named_as_such():
    n = 20_000
    x = np.cos(np.pi * np.arange(n + 1) + 0.4)
    assert np.corrcoef(x[:-1], x[1:])[0, 1] < -0.999
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = mutual_information(x[:-1], x[1:])
    assert value > math.log(2)
    said = [str(w.message) for w in caught if issubclass(w.category, BiasRuleWarning)]
    assert len(said) == 1
    assert "alternate" in said[0] and "difference the series" not in said[0]
