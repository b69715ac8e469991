"""Wavefront forecasting: persistence, linear, ARMA, neural-net and multivariate predictors."""

from modalinfo.forecast.arma import ARMAPredictor, ForecastInterval, psi_weights
from modalinfo.forecast.base import NotFittedError, Predictor
from modalinfo.forecast.evaluate import ForecastEvaluation, evaluate
from modalinfo.forecast.linear import LinearPredictor
from modalinfo.forecast.multivariate import MultivariatePredictor, RLSMultivariatePredictor
from modalinfo.forecast.nn import NeuralNetPredictor
from modalinfo.forecast.persistence import MeanPredictor, PersistencePredictor

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
    "ForecastInterval",
    "psi_weights",
    "evaluate",
    "ForecastEvaluation",
]
