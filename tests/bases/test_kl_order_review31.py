"""The K-L sort key's digits and floor (review 31, round 31 mutation).

``_decreasing_order`` promises: each value rounded to 10 significant digits of its own
magnitude, floored at 1e-13 of the largest. ``tests/bases/test_kl_order_round48.py``
separates values 2e-6 apart (relative), so a key of 6 digits, or a floor at 1e-3 of
the largest, passed it. References: the docstring's promise and numpy's own descending
sort (``np.argsort`` of the negated values) for the values further apart than the key's
digits; twins equal to rounding (1e-12 relative) stay a tie ordered cos (1) first.
"""

import numpy as np
import pytest

from modalinfo.bases.kl import _decreasing_order


@pytest.mark.parametrize("values", [
    [1.0, 1.0000001],  # 1e-7 apart, relative: within 10 digits, not within 6
    [1.0, 1e-9, 1.000001e-9],  # far below the largest, above its 1e-13 floor
], ids=["eighth-digit", "small-values"])
def test_values_apart_in_ten_digits_are_ordered_by_value(values):
    values = np.array(values)
    kinds = np.where(np.arange(values.size) % 2 == 0, 2, 1)  # the smaller listed as cos
    kinds[0] = 0
    order = _decreasing_order(values, kinds)
    assert order.tolist() == np.argsort(-values, kind="stable").tolist()


def test_twins_equal_to_rounding_stay_cos_first():
    values = np.array([0.02 * (1 + 1e-12), 0.02, 0.449])
    order = _decreasing_order(values, np.array([2, 1, 0]))  # sin slightly above cos
    assert order.tolist() == [2, 1, 0]
