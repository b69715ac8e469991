"""fix52-c (stop 58's small items): the local-fit helpers of ``information.resampling``.

References, outside the package: the refusal of a z with one row (a row has no other
row to be its neighbour, so a local fit of it has no data: the former code divided by an
empty sum); ``numpy.linalg.lstsq`` of the local fits one row at a time.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information.resampling import local_linear_split, neighbour_rows


@pytest.mark.parametrize("rank_based", [True, False])
def test_one_row_has_no_neighbours_and_is_refused(rank_based):
    # the public callers refuse fewer than 10 (conditional test) or 21 (select, map)
    # frames before here; the helpers refuse it themselves rather than return an
    # empty neighbour table and a singular local fit
    z = np.array([[0.5]])
    with pytest.raises(ValueError, match=r"`z` needs at least 2 rows"):
        neighbour_rows(z, rank_based)
    with pytest.raises(ValueError, match=r"`z` needs at least 2 rows"):
        local_linear_split(np.array([[1.0]]), z, rank_based)


def test_a_neighbour_table_with_no_columns_is_refused():
    z = np.array([[0.0], [1.0], [3.0]])
    y = np.array([[1.0], [0.0], [2.0]])
    with pytest.raises(ValueError, match=r"`near` needs at least 1 neighbour"):
        local_linear_split(y, z, False, np.empty((3, 0), dtype=int))


def test_two_rows_take_each_others_value():
    # one neighbour each: the local mean of the other row (no line through one point)
    z = np.array([[0.0], [1.0]])
    y = np.array([[2.0], [5.0]])
    fit, rest = local_linear_split(y, z, False)
    np.testing.assert_allclose(fit + rest, y, rtol=0, atol=1e-12)
    assert np.isfinite(fit).all()
