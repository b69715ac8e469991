"""Linear extrapolation from the last two samples (the paper's linear predictor)."""

from __future__ import annotations

import numpy as np

from modalinfo.common.validation import check_real
from modalinfo.forecast._univariate import _LinearRecursion

__all__ = ["LinearPredictor"]


class LinearPredictor(_LinearRecursion):
    """``x_hat[n + 1] = a x[n] + b x[n - 1]`` (``+ c`` when fitted), iterated for h > 1.

    With the paper's fixed weights ``a = 2, b = -1`` this extrapolates the last
    slope: ``x_hat[n + h] = x[n] + h (x[n] - x[n - 1])``. With ``fit_weights=True``
    ``a``, ``b`` and an intercept ``c`` are fitted per mode by least squares on the
    training history, ``x[t] = c + a x[t - 1] + b x[t - 2]`` (statsmodels'
    ``AutoReg(lags=2, trend="c")``): exact on a noise-free law about 0 (``c = 0``
    fitted) and translation-invariant, so a static offset of a mode costs no skill.
    The fit and the recursion run about the training mean (``c`` is the intercept
    about it, added at every step as it is, never turned into a mean
    ``c / (1 - a - b)``, which is ill-conditioned near a random walk). Without the
    intercept (before fix 41-a) an offset pulled ``a + b`` toward 1: on an AR(1) 0.9
    mode of 1e-3 rad the h = 5 skill against persistence fell from 1.117 to 1.002
    with a 1e6 rad offset (round 40 PART a, S01); with it, 1.112 at 0, 1e3 and 1e6
    rad alike (docs/ADVERSARIAL.md, "Fixes 41-a").

    It beats persistence when increments are correlated (a smooth series) and loses
    when they are not: on an AR(1) series with coefficient near 1 the one-step error
    is ``e[n+1] + (e[n] - ...)``, about twice the innovation variance.

    Minimum samples with ``fit_weights=True``: 32 (ten least-squares rows per
    fitted parameter, after the two lags: ``a``, ``b``, ``c``); with fixed weights, 1.
    A constant column (range at most 1e-12 of its magnitude) gets no fitted weights:
    it is forecast as the constant (the fixed weights extrapolate a constant exactly
    as well).

    Parameters
    ----------
    a, b : float
        Fixed weights (used when ``fit_weights`` is False). Defaults: the paper's
        ``a = 2, b = -1``.
    fit_weights : bool
        Fit ``a``, ``b`` and the intercept ``c`` by least squares instead.
    horizon : int
        Number of steps forecast by ``update``.
    refit_every, window : int or None
        Refit policy (only meaningful with ``fit_weights=True``).

    Attributes
    ----------
    coef_ : numpy.ndarray, shape (M, 2)
        ``(a, b)`` per mode, as fitted (refits during a run do not change it).
    intercept_ : numpy.ndarray, shape (M,)
        ``c`` per mode (0 with fixed weights), as fitted.
    """

    def __init__(self, *, a: float = 2.0, b: float = -1.0, fit_weights: bool = False,
                 horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)
        self.a = a
        self.b = b
        self.fit_weights = fit_weights

    def _learns_from_data(self) -> bool:
        return bool(self.fit_weights)  # fixed weights: any data serve (check_fed)

    def _min_samples_rule(self, n_modes: int) -> tuple[int, str]:
        if self.fit_weights:
            return 32, ("2 lags + 10 regression rows per parameter x 3 parameters "
                        "(a, b, intercept)")
        return 1, "fixed weights, nothing to estimate"

    def _fit_params(self, X, previous, name):
        n_modes = X.shape[1]
        mu = np.zeros(n_modes)
        intercept = np.zeros(n_modes)
        if self.fit_weights:
            constant, value = self._constant_columns(X)
            coef = np.zeros((n_modes, 2))
            for m in range(n_modes):
                if constant[m]:  # forecast the constant: mu + 0 (x - mu)
                    mu[m] = value[m]
                    continue
                # about the training mean (well-conditioned under an offset). The
                # intercept column is eliminated (Frisch-Waugh): centring the target and
                # each lag column by its own mean gives the same (a, b) as the column of
                # ones and keeps the fit homogeneous in the units (2^k scalings: same bits)
                mu[m] = X[:, m].mean()
                y = X[:, m] - mu[m]
                cols = (y[2:], y[1:-1], y[:-2])
                means = [col.mean() for col in cols]
                design = np.column_stack([cols[1] - means[1], cols[2] - means[2]])
                coef[m] = np.linalg.lstsq(design, cols[0] - means[0], rcond=None)[0]
                intercept[m] = means[0] - coef[m, 0] * means[1] - coef[m, 1] * means[2]
        else:
            a = check_real(self.a, "a")
            b = check_real(self.b, "b")
            coef = np.tile([a, b], (n_modes, 1))
        return {"mu": mu, "c": intercept, "phi": np.ascontiguousarray(coef),
                "theta": np.zeros((n_modes, 0))}

    @property
    def coef_(self) -> np.ndarray:
        """``(M, 2)`` weights ``(a, b)`` per mode."""
        self._check_fitted()
        return self.params_["phi"]

    @property
    def intercept_(self) -> np.ndarray:
        """``(M,)`` intercept ``c`` of ``x[t] = c + a x[t - 1] + b x[t - 2]`` per mode."""
        self._check_fitted()
        p = self.params_
        return p["c"] + p["mu"] * (1.0 - p["phi"].sum(axis=1))
