"""Shared machinery of the univariate linear recursions (persistence, linear, ARMA)."""

from __future__ import annotations

import numpy as np

from modalinfo.forecast._kernels import arma_filter
from modalinfo.forecast.base import Predictor


def _pack(params: dict) -> tuple[np.ndarray, int, int]:
    """Kernel layout ``(M, 2 + P + Q)``: centring, intercept, AR then MA coefficients.

    ``params["c"]`` (the intercept, :func:`~modalinfo.forecast._kernels.arma_filter`)
    is optional: a model about its mean ``mu`` has none (0).
    """
    coef = params.get("_packed")
    if coef is None:
        intercept = params.get("c")
        if intercept is None:
            intercept = np.zeros_like(params["mu"])
        coef = np.ascontiguousarray(np.column_stack(
            [params["mu"], intercept, params["phi"], params["theta"]]))
        params["_packed"] = coef
    return coef, params["phi"].shape[1], params["theta"].shape[1]


class _LinearRecursion(Predictor):
    """A predictor run by :func:`~modalinfo.forecast._kernels.arma_filter`.

    ``_fit_params`` must return ``mu (M,)``, ``phi (M, P)`` and ``theta (M, Q)``, and
    may return an intercept ``c (M,)`` of the recursion about ``mu`` (default 0).
    """

    def _memory(self, params: dict) -> int:
        return int(params["phi"].shape[1])  # the AR lags (MA innovations start at 0)

    def _check_layout(self, params: dict, n_modes: int, who: str) -> None:
        # the kernel reads mu, c (M,), phi (M, P), theta (M, Q) without bounds checks
        shapes = {"mu": 1, "phi": 2, "theta": 2, "c": 1}
        for key, ndim in shapes.items():
            if key == "c" and params.get("c") is None:
                continue
            if key not in params:
                raise ValueError(f"{who} must return the parameter {key!r} (mu (M,), phi "
                                 "(M, P), theta (M, Q), optional c (M,)).")
            shape = np.shape(params[key])
            if len(shape) != ndim or shape[0] != n_modes:
                want = "(M,)" if ndim == 1 else "(M, k)"
                raise ValueError(f"{who} returned {key!r} of shape {shape}; the recursion "
                                 f"reads {want} with M = {n_modes} modes.")

    def _init_state(self, params: dict, horizon: int) -> dict:
        n_modes, n_ar = params["phi"].shape
        n_ma = params["theta"].shape[1]
        return {"state": np.zeros((n_modes, n_ar + n_ma + 1)), "work": np.zeros(horizon)}

    def _filter(self, params, state, X, out, status):
        coef, n_ar, n_ma = _pack(params)
        arma_filter(X, coef, n_ar, n_ma, state["state"], state["work"], out, status)

    def _step_function(self, params, state, out, status):
        coef, n_ar, n_ma = _pack(params)
        st, work = state["state"], state["work"]

        def step(X):
            arma_filter(X, coef, n_ar, n_ma, st, work, out, status)

        return step
