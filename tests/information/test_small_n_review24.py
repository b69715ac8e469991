"""Planted-bug review 24 (issue 27): the small-n rule spares bins at the cap.

Reference: the cap of the rule-chosen bins, ``ceil(sqrt(n))`` = 4 at n = 12 (by hand),
and the documented rule (``mutual_information``: rule-chosen bins are judged only
where fewer than 4 per axis; their 16 joint cells above n = 12 are by design, the
cap breaking the cells rule as |r| -> 1). A strongly dependent pair (rho 0.995) of 12
samples gets 4 bins (the cap): since fixes 34-a it is warned, but by the Gaussian
grid-loss rule (4 x 4 bins lose about half of a rho 0.988 pair's 1.88 nats: Cover &
Thomas's Gaussian MI against the binned one), never by the cells rule - the cells rule
counts occupied cells, and 12 samples on a near-diagonal fill few of the 16; an
independent pair of 10 gets fewer than 4 and is warned (round 34).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, mutual_information


def test_bins_at_the_cap_are_not_judged_by_the_cells_rule():
    n = 12
    assert math.ceil(math.sqrt(n)) == 4
    rng = np.random.default_rng(1)
    a = rng.standard_normal(n)
    b = 0.995 * a + 0.1 * rng.standard_normal(n)
    with pytest.warns(BiasRuleWarning) as record:
        mutual_information(a, b, method="histogram")
    messages = [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)]
    assert len(messages) == 1
    assert "lose" in messages[0] and "per occupied cell" not in messages[0]


def test_fewer_than_four_bins_still_warn():
    rng = np.random.default_rng(2)
    with pytest.warns(BiasRuleWarning, match="method='histogram'"):
        mutual_information(rng.standard_normal(10), rng.standard_normal(10),
                           method="histogram")
