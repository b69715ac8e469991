"""Persistence, the baseline every predictor is compared with."""

from __future__ import annotations

import numpy as np

from modalinfo.forecast._univariate import _LinearRecursion

__all__ = ["PersistencePredictor", "MeanPredictor"]


class PersistencePredictor(_LinearRecursion):
    """Persistence: ``x_hat[n + h] = x[n]`` for every horizon.

    This is what a loop with a delay does without prediction; the predictor gain
    is measured against it. It has no parameters: ``fit`` only records the number of
    modes (a constant series is accepted).

    Parameters
    ----------
    horizon : int
        Number of steps forecast by ``update``.
    refit_every, window : None
        Accepted for interface uniformity; refitting does not change anything.
    """

    def __init__(self, *, horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)

    def _learns_from_data(self) -> bool:
        return False  # no parameters: any data serve (check_fed)

    def _fit_params(self, X, previous, name):
        n_modes = X.shape[1]
        return {"mu": np.zeros(n_modes), "phi": np.ones((n_modes, 1)),
                "theta": np.zeros((n_modes, 0))}


class MeanPredictor(_LinearRecursion):
    """The training mean: ``x_hat[n + h] = mean(history used at fit)``.

    The optimal forecast of white noise; with persistence, the trivial baseline a
    predictor must beat to claim skill (see :func:`modalinfo.forecast.evaluate`).

    Parameters
    ----------
    horizon : int
        Number of steps forecast by ``update``.
    refit_every : int or None
        Re-estimate the mean every this many samples on the last ``window`` samples.
    window : int or None
        Sliding-window length for refits.
    """

    def __init__(self, *, horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)

    def _fit_params(self, X, previous, name):
        n_modes = X.shape[1]
        constant, value = self._constant_columns(X)
        mu = np.where(constant, value, X.mean(axis=0))  # a constant exactly, not its mean
        return {"mu": mu, "phi": np.zeros((n_modes, 0)),
                "theta": np.zeros((n_modes, 0))}
