"""One column-wise lag-1 autocorrelation (``modalinfo.forecast.lag1_autocorrelations``).

Issue 27, left30-twins: the estimator was written six times (a per-column Python loop
in the spread rules and the shuffle rule, inline in the evaluation's scale shift and in
Figures 2 and 5); now one vectorised function (``modalinfo._stats``, public in
``modalinfo.forecast``) serves them all.

References (outside the code): statsmodels' ``acf(x, nlags=1, adjusted=False)`` (the
biased estimator of Brockwell & Davis eq. 1.4.4) column by column; the exact value
``-2/3`` of the series ``(1, -1, 1)`` (centred ``(2/3, -4/3, 2/3)``: lagged products
``-16/9`` over squares ``24/9``), at any scale (1e300 included);
0 for a constant or a one-frame column (the estimator's empty or zero numerator).
"""

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf

from modalinfo import _stats
from modalinfo._stats import lag1_autocorrelation, lag1_autocorrelations


def _reference(x: np.ndarray) -> np.ndarray:
    return np.array([acf(c, nlags=1, adjusted=False, fft=False)[1] for c in x.T])


def _ar1() -> np.ndarray:
    """AR(1) columns of rho -0.5 .. 0.99, each about its own level."""
    rng = np.random.default_rng(30)
    x = rng.standard_normal((500, 7))
    for t in range(1, 500):
        x[t] += np.array([-0.5, 0.0, 0.3, 0.6, 0.9, 0.95, 0.99]) * x[t - 1]
    return x + 5.0 * np.arange(7)


def _columns() -> np.ndarray:
    """:func:`_ar1` scaled from 1e-200 to 1e150 (the ratio is scale invariant)."""
    return _ar1() * np.array([1e-200, 1e-3, 1.0, 7.0, 1e3, 1e150, 1.0])


@pytest.mark.parametrize("order", ["C", "F"])
def test_each_column_against_statsmodels(order):
    x = np.asarray(_columns(), order=order)
    np.testing.assert_allclose(lag1_autocorrelations(x), _reference(_ar1()),
                               rtol=1e-12, atol=1e-14)


def test_slices_of_columns_give_the_same_answer(monkeypatch):
    """A slice of 2 columns at a time (the memory bound) against statsmodels."""
    monkeypatch.setattr(_stats, "_STACK_VALUES", 1000)  # 500 frames: 2 columns a slice
    np.testing.assert_allclose(lag1_autocorrelations(_columns()), _reference(_ar1()),
                               rtol=1e-12, atol=1e-14)


def test_exact_values_and_degenerate_columns():
    x = np.array([[1.0, 3.0, 1e300], [-1.0, 3.0, -1e300], [1.0, 3.0, 1e300]])
    np.testing.assert_allclose(lag1_autocorrelations(x), [-2.0 / 3.0, 0.0, -2.0 / 3.0],
                               rtol=1e-15)
    assert lag1_autocorrelations(np.ones((1, 4))).tolist() == [0.0] * 4
    assert lag1_autocorrelations(np.empty((0, 3))).tolist() == [0.0] * 3
    assert np.isnan(lag1_autocorrelations(np.array([[1.0], [np.nan], [2.0]]))[0])


def test_one_series_is_the_one_column_case():
    x = _columns()
    for j in range(x.shape[1]):
        assert lag1_autocorrelation(x[:, j]) == pytest.approx(_reference(_ar1()[:, [j]])[0],
                                                              rel=1e-12, abs=1e-14)
    assert lag1_autocorrelation(np.array([])) == 0.0


def test_public_name_refuses_what_is_not_a_real_table():
    """``modalinfo.forecast.lag1_autocorrelations`` (the figures' route) names ``x``."""
    from modalinfo.forecast import lag1_autocorrelations as public

    assert public is lag1_autocorrelations
    np.testing.assert_allclose(public([1.0, -1.0, 1.0]), [-2.0 / 3.0], rtol=1e-15)
    for bad, kind in [(np.ones((2, 2, 2)), ValueError), ([1j, 2.0], TypeError),
                      (["a", "b"], TypeError), (3.0, ValueError),
                      (np.ma.masked_array([1.0, 2.0, 3.0], mask=[0, 1, 0]), ValueError)]:
        with pytest.raises(kind, match="`x`"):
            public(bad)
