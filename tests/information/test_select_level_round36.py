"""``select_inputs`` checks ``confidence_level`` with or without intervals (round 36 PART a).

Reference: the contract of the common brief (bad input: an error naming the argument)
and ``InputSelection.confidence_level``'s docstring (a nominal coverage in (0, 1)).
Before the fix, with ``intervals=False`` the level was never checked: 5 was recorded as
the selection's level, None and "x" met ``float()``'s own TypeError / ValueError.
"""

import numpy as np
import pytest

from modalinfo.information import select_inputs


def _data() -> np.ndarray:
    rng = np.random.default_rng(6)
    a = np.zeros((600, 2))
    e = rng.standard_normal((600, 2))
    for i in range(1, 600):
        a[i, 0] = 0.5 * a[i - 1, 0] + e[i, 0]
        a[i, 1] = 0.5 * a[i - 1, 1] + 0.4 * a[i - 1, 0] + e[i, 1]
    return a


@pytest.mark.parametrize("level", [5, 0.0, None, "x"])
def test_level_refused_without_intervals(level):
    with pytest.raises((TypeError, ValueError), match="`confidence_level`"):
        select_inputs(_data(), 1, max_lag=2, n_surrogates=39, intervals=False,
                      confidence_level=level, seed=0)


def test_valid_level_recorded_without_intervals():
    sel = select_inputs(_data(), 1, max_lag=2, n_surrogates=39, intervals=False,
                        confidence_level=0.8, seed=0)
    assert sel.confidence_level == 0.8
