"""Round 15 PART a: a forecast horizon of 10**9 frames is refused, naming ``horizon``.

Reference: the documented bound ``1 <= horizon <= MAX_HORIZON`` (10**6 frames); at the
bound a persistence forecast is the last sample repeated (its definition), checked on
a short horizon.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import (
    ARMAPredictor,
    InfoPredictor,
    LinearPredictor,
    PersistencePredictor,
)
from modalinfo.forecast.base import MAX_HORIZON

X = np.random.default_rng(0).standard_normal(300)


@pytest.mark.parametrize("call", [
    lambda: PersistencePredictor().fit(X).predict(X, horizon=10**9),
    lambda: PersistencePredictor(horizon=10**9).fit(X).predict(X),
    lambda: LinearPredictor().fit(X).predict(X, horizon=MAX_HORIZON + 1),
    lambda: ARMAPredictor(order=(1, 0)).fit(X).predict_interval(X, horizon=10**9),
    lambda: ARMAPredictor(order=(1, 0)).fit(X).forecast_std(horizon=10**9),
    lambda: InfoPredictor(horizon=10**9).fit(X),
])
def test_huge_horizon_refused(call):
    with pytest.raises(ValueError, match=r"`horizon` must be an int <= 1000000"):
        call()


def test_small_horizon_still_forecasts():
    out = PersistencePredictor().fit(X).predict(X, horizon=3)
    np.testing.assert_array_equal(out, np.full(3, X[-1]))
