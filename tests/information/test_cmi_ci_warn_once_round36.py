"""The CMI interval says its bias rule once, not once per replicate (round 36 PART a, W4-W6).

Reference: the point estimate ``conditional_mutual_information`` with the same method and
options, which gives the rule's ``BiasRuleWarning`` once (one call, one warning: the
common brief's "warnings say what and why, once"), and the same interval computed with
every warning silenced (the values must not move). Before the fix the interval gave one
``BiasRuleWarning`` per bootstrap replicate: 51 for 50 resamples.
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    conditional_mutual_information_ci,
)


@pytest.mark.parametrize(("n", "method", "options"), [
    (30, "histogram", {}), (200, "histogram", {"bins": 3}), (200, "kde", {})])
def test_bias_rule_once_per_interval(n, method, options):
    rng = np.random.default_rng(0)
    x, y, z = rng.standard_normal((3, n))
    with warnings.catch_warnings(record=True) as point:
        warnings.simplefilter("always")
        conditional_mutual_information(x, x + y, z, method=method, **options)
    assert sum(issubclass(w.category, BiasRuleWarning) for w in point) == 1
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        res = conditional_mutual_information_ci(x, x + y, z, method=method, n_resamples=50,
                                                seed=0, **options)
    assert sum(issubclass(w.category, BiasRuleWarning) for w in got) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        quiet = conditional_mutual_information_ci(x, x + y, z, method=method,
                                                  n_resamples=50, seed=0, **options)
    assert (res.low, res.high, res.estimate) == (quiet.low, quiet.high, quiet.estimate)
