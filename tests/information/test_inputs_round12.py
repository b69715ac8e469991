"""Round 12 PART a (issue 27): inputs a scientist passes that the API mishandled.

References (outside the code):
- a variable independent of the other has MI 0 (Cover & Thomas 2006, eq. 2.45): a log
  stuck at one value but for one frame, against white noise, must score ~0, not raise
  scipy's "data must be finite";
- the entropy of rounded or discrete data is that of the dequantised density (uniform
  within each lattice cell; audit 11): ln k for integers uniform on k levels, which the
  histogram gives; the KDE gave -0.60 for a boolean sample (ln 2 = 0.693), -3.9 for a
  log stuck but for one frame (0.008), so it must refuse and name the histogram;
- a pandas DataFrame's column names are the labels its owner gave (pandas'
  ``DataFrame.columns``): the transfer-entropy map and the input search must carry them;
- pandas pairs two Series by label (``Series.align``); the estimators pair by position,
  so Series with different indexes must be refused rather than paired row by row.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from modalinfo.information import (
    MutualInformation,
    conditional_mutual_information,
    entropy,
    mutual_information,
    mutual_information_ci,
    mutual_information_permutation_test,
    select_inputs,
    transfer_entropy,
    transfer_entropy_map,
)


def _stuck_but_one(n=1000):
    z = np.ones(n)
    z[500] = 2.0  # not on the 128-sample screen's stride (n // 128 = 7)
    return z, np.random.default_rng(7).standard_normal(n)


@pytest.mark.parametrize("method", ["ksg", "kde", "histogram", "gaussian"])
def test_stuck_log_but_one_frame_scores_independence(method):
    z, w = _stuck_but_one()
    assert abs(mutual_information(z, w, method=method)) < 0.01


def test_stuck_log_but_one_frame_transfer_entropy():
    z, w = _stuck_but_one()
    assert abs(transfer_entropy(z, w)) < 0.01


@pytest.mark.parametrize("levels", [2, 3])
def test_kde_entropy_refuses_a_lattice_sample(levels):
    x = np.random.default_rng(1).integers(0, levels, 2000)
    with pytest.raises(ValueError, match=rf"`x` takes only {levels} distinct values.*"
                                         r"method='histogram'"):
        entropy(x)
    with pytest.raises(ValueError, match="lattice"):
        entropy(x.astype(bool) if levels == 2 else x.astype(float), method="kde")


def test_kde_entropy_refuses_a_log_stuck_but_one_frame():
    z, _ = _stuck_but_one()
    with pytest.raises(ValueError, match="2 distinct values"):
        entropy(z)


@pytest.mark.parametrize("levels", [2, 3])
def test_the_advised_histogram_gives_the_dequantised_entropy(levels):
    # integers uniform on 0..levels-1, dequantised: uniform on [-1/2, levels - 1/2),
    # entropy ln(levels) (audit 11's reference)
    x = np.random.default_rng(1).integers(0, levels, 2000)
    assert entropy(x, method="histogram") == pytest.approx(np.log(levels), abs=0.01)


def test_entropy_of_rounded_adu_is_still_the_scaled_entropy():
    # int16 ADU at 1/1000 of the spread: continuous, h(1000 x) = h(x) + ln 1000
    x = np.random.default_rng(1).standard_normal(2000)
    adu = np.round(x * 1000).astype(np.int16)
    truth = 0.5 * np.log(2 * np.pi * np.e) + np.log(1000)
    assert entropy(adu, method="histogram") == pytest.approx(truth, abs=0.05)
    assert entropy(adu, method="gaussian") == pytest.approx(truth, abs=0.05)


def _frame():
    rng = np.random.default_rng(3)
    a = rng.standard_normal((1500, 3))
    a[1:, 1] += 0.8 * a[:-1, 0]  # Z3 follows Z2 by one frame
    return pd.DataFrame(a, columns=["Z2", "Z3", "Z4"],
                        index=pd.date_range("2026-01-01", periods=1500, freq="500us"))


def test_transfer_entropy_map_keeps_dataframe_column_names():
    m = transfer_entropy_map(_frame(), lags=1, n_surrogates=19, seed=0)
    assert m.labels == ("Z2", "Z3", "Z4")


def test_select_inputs_keeps_dataframe_column_names():
    s = select_inputs(_frame(), "Z3", max_lag=2, n_surrogates=19, seed=0, intervals=False)
    assert s.target == "Z3"
    assert "Z2[t]" in [i.label for i in s.inputs]


def _shifted_pair():
    rng = np.random.default_rng(21)
    x = rng.standard_normal(2000)
    y = 0.6 * x + 0.8 * rng.standard_normal(2000)
    idx = pd.date_range("2026-01-01", periods=2000, freq="1ms")
    return pd.Series(x, index=idx), pd.Series(y, index=idx + pd.Timedelta("5ms"))


@pytest.mark.parametrize("call", [
    lambda x, y: mutual_information(x, y),
    lambda x, y: conditional_mutual_information(x, y, np.zeros(2000) + np.arange(2000)),
    lambda x, y: mutual_information_ci(x, y, n_resamples=9, seed=0),
    lambda x, y: mutual_information_permutation_test(x, y, n_permutations=9, seed=0),
    lambda x, y: transfer_entropy(x, y),
    lambda x, y: MutualInformation().estimate(x, y),
], ids=["mi", "cmi", "ci", "perm", "te", "object"])
def test_series_with_different_indexes_are_refused(call):
    # pandas pairs by label (x.align(y)); the estimators pair by position: the pair
    # (x at t, y at t + 5 ms) is not the simultaneous pair the user asked about
    x, y = _shifted_pair()
    with pytest.raises(ValueError, match="different indexes"):
        call(x, y)


def test_series_with_the_same_index_equal_the_arrays():
    x, y = _shifted_pair()
    y.index = x.index
    assert mutual_information(x, y) == mutual_information(x.to_numpy(), y.to_numpy())
