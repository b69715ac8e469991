"""Planted-bug review 26 (stop 50): the square-floor refusal's documented edges.

``check_square_floor`` (round 40 PART a, L30, L31) promises: "Constant columns (a zeroed
mode) are accepted" and names the first refused column with ``(and N more)``, N the
number of other refused columns. References: the docstring's promise, numpy's
``eigvalsh`` of the mean-square matrix, and the count of the columns scaled below
``SQUARE_FLOOR`` by hand. Plants R26-E1 (``spread >= 1e-12 * peak``: a zeroed column
refused) and R26-E2 (``(and N more)`` off by one) escaped
tests/common/test_square_limits_round40.py.
"""

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis
from modalinfo.common.validation import SQUARE_FLOOR, check_square_floor


def _coeffs():
    rng = np.random.default_rng(5)
    return rng.standard_normal((2000, 10)) * np.linspace(1.0, 0.2, 10)


def test_a_zeroed_mode_is_accepted_by_the_floor():
    c = _coeffs()
    c[:, 3] = 0.0  # a mode the loop does not control: constant, not too small
    check_square_floor(c, "coeffs")  # no refusal
    check_square_floor(np.zeros(50), "x")


def test_data_kl_of_a_log_with_a_zeroed_mode_is_numpy_eigvalsh():
    c = _coeffs()
    c[:, 3] = 0.0
    ref = np.sort(np.linalg.eigvalsh(c.T @ c / c.shape[0]))[::-1]
    got = KLBasis.from_data(ZernikeBasis(Pupil(16), range(2, 12)), c).variances
    np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-14)


@pytest.mark.parametrize("columns", [[1], [1, 4], [0, 2, 7]])
def test_the_refusal_names_the_first_column_and_counts_the_others(columns):
    c = _coeffs()
    c[:, columns] *= 1e-160
    assert np.all(np.ptp(c[:, columns], axis=0) < SQUARE_FLOOR)
    more = f" (and {len(columns) - 1} more)" if len(columns) > 1 else ""
    with pytest.raises(ValueError) as err:
        check_square_floor(c, "coeffs")
    assert f"`coeffs`: column {columns[0]}{more} varies over only" in str(err.value)
    assert "more" in str(err.value) or len(columns) == 1


def test_data_kl_counts_the_rows_summed_not_the_modes():
    # the mean-square matrix sums T = 2000 products per entry: values of +-1.5e153 stay
    # below sqrt(max / (4 M)) = 2.1e153 for M = 10 modes, but their sum of squares
    # overflows float64 (numpy: inf); refused by the rows' limit sqrt(max / (4 T)).
    # Plant R26-E4 (n_terms = the mode count) escaped
    signs = np.random.default_rng(3).choice([-1.0, 1.0], size=(2000, 10))
    c = signs * 1.5e153
    with np.errstate(over="ignore"):
        assert np.isinf(np.sum(c[:, 0] ** 2))
    assert 1.5e153 < np.sqrt(np.finfo(np.float64).max / 40)
    with pytest.raises(ValueError, match="`coeffs`: column 0 .*beyond"):
        KLBasis.from_data(ZernikeBasis(Pupil(16), range(2, 12)), c)
