"""Review 21: the pile rule's shared-pile threshold and its continuum requirement.

References from outside the code: the samples are built with an exact number of
piled values (counted by hand, no sampling error): n = 4000 standard normal draws
(distinct with probability 1), of which k are replaced by 0.0. The documented rule
(``modalinfo.information.discrete`` module notes, "Piles"): two variables sharing one
value each on MORE than 0.5 % of the samples (n = 4000: more than 20) are judged; a
sample is continuous when at least half of the samples outside its atoms take a value of
their own, so a 60 % dropout pile beside 1600 distinct draws is a pile, not rounded data.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information.discrete import pile_of, pile_why

N = 4000


def _shared(k: int) -> tuple[np.ndarray, np.ndarray]:
    z = np.random.default_rng(21).standard_normal((N, 2))
    x, y = z[:, 0], 0.5 * z[:, 0] + np.sqrt(0.75) * z[:, 1]
    x[:k] = 0.0
    y[:k] = 0.0
    return x, y


@pytest.mark.parametrize("method", ["kde", "histogram", "gaussian"])
def test_shared_pile_judged_just_above_half_a_percent(method):
    # 21 of 4000 (0.525 %) shared: more than 0.5 %, judged; 20 (exactly 0.5 %) is not
    x, y = _shared(21)
    why = pile_why({"x": x, "y": y}, method)
    assert why is not None and "`x` and `y` hold 0.5% " in why and "method='ksg'" in why
    x, y = _shared(20)
    assert pile_why({"x": x, "y": y}, method) is None


def test_shared_pile_not_judged_for_ksg():
    x, y = _shared(40)
    assert pile_why({"x": x, "y": y}, "ksg") is None


@pytest.mark.parametrize("share", [0.55, 0.6, 0.7])
def test_a_majority_dropout_pile_beside_distinct_values_is_a_pile(share):
    # 1 - share of the samples (>= 1200) are distinct draws: the whole remainder outside
    # the atom takes values of its own, the continuum rule's condition
    x = np.random.default_rng(3).standard_normal(N)
    k = int(round(share * N))
    x[:k] = 0.0
    assert pile_of(x) == (0.0, k / N, "inside")
    assert "inside its range" in pile_why({"x": x}, "kde")


def test_a_majority_clip_beside_distinct_values_is_a_pile():
    # clipped at +-0.3 sigma: 2 * Phi(-0.3) = 76 % at the two ends, 24 % distinct
    x = np.random.default_rng(4).standard_normal(N)
    c = np.clip(x, -0.3, 0.3)
    edge = int(np.count_nonzero(np.abs(x) >= 0.3))
    value, share, where = pile_of(c)
    assert where == "ends" and share == edge / N and value in (-0.3, 0.3)
