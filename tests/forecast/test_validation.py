"""Bad input raises clear errors naming the argument (DESIGN.md error convention).

Reference: the project's error-message rule (name the argument, state the rule, show
the value), checked with ``pytest.raises(match=...)`` for short series, constant
series, non-finite values, horizons < 1 and mismatched shapes.
"""

import numpy as np
import pytest

from modalinfo.forecast import (
    ARMAPredictor,
    LinearPredictor,
    MultivariatePredictor,
    NeuralNetPredictor,
    PersistencePredictor,
    RLSMultivariatePredictor,
    evaluate,
)

RNG = np.random.default_rng(0)
X = RNG.standard_normal((500, 2))


@pytest.mark.parametrize("pred,n_min", [
    (ARMAPredictor(order=(2, 3)), 90),
    (NeuralNetPredictor(), 12),
    (LinearPredictor(fit_weights=True), 3),
    (MultivariatePredictor(order=4), 10),
])
def test_series_shorter_than_order(pred, n_min):
    with pytest.raises(ValueError, match=f"`history` needs at least {n_min} samples"):
        pred.fit(X[: n_min - 1])
    pred.fit(X[:n_min])


@pytest.mark.parametrize("pred", [ARMAPredictor(), NeuralNetPredictor(),
                                  LinearPredictor(fit_weights=True),
                                  MultivariatePredictor(), RLSMultivariatePredictor()])
def test_constant_series(pred):
    Y = X.copy()
    Y[:, 1] = 3.0
    with pytest.raises(ValueError, match=r"`history` is constant in mode column\(s\) \[1\]"):
        pred.fit(Y)


def test_constant_series_fine_for_persistence():
    assert np.all(PersistencePredictor().fit(np.ones(20)).predict(np.ones(20)) == 1.0)


def test_nonfinite():
    Y = X.copy()
    Y[7, 0] = np.nan
    with pytest.raises(ValueError, match="`history` must be finite"):
        ARMAPredictor().fit(Y)
    pred = ARMAPredictor(order=(1, 1)).fit(X)
    with pytest.raises(ValueError, match="`history` must be finite; got 1 NaN"):
        pred.predict(Y)
    pred.reset()
    pred.update(X[0])
    with pytest.raises(ValueError, match="`x_t` must be finite"):
        pred.update([np.inf, 0.0])
    with pytest.raises(ValueError, match="`log` must be finite"):
        evaluate([LinearPredictor()], Y)


def test_horizon_below_one():
    with pytest.raises(ValueError, match="`horizon` must be an int >= 1; got 0"):
        ARMAPredictor(horizon=0).fit(X)
    pred = LinearPredictor().fit(X)
    with pytest.raises(ValueError, match="`horizon` must be an int >= 1; got -2"):
        pred.predict(X, horizon=-2)
    with pytest.raises(TypeError, match="`horizon` must be an int; got 1.5"):
        pred.predict(X, horizon=1.5)
    with pytest.raises(ValueError, match="`horizons` must be an int >= 1; got 0"):
        evaluate([LinearPredictor()], X, horizons=[0, 1])


def test_shapes_and_parameters():
    pred = ARMAPredictor(order=(1, 0)).fit(X)
    with pytest.raises(ValueError, match=r"`history` must have 2 mode\(s\)"):
        pred.predict(X[:, :1])
    with pytest.raises(ValueError, match=r"`x_t` must have shape \(2,\); got \(3,\)"):
        pred.update(np.zeros(3))
    with pytest.raises(ValueError, match="`history` must be 1-D or 2-D"):
        pred.predict(np.zeros((3, 2, 2)))
    with pytest.raises(ValueError, match="`order` must be one of 'aic', 'bic'; got 'foo'"):
        ARMAPredictor(order="foo").fit(X)
    with pytest.raises(ValueError, match=r"`order\[1\] \(q\)` must be an int >= 0; got -1"):
        ARMAPredictor(order=(1, -1)).fit(X)
    with pytest.raises(ValueError, match="`refit_every` must be an int >= 1; got 0"):
        ARMAPredictor(refit_every=0).fit(X)
    with pytest.raises(ValueError, match="`forgetting` must be <= 1.0; got 1.5"):
        RLSMultivariatePredictor(forgetting=1.5).fit(X)
    with pytest.raises(ValueError, match="`activation` must be one of"):
        NeuralNetPredictor(activation="softplus").fit(X)
    with pytest.raises(ValueError, match="`train` must leave at least"):
        evaluate([LinearPredictor()], X, train=495)
    with pytest.raises(ValueError, match="`train` must be < 1.0; got 1.5"):
        evaluate([LinearPredictor()], X, train=1.5)
    with pytest.raises(TypeError, match=r"`predictors\['a'\]` must be a Predictor"):
        evaluate({"a": object()}, X)


def test_cli_names_are_the_presets():
    # the CLI lists the names without importing the forecast package; they must agree
    from modalinfo.cli.cmd_forecast import NAMES
    from modalinfo.forecast.presets import PRESETS, make_predictor

    assert tuple(PRESETS) == NAMES
    a, b = make_predictor("arma"), make_predictor("arma")
    assert a is not b and a.get_params() == b.get_params()
    with pytest.raises(ValueError, match="`name` must be one of"):
        make_predictor("kalman")
