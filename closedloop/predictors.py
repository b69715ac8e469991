"""Predictors inside the loop: names, and training on a no-prediction run as in the paper.

The paper trains its ARMA and neural net on "the standard MFoV MCAO simulation" (the run
without prediction, same conditions), after the loop closure: the NN on 10 patterns of
10 values taken after 15 ms, the ARMA(2,3) from the autocovariance. :func:`train` does
that with the POL coefficients of a no-prediction :class:`SimulationResult` (every DM's
modes side by side), and :func:`make` names the configurations: the paper's
(``linear``: a = 2, b = -1; ``arma``: ARMA(2,3); ``nn-paper``: 10 patterns) beside the
working defaults of :mod:`modalinfo.forecast` (``nn``, ``arma-aic``, ``multivariate``,
...), all from :data:`modalinfo.forecast.presets.PRESETS`, plus ``persistence`` and the
``oracle`` (the true future; no training).
"""

from __future__ import annotations

import numpy as np

from closedloop.result import SimulationResult
from modalinfo.forecast import PersistencePredictor
from modalinfo.forecast.presets import PRESETS, make_predictor

__all__ = ["NAMES", "make", "train", "needs_training", "training_data", "training_start"]

#: every name ``closedloop run --predictor`` accepts
NAMES: tuple[str, ...] = ("none", "persistence", "oracle", *PRESETS)

#: the paper trains after the loop closure, from t > 15 ms
_PAPER_TRAINING_START = 15e-3


def make(name: str):
    """Return a fresh predictor for ``name`` (None for "none", the string for "oracle")."""
    if name not in NAMES:
        raise ValueError(f"`predictor` must be one of {', '.join(NAMES)}; got {name!r}.")
    if name == "none":
        return None
    if name == "oracle":
        return "oracle"
    if name == "persistence":
        return PersistencePredictor()
    return make_predictor(name)


def needs_training(predictor) -> bool:
    """Whether ``predictor`` must be fitted on a no-prediction run before use."""
    return predictor is not None and not isinstance(predictor, str)


def training_start(result: SimulationResult) -> int:
    """First frame the paper would train on: after the loop closure and after 15 ms."""
    return max(result.closure_index,
               int(np.searchsorted(result.times, _PAPER_TRAINING_START, side="right")))


def training_data(reference: SimulationResult) -> np.ndarray:
    """POL coefficients ``(T, M)`` of every DM after the loop closure (and after 15 ms)."""
    if reference.predictor != "none":
        raise ValueError("training needs the no-prediction run; got a run with predictor "
                         f"{reference.predictor!r}.")
    pols = [reference.logs[f"dm{i}.pol"].coeffs for i in range(len(reference.config.dms))]
    pol = np.hstack(pols)
    start = training_start(reference)
    if pol.shape[0] - start < 20:
        raise ValueError(f"the reference run has {pol.shape[0] - start} frames after its "
                         "loop closure; run it longer to train a predictor.")
    return pol[start:]


def train(predictor, reference: SimulationResult):
    """Fit ``predictor`` on the POL of the no-prediction run ``reference``; return it."""
    if needs_training(predictor):
        predictor.fit(training_data(reference))
    return predictor
