"""Shared machinery of the univariate linear recursions (persistence, linear, ARMA)."""

from __future__ import annotations

import numpy as np

from modalinfo.forecast._kernels import arma_filter
from modalinfo.forecast.base import Predictor


class _LinearRecursion(Predictor):
    """A predictor run by :func:`~modalinfo.forecast._kernels.arma_filter`.

    ``_fit_params`` must return ``mu (M,)``, ``phi (M, P)`` and ``theta (M, Q)``.
    """

    def _init_state(self, params: dict, horizon: int) -> dict:
        n_modes, n_ar = params["phi"].shape
        n_ma = params["theta"].shape[1]
        return {
            "values": np.zeros((n_modes, n_ar)),
            "innov": np.zeros((n_modes, n_ma)),
            "pred1": np.zeros(n_modes),
            "work": np.zeros(horizon),
        }

    def _filter(self, params, state, X, out, status):
        arma_filter(X, params["mu"], params["phi"], params["theta"], state["values"],
                    state["innov"], state["pred1"], state["work"], out, status)
