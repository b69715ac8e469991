"""Wavefront forecasting: persistence, linear, ARMA, neural-net and multivariate predictors.

Every predictor shares the :class:`Predictor` interface: ``fit(history)``,
``predict(history, horizon)`` offline, and ``reset()`` / ``update(x_t)`` online (what
the closed-loop simulator calls each loop step), with bit-identical forecasts on both
paths. :func:`evaluate` compares predictors on a log, rolling-origin and without
look-ahead, and returns a :class:`ForecastEvaluation` (RMSE per mode and for the whole
wavefront, gain over persistence, interval coverage, skill test).

Example
-------
>>> from modalinfo.forecast import ARMAPredictor, LinearPredictor, evaluate
>>> result = evaluate({"arma": ARMAPredictor(), "linear": LinearPredictor()}, log,
...                   train=7000)                                  # doctest: +SKIP
>>> print(result.summary())                                        # doctest: +SKIP
"""

from modalinfo._stats import lag1_autocorrelations
from modalinfo.forecast.arma import (
    ARMAPredictor,
    ForecastInterval,
    psi_weights,
    sample_autocovariance,
)
from modalinfo.forecast.base import NotFittedError, Predictor
from modalinfo.forecast.evaluate import ForecastEvaluation, evaluate
from modalinfo.forecast.info import InfoPredictor
from modalinfo.forecast.info_nn import InfoNNPredictor
from modalinfo.forecast.linear import LinearPredictor
from modalinfo.forecast.multivariate import MultivariatePredictor, RLSMultivariatePredictor
from modalinfo.forecast.nn import NeuralNetPredictor
from modalinfo.forecast.persistence import MeanPredictor, PersistencePredictor
from modalinfo.forecast.presets import PRESETS, make_predictor

__all__ = [
    "Predictor",
    "NotFittedError",
    "PersistencePredictor",
    "MeanPredictor",
    "LinearPredictor",
    "ARMAPredictor",
    "NeuralNetPredictor",
    "MultivariatePredictor",
    "RLSMultivariatePredictor",
    "InfoPredictor",
    "InfoNNPredictor",
    "ForecastInterval",
    "psi_weights",
    "sample_autocovariance",
    "lag1_autocorrelations",
    "evaluate",
    "ForecastEvaluation",
    "PRESETS",
    "make_predictor",
]
