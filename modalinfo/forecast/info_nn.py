"""A nonlinear predictor over the inputs chosen by conditional MI (issue 21, item 3b).

:class:`InfoNNPredictor` is :class:`~modalinfo.forecast.InfoPredictor` (the same
greedy Gaussian-CMI choice of inputs and the same least-squares weights, per mode and
horizon) plus a one-hidden-layer tanh network on the same inputs, fitted to the linear
model's residual:

    x_hat[t + h, m] = (info forecast) + sum_f beta_f tanh(b_f + sum_k w_fk u_k),

with ``u_k = x_c[t - l_k, j_k] / s_{j_k}`` the chosen inputs scaled by their mode's
training standard deviation. The hidden weights ``w, b`` are random and fixed
(``w ~ N(0, 1 / K)``, ``b ~ N(0, 1)``, seeded per model): a random-feature network
(Rahimi & Recht 2008), whose output weights ``beta`` are a ridge regression, so the fit
is a linear solve, deterministic, with no training loop. The ridge penalty is chosen
per model on a hold-out (the last quarter of the training rows) among
``ridge_grid`` x rows, and ``beta = 0`` (the ``info`` forecast exactly) is kept when no
penalty lowers the hold-out error: the network is only used where it helps out of
sample on the training data.

What to expect: the selection and the weights are those of the best *linear* model
of the chosen inputs, so on a linear Gaussian process (AO telemetry is close to one)
the network has nothing to add and its hold-out test mostly switches it off
(``n_active_``); it can gain only where the future depends nonlinearly on the chosen
inputs (measured in ``benchmarks/RESULTS.md``).

Online and offline forecasts run the same numba kernel
(:func:`modalinfo.forecast._info_kernels.sparse_direct_rf_filter`, which calls the
linear predictor's kernel sample by sample), so they agree bit for bit.
"""

from __future__ import annotations

import numpy as np

from modalinfo.common.validation import check_int, check_real
from modalinfo.forecast._info_kernels import sparse_direct_rf_filter
from modalinfo.forecast.info import InfoPredictor

__all__ = ["InfoNNPredictor"]


class InfoNNPredictor(InfoPredictor):
    """The ``info`` predictor plus a random-feature tanh network on its inputs.

    Parameters
    ----------
    n_features : int
        Hidden tanh units per model, >= 1.
    ridge_grid : sequence of float
        Candidate ridge penalties per training row (each > 0); the hold-out picks one
        per model, or none (the linear forecast).
    holdout : float
        Fraction of the training rows held out to choose the penalty, in (0, 0.5].
    max_lag, max_inputs, selection, alpha, n_surrogates, seed, horizon, refit_every, window
        As :class:`~modalinfo.forecast.InfoPredictor`; ``seed`` also draws the hidden
        weights.

    Minimum samples: those of ``InfoPredictor`` plus ten rows per hidden unit.

    Attributes
    ----------
    n_active_ : numpy.ndarray of int, shape (H, M)
        1 where the model uses its network (hold-out gain), else 0.
    """

    def __init__(self, *, n_features: int = 32, ridge_grid=(1e-3, 1e-2, 1e-1, 1.0),
                 holdout: float = 0.25, max_lag: int = 10, max_inputs: int = 8,
                 selection: str = "ebic", alpha: float = 0.05, n_surrogates: int = 99,
                 seed: int = 0, horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        super().__init__(max_lag=max_lag, max_inputs=max_inputs, selection=selection,
                         alpha=alpha, n_surrogates=n_surrogates, seed=seed,
                         horizon=horizon, refit_every=refit_every, window=window)
        self.n_features = n_features
        self.ridge_grid = ridge_grid
        self.holdout = holdout

    def _check_nn(self) -> tuple[int, np.ndarray, float]:
        n_feat = check_int(self.n_features, "n_features", minimum=1)
        grid = np.atleast_1d(np.asarray(self.ridge_grid, dtype=float))
        if grid.ndim != 1 or grid.size == 0 or not np.all(np.isfinite(grid)) \
                or (grid <= 0).any():
            raise ValueError(f"`ridge_grid` must be a non-empty sequence of finite "
                             f"penalties > 0; got {self.ridge_grid!r}.")
        holdout = check_real(self.holdout, "holdout", minimum=0.0, maximum=0.5,
                             strict_min=True)
        return n_feat, grid, holdout

    def _min_samples_rule(self, n_modes: int) -> tuple[int, str]:
        n_lin, rule = super()._min_samples_rule(n_modes)
        n_feat = check_int(self.n_features, "n_features", minimum=1)
        return n_lin + 10 * n_feat, f"{rule} + 10 rows per hidden unit x {n_feat}"

    def _fit_params(self, X, previous, name):
        n_feat, grid, holdout = self._check_nn()
        p = super()._fit_params(X, previous, name)
        mu, src, lag, coef = p["mu"], p["src"], p["lag"], p["coef"]
        H, M, K = coef.shape
        max_lag = int(p["max_lag"][0])
        constant, _ = self._constant_columns(X)
        Xc = X - mu
        Xc[:, constant] = 0.0  # as the linear fit: a constant column is never an input
        scale = np.where(constant, 1.0, Xc.std(axis=0))
        origins = np.arange(max_lag - 1, X.shape[0] - H)
        n = origins.size
        n_fit = n - max(int(round(holdout * n)), 1)
        w = np.zeros((H, M, n_feat, K))
        b = np.zeros((H, M, n_feat))
        beta = np.zeros((H, M, n_feat))
        seeds = np.random.SeedSequence(int(self.seed)).spawn(H * M)
        for h in range(H):
            for m in range(M):
                used = np.flatnonzero(coef[h, m] != 0.0)
                if used.size == 0:
                    continue
                rng = np.random.default_rng(seeds[h * M + m])
                wf = rng.standard_normal((n_feat, used.size)) / np.sqrt(used.size)
                bf = rng.standard_normal(n_feat)
                lagged = Xc[origins[:, None] - lag[h, m, used][None, :], src[h, m, used]]
                resid = Xc[origins + h + 1, m] - lagged @ coef[h, m, used]
                phi = np.tanh(bf + (lagged / scale[src[h, m, used]]) @ wf.T)
                beta_hm = _ridge_on_holdout(phi, resid, n_fit, grid)
                if beta_hm is not None:
                    w[h, m][:, used] = wf
                    b[h, m] = bf
                    beta[h, m] = beta_hm
        p.update({"scale": scale, "w": w, "b": b, "beta": beta})
        return p

    def _init_state(self, params, horizon):
        state = super()._init_state(params, horizon)
        state["row"] = np.zeros((1, horizon, params["mu"].shape[0]))
        return state

    def _filter(self, params, state, X, out, status):
        sparse_direct_rf_filter(X, params["mu"], params["src"], params["lag"],
                                params["coef"], params["scale"], params["w"], params["b"],
                                params["beta"], state["values"], state["row"], out, status)

    @property
    def n_active_(self) -> np.ndarray:
        """``(H, M)`` 1 where a model uses its network, else 0."""
        self._check_fitted()
        return np.any(self.params_["beta"] != 0.0, axis=2).astype(np.int64)


def _ridge_on_holdout(phi: np.ndarray, y: np.ndarray, n_fit: int, grid: np.ndarray
                      ) -> np.ndarray | None:
    """Ridge weights of ``y`` on ``phi`` with the penalty of least hold-out error.

    The rows ``[:n_fit]`` fit and ``[n_fit:]`` score each penalty ``grid * n_fit``;
    returns None if none beats ``beta = 0`` on the hold-out, else the weights refitted
    on all rows with the chosen penalty (``grid * rows``).
    """
    F = phi.shape[1]
    best, best_err = None, float(np.mean(y[n_fit:] ** 2))
    G = phi[:n_fit].T @ phi[:n_fit]
    c = phi[:n_fit].T @ y[:n_fit]
    for lam in grid:
        beta = np.linalg.solve(G + lam * n_fit * np.eye(F), c)
        err = float(np.mean((y[n_fit:] - phi[n_fit:] @ beta) ** 2))
        if err < best_err:
            best, best_err = lam, err
    if best is None:
        return None
    n = phi.shape[0]
    return np.linalg.solve(phi.T @ phi + best * n * np.eye(F), phi.T @ y)
