"""``update`` given a sample whose mode names are in another order than ``fit``'s (fixes 42).

Round 42 PART a, Left: ``LinearPredictor(1).fit(df)`` then ``update(df[perm].iloc[t])`` (a
pandas Series indexed by the mode names) read the sample by position, as ``predict`` did
before M17. Reference: pandas' own reordering ``row[NAMES]``, and scikit-learn's rule of
refusing feature names that differ from ``feature_names_in_``.
"""

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor

from .test_frame_columns_round42 import NAMES, _frame


def test_update_refuses_a_permuted_row():
    frame = _frame()
    predictor = LinearPredictor(horizon=1).fit(frame)
    row = frame[["Z4", "Z2", "Z3", "Z5"]].iloc[10]
    with pytest.raises(ValueError, match=r"`x_t` has columns \(Z4, Z2, Z3, Z5\)"):
        predictor.update(row)


def test_update_accepts_the_fitted_order_and_arrays():
    frame = _frame()
    a = LinearPredictor(horizon=1).fit(frame)
    b = LinearPredictor(horizon=1).fit(frame)
    for t in range(5):
        by_name = a.update(frame[["Z4", "Z2", "Z3", "Z5"]].iloc[t][NAMES])  # pandas reorders
        np.testing.assert_array_equal(by_name, b.update(frame.to_numpy()[t]))
