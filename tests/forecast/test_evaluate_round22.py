"""Round 22 PART a: the verdict on a mode constant in training that steps afterwards.

Reference: hand arithmetic on a step from 2 to 5 at frame 1500 after 1000 training
frames: persistence errs once by 3 (RMSE sqrt(9 / 1000)), the fixed-weight line
2 x_t - x_{t-1} twice (sqrt(18 / 1000)), the training mean always after the step
(sqrt(500 * 9 / 1000)). Before the fix the summary said the mode was "forecast as that
constant by every predictor", false for persistence and the linear extrapolation, and
did not say the constant stopped holding.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate


def test_step_after_training_is_reported_and_not_claimed_constant():
    x = np.where(np.arange(2000) < 1500, 2.0, 5.0)[:, None]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = evaluate({"lin": LinearPredictor()}, x, train=1000, horizons=[1])
    rmse = dict(zip(res.names, res.rmse_wavefront[:, 0], strict=True))
    np.testing.assert_allclose(rmse["persistence"], np.sqrt(9 / 1000), rtol=1e-12)
    np.testing.assert_allclose(rmse["lin"], np.sqrt(18 / 1000), rtol=1e-12)
    np.testing.assert_allclose(rmse["mean"], np.sqrt(4500 / 1000), rtol=1e-12)
    text = res.summary()
    assert "by every predictor" not in text
    assert "Not constant after training: mode0" in text


def test_replace_with_inconsistent_fields_is_refused():
    x = np.random.default_rng(1).standard_normal((300, 2)).cumsum(axis=0)
    res = evaluate({"lin": LinearPredictor()}, x, train=150, horizons=[1, 2])
    assert dataclasses.replace(res) == res
    with pytest.raises(ValueError,
                       match=r"`rmse` has shape \(3, 2, 2\); the other fields need \(1, 2, 2\)"):
        dataclasses.replace(res, names=("a",))
    with pytest.raises(ValueError, match=r"`rmse` has shape \(1, 1, 1\)"):
        dataclasses.replace(res, rmse=np.zeros((1, 1, 1)))
