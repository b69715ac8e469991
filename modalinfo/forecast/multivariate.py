"""Multivariate linear prediction: the recent history of all modes predicts each mode.

Beyond the paper. The batch form is the regularised least-squares predictor of
Guyon & Males (2017, "Adaptive prediction for wavefront control", the "empirical
orthogonal functions" predictor): a vector autoregression of order ``p``,
``x_hat[t + 1] = mu + sum_{i=1}^p A_i^T (x[t + 1 - i] - mu)``, whose ``p M x M``
coefficients solve the Tikhonov-regularised normal equations
``(Z^T Z + alpha diag(Z^T Z)) B = Z^T Y``: each lagged regressor is penalised in
proportion to its own sum of squares (ridge regression on standardised regressors,
Hastie, Tibshirani & Friedman 2009, section 3.4.1), so ``alpha`` is scale-free and the
forecast of every mode is unchanged when any one mode is expressed in other units (a
single ``lambda = alpha trace(Z^T Z) / (p M)`` shrank the lags of a mode of small
variance towards its mean). The recursive form updates ``B`` every step by recursive
least squares with forgetting factor ``lambda_f`` (memory ``1 / (1 - lambda_f)``
samples), starting from the batch solution.

``alpha="gcv"`` (the ``multivariate`` preset's) chooses ``alpha`` at each fit by
generalised cross-validation (Golub, Heath & Wahba 1979): the relative ridge is the
ordinary ridge ``(Z_s^T Z_s + alpha I)`` on the lags scaled to unit sum of squares
``Z_s``, so one SVD ``Z_s = U S V^T`` (taken from the QR factor of ``[Z_s, Y]`` by row
blocks, never forming the ``T x p M`` ``U``: ``_gcv_ridge``) gives, for every ``alpha``
of ``GCV_GRID`` (0 and ``10^-10 .. 10^0`` by half decades), the hat matrix's trace
``sum s^2 / (s^2 + alpha)`` and the residual, and the fit takes the ``alpha`` minimising
``GCV = n ||(I - H) Y||_F^2 / (n - tr H)^2`` (``n`` regression rows, one ``alpha``
shared by all modes; the smallest on a tie). ``alpha = 0`` (ordinary least squares) is a
candidate only where the scaled lags are well conditioned (smallest singular value at
least ``sqrt(eps)`` of the largest): a rank-deficient log (a mode duplicated or a
combination of others) gets the smallest positive ``alpha`` GCV prefers, never a
singular solve. The weights are then ``V diag(s / (s^2 + alpha)) U^T Y`` scaled back. A
fixed ``alpha = 1e-3`` shrinks the near-cancelling lag weights that forecast a smooth,
noise-free mode, and such a log's forecast falls back towards the mean (gain 0.3-0.7
over persistence where ``alpha = 0`` gains 48-933, fix48-c); GCV takes 0 there and
``1e-2`` / ``3e-3`` on Figure 5's closed-loop logs. The RLS form keeps a fixed ``alpha``
(its RLS matrix starts from the inverse of the regularised Gram matrix).
"""

from __future__ import annotations

import numpy as np

from modalinfo.common.validation import check_int, check_real
from modalinfo.forecast._kernels import rls_var_filter, var_filter
from modalinfo.forecast.base import Predictor

__all__ = ["GCV_GRID", "MultivariatePredictor", "RLSMultivariatePredictor"]

#: Relative ridges ``alpha = "gcv"`` chooses from: 0 and 10^-10 .. 10^0 by half decades.
GCV_GRID = (0.0, *(10.0 ** (0.5 * k) for k in range(-20, 1)))

#: ``alpha = 0`` is a GCV candidate only if the scaled lags' smallest singular value is
#: at least this fraction (``sqrt(eps)``, 1.5e-8) of the largest: beyond, the least-squares
#: weights amplify rounding by more than ``1 / sqrt(eps)``. Measured: 1.6e-5 - 2.0e-7 on
#: the shipped open-loop log and smooth synthetic logs (fix48-c), 2e-21 with a mode
#: duplicated.
_OLS_RCOND = float(np.sqrt(np.finfo(float).eps))

#: Elements (float64) of each row block :func:`_lag_qr` puts under its triangle (2 MiB,
#: whatever the number of columns; at least one row).
_QR_ELEMENTS = 2 ** 18

#: Block size of LAPACK's ``tpqrt`` (its ``T`` factor: ``nb x n``).
_QR_NB = 64


def _lagged(Xc: np.ndarray, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Regressors ``Z (T - p, p M)`` (lag 1 first) and targets ``Y (T - p, M)``."""
    n = Xc.shape[0]
    Z = np.concatenate([Xc[order - i : n - i] for i in range(1, order + 1)], axis=1)
    return Z, Xc[order:]


def _lag_qr(Z: np.ndarray, Y: np.ndarray, scale: np.ndarray, columns=slice(None),
            targets=slice(None)) -> np.ndarray:
    """``R (n, n)`` of the QR factorisation of ``[Z[:, columns] / scale, Y[:, targets]]``.

    ``n = k + M`` columns. Tall-skinny QR by row blocks: each block of ``max(1,
    _QR_ELEMENTS / n)`` rows is written (scaled, the chosen columns) into one
    Fortran-ordered buffer and folded into the ``n x n`` triangle by LAPACK's ``tpqrt``
    (the QR of a triangle stacked on a rectangle, Householder, both updated in place), so
    nothing of ``T`` rows is allocated beyond the caller's ``Z`` and ``Y``; backward
    stable as one QR of the whole matrix is (the Gram matrix ``Zs^T Zs`` would square the
    condition number, 8e5 on round 47's smooth log and 8e13-3e16 with a mode nearly or
    exactly repeated, and lose the small singular values GCV and the test for ``alpha =
    0`` read). The rows of ``R`` are those of any QR of the matrix up to their signs.

    fix49-b stacked the triangle on ``max(n, 2^18 / n)`` rows and factorised the whole
    ``2n x n`` block with ``geqrf`` (and copied the triangle out): beyond ``n = 512`` the
    block alone was ``16 n^2`` bytes (64 MB for the 400-mode latency fit's ``n = 2000``),
    tracemalloc's peak of ``_gcv_ridge`` 131 MB there; now the triangle (``8 n^2``), a
    2 MiB block and the ``tpqrt`` work arrays (fix50-b).
    """
    from scipy.linalg.lapack import dtpqrt

    n_rows = Z.shape[0]
    k = scale.size
    n = k + Y[:1, targets].shape[1]
    R = np.zeros((n, n), order="F")
    if n == 0:
        return R
    step = max(1, _QR_ELEMENTS // n)
    block = np.empty((min(step, n_rows), n), order="F")
    nb = min(n, _QR_NB)
    for start in range(0, n_rows, step):
        stop = min(start + step, n_rows)
        rows = block[: stop - start]  # the last block: a view, copied by the wrapper
        np.divide(Z[start:stop, columns], scale, out=rows[:, :k])
        rows[:, k:] = Y[start:stop, targets]
        R, _, _, info = dtpqrt(0, nb, R, rows, overwrite_a=1, overwrite_b=1)
        if info != 0:  # an argument LAPACK refuses: cannot happen with these shapes
            raise RuntimeError(f"LAPACK dtpqrt refused argument {-info}")
    return R


def _gcv_ridge(Z: np.ndarray, Y: np.ndarray, scale: np.ndarray | None = None,
               columns=slice(None), targets=slice(None)) -> tuple[float, np.ndarray]:
    """GCV's relative ridge and the weights on unit-norm lags ``Zs = Z / scale``.

    Returns ``alpha`` from ``GCV_GRID`` and ``Bs (k, M)``, the solution of
    ``(Zs^T Zs + alpha I) Bs = Zs^T Y`` (module notes). ``scale`` (k,): the norms of the
    columns ``Z[:, columns]`` (default 1: ``Z`` is already ``Zs``); ``Y[:, targets]``
    the targets (the regression's columns, taken row block by row block, never copied).

    The SVD ``Zs = U S V^T`` is never formed with its ``T x k`` ``U``: the QR factor of
    ``[Zs, Y]`` (:func:`_lag_qr`), ``R = [[R11, R12], [0, R22]]``, gives ``Zs = Q1 R11``,
    so the SVD of the ``k x k`` ``R11 = Ur S V^T`` has ``U = Q1 Ur``, ``U^T Y = Ur^T R12``,
    and the part of ``Y`` outside the span of the lags is ``||R22||_F^2``: computed
    without cancellation (not as ``||Y||^2 - ||U^T Y||^2``, which cancels where the lags
    forecast ``Y`` to 1e-5).
    """
    if scale is None:
        scale = np.ones(Z[:1, columns].shape[1])
    k = scale.size
    R = _lag_qr(Z, Y, scale, columns, targets)
    Ur, s, Vt = np.linalg.svd(R[:k, :k])
    uty = Ur.T @ R[:k, k:]
    rss_out = float(np.sum(R[k:, k:] ** 2))
    n = Y.shape[0]
    s2 = s * s
    well_conditioned = s.size and s[-1] >= _OLS_RCOND * s[0]
    best = (np.inf, None)
    for alpha in GCV_GRID:
        if alpha == 0.0 and not well_conditioned:
            continue
        f = s2 / (s2 + alpha) if alpha > 0 else np.ones_like(s)
        rss = rss_out + float(np.sum(((1.0 - f)[:, None] * uty) ** 2))
        dof = n - float(np.sum(f))
        score = n * rss / (dof * dof)
        if score < best[0]:
            best = (score, alpha)
    alpha = best[1]
    if alpha is None:  # every score NaN / inf: cannot happen on finite, varying lags
        alpha = GCV_GRID[-1]
    weight = s / (s2 + alpha)
    return alpha, Vt.T @ (weight[:, None] * uty)


class MultivariatePredictor(Predictor):
    """Batch regularised vector-autoregressive predictor (all modes -> each mode).

    Parameters
    ----------
    order : int
        Number of past samples ``p`` of every mode in the regression.
    alpha : float or "gcv"
        Relative Tikhonov regularisation (see module notes), >= 0; ``"gcv"``: chosen at
        each fit (and refit) by generalised cross-validation from ``GCV_GRID``
        (0 and ``10^-10 .. 1`` by half decades; module notes).
    horizon : int
        Number of steps forecast by ``update``.
    refit_every, window : int or None
        Refit policy.

    Minimum samples: ``p + 10 p M`` (ten regression rows per coefficient of one
    mode's equation, which has ``p M``), e.g. 84 for VAR(4) on 2 modes and 1084 on
    27. A constant column (range at most 1e-12 of its magnitude: a zeroed or dead
    mode) is left out of the regression and forecast as the constant.

    Attributes
    ----------
    coef_ : numpy.ndarray, shape (p, M, M)
        ``coef_[i, k, m]``: weight of lag ``i + 1`` of mode ``k`` in the forecast of
        mode ``m``.
    mean_ : numpy.ndarray, shape (M,)
    alpha_ : float
        The relative ridge in force: ``alpha``, or GCV's choice at ``fit`` (or at the
        last refit of the online pass, ``update`` with ``refit_every``).
    """

    _multivariate = True

    def __init__(self, *, order: int = 2, alpha: float | str = 1e-3, horizon: int = 10,
                 refit_every: int | None = None, window: int | None = None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)
        self.order = order
        self.alpha = alpha

    def _min_samples_rule(self, n_modes: int) -> tuple[int, str]:
        order = check_int(self.order, "order", minimum=1)
        n_coef = order * n_modes
        return order + 10 * n_coef, (f"order {order} + 10 regression rows per coefficient "
                                     f"x {n_coef} coefficients per mode (order x "
                                     f"{n_modes} modes)")

    def _solve(self, X: np.ndarray, name: str):
        order = check_int(self.order, "order", minimum=1)
        alpha = self._check_alpha()
        constant, value = self._constant_columns(X)
        mu = np.where(constant, value, X.mean(axis=0))
        Xc = X - mu
        Xc[:, constant] = 0.0  # exactly 0 for a constant; a near-constant is not modelled
        Z, Y = _lagged(Xc, order)
        G = Z.T @ Z
        n_modes = X.shape[1]
        # constant modes are left out of the regression: no weight to or from them
        keep = np.tile(~constant, order)
        # each regressor's ridge is alpha times its own sum of squares: the solution is
        # then equivariant under a change of units of any one mode (a common ridge
        # lambda I shrinks a mode of small variance to its mean, whatever alpha)
        B = np.zeros((G.shape[0], n_modes))
        gcv = alpha == "gcv"
        if gcv:
            alpha = 0.0  # every mode constant: nothing is regressed, nothing shrunk
            if keep.any():
                # the relative ridge is the ordinary one on unit-norm lag columns
                norm = np.sqrt(np.diag(G)[keep])
                every = keep.all()  # a slice takes views of the row blocks, a mask copies
                alpha, Bs = _gcv_ridge(Z, Y, norm, slice(None) if every else keep,
                                       slice(None) if every else ~constant)
                B[np.ix_(keep, ~constant)] = Bs / norm[:, None]
        Greg = G + alpha * np.diag(np.diag(G))
        if not gcv and keep.any():
            B[np.ix_(keep, ~constant)] = np.linalg.solve(
                Greg[np.ix_(keep, keep)], (Z.T @ Y)[np.ix_(keep, ~constant)])
        if not keep.all():
            # decouple the lags of constant modes in the Gram matrix the RLS starts from:
            # their regressors are 0, so any positive diagonal leaves their weights at 0
            drop = np.flatnonzero(~keep)
            Greg[drop, :] = 0.0
            Greg[:, drop] = 0.0
            Greg[drop, drop] = 1.0
        coef = np.ascontiguousarray(B.reshape(order, n_modes, n_modes))
        return mu, coef, Greg, Z.shape[0], alpha

    def _check_alpha(self) -> float | str:
        if isinstance(self.alpha, str):
            if self.alpha != "gcv":
                raise ValueError(f"`alpha` must be a number >= 0 or 'gcv'; got "
                                 f"{self.alpha!r}.")
            return self.alpha
        return check_real(self.alpha, "alpha", minimum=0.0)

    def _fit_params(self, X, previous, name):
        mu, coef, _, _, alpha = self._solve(X, name)
        return {"mu": mu, "coef": coef, "alpha": alpha}

    def fit_bytes(self, n_samples: int, n_modes: int) -> int:
        """Upper estimate of the memory ``fit`` allocates at its peak [bytes].

        The lagged design ``(T, order x M)``, the targets and the centred history
        (``order + 2`` float64 copies of the history) and two ``(order M)^2`` normal
        matrices. tracemalloc's peak: 3.0-3.2, 5.1-5.7 and 9.4-11.1 copies at orders
        2, 4 and 8 (3,000 and 8,000 samples of 10 and 27 modes, left19-est). With
        ``alpha="gcv"`` the QR factorisation of the scaled lags and targets by row blocks
        (``_lag_qr``) adds a block of ``min(T, max(1, 2^18 / n))`` rows of ``n = (order +
        1) M`` columns (2 MiB), the ``n x n`` triangle and ``tpqrt``'s ``64 x n`` factor,
        counted here as two triangles, whatever ``T`` (fix50-b; fix49-b's ``2n x n`` block
        was ``16 n^2`` bytes beyond ``n = 512``). tracemalloc's peak 3.3, 5.3
        and 9.5 copies of the history at orders 2, 4 and 8 on 40,000 samples of 27 modes
        (fixed alpha: 3.0, 5.1, 9.2), 6.6, 10.6 and 18.6 on 3,000 of 10, where the block
        is the whole history (fix49-b; stop 55's SVD of the scaled lags added ``2 order +
        3`` copies of the history whatever ``T``: 16.2-16.4 at order 4, fix48-d).
        """
        k = self.order * n_modes
        base = 8 * ((self.order + 2) * n_samples * n_modes + 2 * k * k)
        if not isinstance(self.alpha, str):
            return base
        n = k + n_modes
        rows = min(n_samples, max(1, _QR_ELEMENTS // n))
        return base + 8 * (rows * n + 2 * n * n)

    def _memory(self, params):
        return int(params["coef"].shape[0])

    def _init_state(self, params, horizon):
        order, n_modes, _ = params["coef"].shape
        return {"values": np.zeros((order, n_modes)), "work": np.zeros((horizon, n_modes))}

    def _filter(self, params, state, X, out, status):
        var_filter(X, params["mu"], params["coef"], state["values"], state["work"], out,
                   status)

    @property
    def coef_(self) -> np.ndarray:
        """``(p, M, M)`` lag weights."""
        self._check_fitted()
        return self.params_["coef"]

    @property
    def mean_(self) -> np.ndarray:
        """``(M,)`` means removed before the regression."""
        self._check_fitted()
        return self.params_["mu"]

    @property
    def alpha_(self) -> float:
        """Relative ridge in force (``alpha``, or GCV's choice at the last (re)fit).

        GCV chooses at ``fit`` and again at each refit of the online pass (``update``
        with ``refit_every``).
        """
        self._check_fitted()
        run = self.__dict__.get("_run")
        params = self.params_ if run is None else run.params
        return float(params["alpha"])


class RLSMultivariatePredictor(MultivariatePredictor):
    """Vector-autoregressive predictor adapted every step by recursive least squares.

    ``fit`` solves the batch problem of :class:`MultivariatePredictor`; ``reset``
    restores that solution and ``update`` then adapts the weights with each new
    sample (exponentially weighted least squares, forgetting factor ``forgetting``).
    The RLS matrix starts as the inverse of the regularised Gram matrix per sample
    times ``1 / (1 - forgetting)`` (the Gram matrix of an exponential window of the
    same statistics), so the first updates are neither over- nor under-confident.
    Cost per step: ``O((p M)^2 + p M^2 H)``.

    Parameters
    ----------
    order : int
        Past samples ``p`` of every mode.
    alpha : float
        Relative Tikhonov regularisation of the initial batch solution (a number:
        ``"gcv"`` is refused, the ``rls`` preset keeps 1e-3).
    forgetting : float
        Forgetting factor in (0, 1]; 1 is ordinary (growing-memory) RLS.
    horizon : int
        Number of steps forecast by ``update``.
    refit_every, window : int or None
        Refit policy (re-initialises the RLS from a batch solve on the window).
    """

    def __init__(self, *, order: int = 2, alpha: float = 1e-3, forgetting: float = 0.999,
                 horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        super().__init__(order=order, alpha=alpha, horizon=horizon,
                         refit_every=refit_every, window=window)
        self.forgetting = forgetting

    def _fit_params(self, X, previous, name):
        lam = check_real(self.forgetting, "forgetting", minimum=0.0, maximum=1.0,
                         strict_min=True)
        mu, coef, Greg, n, alpha = self._solve(X, name)
        memory = n if lam == 1.0 else min(n, 1.0 / (1.0 - lam))
        gain_inv = np.linalg.inv(Greg * (memory / n))
        gain_inv = 0.5 * (gain_inv + gain_inv.T)
        return {"mu": mu, "coef": coef, "gain_inv": np.ascontiguousarray(gain_inv),
                "forgetting": lam, "alpha": alpha}

    def _check_alpha(self) -> float:
        if isinstance(self.alpha, str):
            raise ValueError(
                f"`alpha` must be a number >= 0 for {type(self).__name__} (its RLS matrix "
                f"starts from the inverse of the regularised Gram matrix, which alpha 0 on "
                f"collinear lags makes singular); got {self.alpha!r}. 'gcv' is "
                f"MultivariatePredictor's.")
        return check_real(self.alpha, "alpha", minimum=0.0)

    def _init_state(self, params, horizon):
        order, n_modes, _ = params["coef"].shape
        dim = order * n_modes
        return {
            "coef": params["coef"].copy(),
            "gain_inv": params["gain_inv"].copy(),
            "values": np.zeros((order, n_modes)),
            "n_seen": np.zeros(1, dtype=np.int64),
            "zvec": np.zeros(dim),
            "pz": np.zeros(dim),
            "work": np.zeros((horizon, n_modes)),
        }

    def _filter(self, params, state, X, out, status):
        if state.get("params") is not params:
            # a refit replaced the parameters: restart the adaptation from them
            if "params" in state:
                state["coef"][...] = params["coef"]
                state["gain_inv"][...] = params["gain_inv"]
            state["params"] = params
        rls_var_filter(X, params["mu"], state["coef"], state["gain_inv"],
                       params["forgetting"], state["values"], state["n_seen"],
                       state["zvec"], state["pz"], state["work"], out, status)

    @property
    def adapted_coef_(self) -> np.ndarray:
        """``(p, M, M)`` weights after the online updates since the last reset."""
        self._check_fitted()
        return self._run.state["coef"].copy()
