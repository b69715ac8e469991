"""Planted-bug review 24 (issue 27): the small-n rule spares bins at the cap.

Reference: the cap of the rule-chosen bins, ``ceil(sqrt(n))`` = 4 at n = 12 (by hand),
and the documented rule (``mutual_information``: rule-chosen bins are judged only
where fewer than 4 per axis; their 16 joint cells above n = 12 are by design, the
cap breaking the cells rule as |r| -> 1). A strongly dependent pair (rho 0.995) of 12
samples gets 4 bins (the cap) and no bias-rule warning; an independent pair of 10 gets
fewer than 4 and is warned (round 34).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, mutual_information


def test_bins_at_the_cap_are_not_judged_by_the_cells_rule():
    n = 12
    assert math.ceil(math.sqrt(n)) == 4
    rng = np.random.default_rng(1)
    a = rng.standard_normal(n)
    b = 0.995 * a + 0.1 * rng.standard_normal(n)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        mutual_information(a, b, method="histogram")


def test_fewer_than_four_bins_still_warn():
    rng = np.random.default_rng(2)
    with pytest.warns(BiasRuleWarning, match="method='histogram'"):
        mutual_information(rng.standard_normal(10), rng.standard_normal(10),
                           method="histogram")
