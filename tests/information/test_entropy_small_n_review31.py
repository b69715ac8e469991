"""The KDE entropy's small-sample warning at its edges (review 31, round 31 mutation).

``tests/information/test_entropy_small_n_round48.py`` checks n = 10 (warned) and n = 200
(not): a threshold of 20 instead of 30, ``n > 30`` for ``n >= 30``, the warning given
for an explicit float bandwidth too (which the occupancy rule judges instead), and a
warning attributed to a frame inside the package rather than the caller all passed it.
References: the rule's docstring ("below 30 samples", "an explicit float bandwidth is
judged by the occupancy rule instead") and ``warnings``' own record of the caller's file.
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, entropy


def _rule_warnings(n, **kw):
    x = np.random.default_rng(7).standard_normal(n)
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        entropy(x, method="kde", **kw)
    return [w for w in ws
            if issubclass(w.category, BiasRuleWarning) and "n >= 30" in str(w.message)]


@pytest.mark.parametrize("n, warned", [(29, True), (30, False)])
def test_the_rule_is_thirty_samples(n, warned):
    assert len(_rule_warnings(n)) == (1 if warned else 0)


def test_an_explicit_float_bandwidth_is_not_judged_by_the_count():
    assert _rule_warnings(10, bandwidth=0.5) == []


def test_the_warning_names_the_callers_line():
    (w,) = _rule_warnings(12)
    assert w.filename == __file__, w.filename
