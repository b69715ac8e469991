"""A predictor fitted on a labelled DataFrame, given its columns permuted (round 42 PART a, M17).

``LinearPredictor(1).fit(df).predict(df[["Z4", "Z2", ...]])`` read the columns by
position: the forecast of Z4 came out under Z2's name. Reference: the forecast of the
same predictor on the columns in the fitted order, reordered by pandas (what
scikit-learn's ``feature_names_in_`` check enforces by refusing the permuted frame).
"""

import numpy as np
import pandas as pd
import pytest

from modalinfo.forecast import ARMAPredictor, LinearPredictor

RNG = np.random.default_rng(4217)
NAMES = [f"Z{j}" for j in range(2, 6)]


def _frame():
    x = np.zeros((400, 4))
    noise = RNG.standard_normal((400, 4))
    for t in range(1, 400):
        x[t] = 0.8 * x[t - 1] + noise[t]
    return pd.DataFrame(x, columns=NAMES)


def test_permuted_columns_refused():
    frame = _frame()
    predictor = LinearPredictor(horizon=1).fit(frame)
    permuted = frame[["Z4", "Z2", "Z3", "Z5"]]
    with pytest.raises(ValueError, match=r"`history` has columns \(Z4, Z2, Z3, Z5\)"):
        predictor.predict(permuted.iloc[:50])


def test_permuted_columns_refused_by_the_interval():
    frame = _frame()
    predictor = ARMAPredictor(horizon=1, order=(1, 0)).fit(frame)
    with pytest.raises(ValueError, match="was fitted on columns"):
        predictor.predict_interval(frame[["Z5", "Z4", "Z3", "Z2"]].iloc[:50])


def test_same_order_and_arrays_accepted():
    frame = _frame()
    predictor = LinearPredictor(horizon=1).fit(frame)
    expected = predictor.predict(frame.to_numpy()[:50])
    np.testing.assert_array_equal(predictor.predict(frame.iloc[:50]), expected)
    reordered = frame[["Z4", "Z2", "Z3", "Z5"]][NAMES]  # pandas puts them back
    np.testing.assert_array_equal(predictor.predict(reordered.iloc[:50]), expected)
    # refitted on an array: no names kept, a DataFrame is read by position
    predictor.fit(frame.to_numpy())
    np.testing.assert_array_equal(
        predictor.predict(frame[["Z4", "Z2", "Z3", "Z5"]].iloc[:50]),
        predictor.predict(frame[["Z4", "Z2", "Z3", "Z5"]].to_numpy()[:50]))
