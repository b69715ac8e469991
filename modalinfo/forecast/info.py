"""A sparse direct linear predictor whose inputs are chosen by conditional MI.

For each mode m and each horizon h = 1..H, the inputs are the past values (mode j,
lag l) chosen by the greedy Gaussian-CMI search of
:mod:`modalinfo.information.selection` over lags 0 .. max_lag - 1 of every mode, and
the forecast is their least-squares combination,

    x_hat[t + h, m] = mu_m + sum_k w_hmk (x[t - l_hmk, j_hmk] - mu_j),

one direct model per horizon (no iteration). The Gaussian CMI gain of an input is
``0.5 ln(RSS without / RSS with)`` of this very regression, so the search adds the
input that most reduces the forecast's residual variance, and stops when the
reduction is no longer worth an input:

- ``selection="ebic"`` (default): while ``2 n gain > ln n + 2 ln m`` (extended BIC,
  Chen & Chen 2008, for a greedy search over m candidates), computed from one Gram
  matrix of the candidates shared by every mode and horizon (fast: a 27-mode log
  with 10 lags fits 270 models in seconds);
- ``selection="surrogate"``: the maximum-statistic time-shift surrogate test of
  :func:`~modalinfo.information.select_inputs` at level ``alpha`` per step
  (``n_surrogates`` per step; slower by about that factor).

Candidates at thousands of modes (``candidates=``, :mod:`modalinfo.information.candidates`).
With every mode a candidate, the search holds an ``(M L) x (M L)`` Gram (1,500 modes
x 10 lags: 1.8 GB, ~10^12 multiply-adds). ``candidates="radial"`` lets a target's
inputs be the lags of the modes within ``radial_width`` radial orders of it (frozen
flow couples modes of similar radial order; Conan, Rousset & Madec 1995), or an
explicit ``(M, M)`` mask ``allowed[j, i]`` (e.g. a DM's neighbours). The targets that
share a candidate set share one Gram of its columns. The extended-BIC penalty stays
that of the *whole* family (m = every non-constant mode and lag), so the restriction
changes no decision the unrestricted search would take: whenever the unrestricted
search's inputs for a target all lie in the target's restricted set, the restricted
search chooses the same inputs, in the same order (the greedy maximum over a subset
that holds the overall maximum is that maximum, and the stop compares the same best
gain with the same penalty); otherwise it chooses the best inputs within the set.
(``selection="surrogate"`` tests each step over the restricted candidates instead.)

Beyond the paper (its predictors are univariate). Compare with
:class:`~modalinfo.forecast.MultivariatePredictor`, which uses every mode at every lag.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from modalinfo.common.validation import check_choice, check_int, check_real
from modalinfo.forecast._info_kernels import sparse_direct_filter
from modalinfo.forecast.base import Predictor, check_horizon
from modalinfo.information.candidates import RADIAL_WIDTH, candidate_mask
from modalinfo.information.conditional import _estimator
from modalinfo.information.resampling import auto_block_length
from modalinfo.information.selection import (
    _greedy_search,
    _unit_columns,
    greedy_gaussian_gram,
    lagged_candidates,
    unit_candidates,
)

__all__ = ["InfoPredictor"]



def ebic_penalty(n: int, m: int) -> float:
    """Return the extended-BIC price of one more input: ``ln n + 2 ln m`` [nats x 2 n].

    Chen & Chen (2008, Biometrika 95, 759), EBIC with gamma = 1 for a search over ``m``
    candidates on ``n`` samples: an input enters while ``2 n gain`` exceeds it. The
    prior term ``2 ln C(m, k)`` of k inputs is taken at its bound ``2 k ln m``
    (``C(m, k) <= m^k``), so each input pays ``2 ln m``: the stricter price, the same for
    every step of the greedy search. ``m`` below 1 counts as 1.
    """
    return math.log(n) + 2.0 * math.log(max(m, 1))

class InfoPredictor(Predictor):
    """Sparse direct linear forecasts over inputs chosen by conditional MI.

    Parameters
    ----------
    max_lag : int
        Candidate lags 0 .. max_lag - 1 of every mode [samples], >= 1.
    max_inputs : int
        Budget of inputs per mode and horizon, >= 1.
    selection : {"ebic", "surrogate"}
        Stopping rule of the greedy search (see the module notes).
    alpha : float
        Family-wise level per step for ``selection="surrogate"``.
    n_surrogates : int
        Surrogates per step for ``selection="surrogate"`` (>= 1 / alpha - 1).
    seed : int
        Seed of the surrogate shifts (the fit is reproducible).
    horizon : int
        Number of steps H; one model per horizon 1..H is fitted, and forecasts beyond
        H are refused.
    refit_every, window : int or None
        Refit policy.
    candidates : {"all", "radial"} or array_like of bool, shape (M, M)
        Candidate sources of each mode (module notes): every mode (default), those
        within ``radial_width`` radial orders (read from ``mode_labels``), or an explicit
        mask ``allowed[j, i]`` (source j may inform mode i).
    radial_width : int
        Largest radial-order difference of ``candidates="radial"`` (default 2).
    mode_labels : sequence of str, optional
        Labels of the fitted columns for ``candidates="radial"`` (``"Z<j>"`` Noll or
        ``"KL<k>"``); default ``Z2, Z3, ...`` (the first modes after piston, as
        :class:`~modalinfo.telemetry.ModalLog` numbers an unlabelled log).

    Minimum samples: ``max_lag + horizon + 10 max_inputs + 10`` (ten regression rows
    per weight, after the lags and the horizon). A constant column (range at most
    1e-12 of its magnitude) is neither an input nor modelled: it is forecast as the
    constant.

    Attributes
    ----------
    n_inputs_ : numpy.ndarray of int, shape (H, M)
        Number of inputs of each model.
    mean_ : numpy.ndarray, shape (M,)
        Means removed before the regressions.
    """

    _multivariate = True

    def __init__(self, *, max_lag: int = 10, max_inputs: int = 8, selection: str = "ebic",
                 alpha: float = 0.05, n_surrogates: int = 99, seed: int = 0,
                 horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None, candidates: Any = "all",
                 radial_width: int = RADIAL_WIDTH,
                 mode_labels: Sequence[str] | None = None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)
        self.candidates = candidates
        self.radial_width = radial_width
        self.mode_labels = mode_labels
        self.max_lag = max_lag
        self.max_inputs = max_inputs
        self.selection = selection
        self.alpha = alpha
        self.n_surrogates = n_surrogates
        self.seed = seed


    def fit_bytes(self, n_samples: int, n_modes: int) -> int:
        """Upper estimate of the memory ``fit`` allocates at its peak [bytes].

        ``4 max_lag + 10`` float64 copies of the history (what the CMI selection
        builds from the lagged history): tracemalloc's peak of ``fit`` is 21.1, 40.9
        and 80.4 copies at ``max_lag`` 5, 10 and 20 (3,000 samples of 4 and 10 modes)
        and up to 42.3 at horizon 1; within ``evaluate`` it grows by 45.5 copies per
        training frame and mode (3,000-6,000 training frames of 4 modes, left19-est).
        """
        return 8 * (4 * self.max_lag + 10) * n_samples * n_modes

    def _min_samples_rule(self, n_modes: int) -> tuple[int, str]:
        max_lag = check_int(self.max_lag, "max_lag", minimum=1)
        k = check_int(self.max_inputs, "max_inputs", minimum=1)
        h = check_horizon(self.horizon)
        return (max_lag + h + 10 * k + 10,
                f"max_lag {max_lag} + horizon {h} + 10 regression rows per weight x "
                f"{k} inputs + 10")

    def _fit_params(self, X, previous, name):
        max_lag = check_int(self.max_lag, "max_lag", minimum=1)
        k_max = check_int(self.max_inputs, "max_inputs", minimum=1)
        H = check_horizon(self.horizon)
        selection = check_choice(self.selection, "selection", ("ebic", "surrogate"))
        alpha = check_real(self.alpha, "alpha", minimum=0.0, maximum=1.0, strict_min=True,
                           strict_max=True)
        n_surr = check_int(self.n_surrogates, "n_surrogates", minimum=1)
        seed = check_int(self.seed, "seed", minimum=0)
        n_modes = X.shape[1]
        labels = ([f"Z{j}" for j in range(2, n_modes + 2)] if self.mode_labels is None
                  else [str(v) for v in self.mode_labels])
        if len(labels) != n_modes:
            raise ValueError(f"`mode_labels` must name the {n_modes} fitted columns; got "
                             f"{len(labels)} labels.")
        twice = sorted({s for s in labels if labels.count(s) > 1})
        if twice:  # two columns of one mode: the radial mask was built for other columns
            raise ValueError(f"`mode_labels` must name each column once; {twice} appear "
                             "more than once.")
        allowed = candidate_mask(labels, self.candidates, self.radial_width)
        constant, value = self._constant_columns(X)
        mu = np.where(constant, value, X.mean(axis=0))
        Xc = X - mu
        Xc[:, constant] = 0.0
        if allowed is not None:
            return self._fit_restricted(Xc, mu, constant, allowed, max_lag, k_max, H,
                                        selection, alpha, n_surr, seed)
        # the same origins for every horizon, so one Gram serves all models
        origins, C, cols = lagged_candidates(Xc, H, max_lag)
        n = origins.shape[0]
        Cu, alive = unit_candidates(C)
        m = int(alive.sum())
        src = np.zeros((H, n_modes, k_max), dtype=np.int64)
        lag = np.zeros((H, n_modes, k_max), dtype=np.int64)
        coef = np.zeros((H, n_modes, k_max))
        G = penalty = est = rng = None
        if selection == "ebic":
            G = Cu.T @ Cu
            penalty = ebic_penalty(n, m)
        else:
            rng = np.random.default_rng(seed)
            est = _estimator("gaussian", "nats", {})
        for h in range(1, H + 1):
            Y = Xc[origins + h]
            if selection == "ebic":
                Yu, _ = _unit_columns(Y)
                CY = Cu.T @ Yu
            for mode in range(n_modes):
                if constant[mode]:
                    continue
                y = Y[:, mode]
                fit = _fit_target(y, CY[:, mode] if selection == "ebic" else None, C, Cu,
                                  alive, selection, G, penalty, est, alpha, n_surr, k_max,
                                  rng)
                if fit is None:
                    continue
                chosen, w = fit
                k = len(chosen)
                src[h - 1, mode, :k] = cols[chosen, 0]
                lag[h - 1, mode, :k] = cols[chosen, 1]
                coef[h - 1, mode, :k] = w
        return {"mu": mu, "src": src, "lag": lag, "coef": coef,
                "max_lag": np.array([max_lag])}

    def _fit_restricted(self, Xc, mu, constant, allowed, max_lag, k_max, H, selection,
                        alpha, n_surr, seed):
        """Fit with each mode's candidates restricted to ``allowed[:, mode]``.

        The targets that share a candidate set form a group, searched on that set's
        columns in the unrestricted order (lag-major, modes ascending), with the EBIC
        penalty of the whole family (module notes). The modes that enter the same
        groups form an *atom* (for ``"radial"``: one radial order); each group's Gram is
        assembled from atom-by-atom blocks, each computed once and dropped after the
        last group that needs it (neighbouring radial groups share most of their atoms).
        """
        T, n_modes = Xc.shape
        origins = np.arange(max_lag - 1, T - H)
        n = origins.shape[0]
        # the lag-l block of every mode, as the columns l M + j of lagged_candidates
        blocks = [Xc[max_lag - 1 - lag : T - H - lag] for lag in range(max_lag)]
        keys, group = np.unique(allowed.T, axis=0, return_inverse=True)
        group = group.ravel()
        first = np.array([np.flatnonzero(k)[0] for k in keys])
        order = np.argsort(first, kind="stable")  # neighbouring groups one after another
        _, atom_of = np.unique(keys.T, axis=0, return_inverse=True)
        atom_of = atom_of.ravel()
        atom_modes = [np.flatnonzero(atom_of == a) for a in range(atom_of.max() + 1)]
        group_atoms = [np.unique(atom_of[keys[g]]) for g in order]
        last_use = {}
        for step, atoms in enumerate(group_atoms):
            for a in atoms:
                last_use[int(a)] = step
        # per atom: raw and unit lagged columns (lag-major over its modes) and alive mask
        atom_cols: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        m = 0
        for a, modes in enumerate(atom_modes):
            Ca = np.ascontiguousarray(np.concatenate([b[:, modes] for b in blocks], axis=1))
            Cua, alive_a = unit_candidates(Ca)
            atom_cols[a] = (Ca, Cua, alive_a)
            m += int(alive_a.sum())
        penalty = ebic_penalty(n, m)
        src = np.zeros((H, n_modes, k_max), dtype=np.int64)
        lag = np.zeros((H, n_modes, k_max), dtype=np.int64)
        coef = np.zeros((H, n_modes, k_max))
        rng = np.random.default_rng(seed)
        est = _estimator("gaussian", "nats", {}) if selection == "surrogate" else None
        G = None
        gram_blocks: dict[tuple[int, int], np.ndarray] = {}
        for step, g in enumerate(order):
            atoms = [int(a) for a in group_atoms[step]]
            targets = np.flatnonzero((group == g) & ~constant)
            if targets.size:
                # columns in atom order, then the permutation to the unrestricted order
                cat = np.concatenate([[(j, lg) for lg in range(max_lag)
                                       for j in atom_modes[a]] for a in atoms])
                perm = np.lexsort((cat[:, 0], cat[:, 1]))  # lag-major, modes ascending
                cols = cat[perm].astype(np.int64)
                C = np.concatenate([atom_cols[a][0] for a in atoms], axis=1)[:, perm]
                Cu = np.concatenate([atom_cols[a][1] for a in atoms], axis=1)[:, perm]
                alive = np.concatenate([atom_cols[a][2] for a in atoms])[perm]
                if selection == "ebic":
                    G = self._group_gram(atoms, atom_cols, gram_blocks)[np.ix_(perm, perm)]
            for h in range(1, H + 1) if targets.size else ():
                Y = np.ascontiguousarray(Xc[max_lag - 1 + h : T - H + h, targets])
                if selection == "ebic":
                    Yu, _ = _unit_columns(Y)
                    CY = Cu.T @ Yu
                for t, mode in enumerate(targets):
                    y = Y[:, t]
                    fit = _fit_target(y, CY[:, t] if selection == "ebic" else None, C, Cu,
                                      alive, selection, G, penalty, est, alpha, n_surr,
                                      k_max, rng)
                    if fit is None:
                        continue
                    chosen, w = fit
                    k = len(chosen)
                    src[h - 1, mode, :k] = cols[chosen, 0]
                    lag[h - 1, mode, :k] = cols[chosen, 1]
                    coef[h - 1, mode, :k] = w
            done = {a for a in atoms if last_use[a] == step}  # no later group needs them
            for key in [key for key in gram_blocks if done & set(key)]:
                del gram_blocks[key]
            for a in done:
                del atom_cols[a]
        return {"mu": mu, "src": src, "lag": lag, "coef": coef,
                "max_lag": np.array([max_lag])}

    @staticmethod
    def _group_gram(atoms, atom_cols, cache) -> np.ndarray:
        """Gram of the unit columns of ``atoms`` (in atom order) from cached atom blocks."""
        sizes = [atom_cols[a][1].shape[1] for a in atoms]
        edges = np.concatenate([[0], np.cumsum(sizes)])
        G = np.empty((edges[-1], edges[-1]))
        for p, a in enumerate(atoms):
            for q in range(p, len(atoms)):
                b = atoms[q]
                key = (min(a, b), max(a, b))
                if key not in cache:
                    Ua, Ub = atom_cols[key[0]][1], atom_cols[key[1]][1]
                    cache[key] = Ua.T @ Ua if key[0] == key[1] else Ua.T @ Ub
                blk = cache[key] if a <= b else cache[key].T
                G[edges[p]:edges[p + 1], edges[q]:edges[q + 1]] = blk
                if q != p:
                    G[edges[q]:edges[q + 1], edges[p]:edges[p + 1]] = blk.T
        return G

    def _memory(self, params):
        return int(params["max_lag"][0])

    def _init_state(self, params, horizon):
        h_fit = params["coef"].shape[0]
        if horizon > h_fit:
            raise ValueError(f"`horizon` must be <= {h_fit} for this InfoPredictor (one "
                             f"model per fitted horizon 1..{h_fit}); got {horizon}.")
        n_modes = params["mu"].shape[0]
        return {"values": np.zeros((int(params["max_lag"][0]), n_modes))}

    def _filter(self, params, state, X, out, status):
        sparse_direct_filter(X, params["mu"], params["src"], params["lag"], params["coef"],
                             state["values"], out, status)

    @property
    def n_inputs_(self) -> np.ndarray:
        """``(H, M)`` number of inputs of each model."""
        self._check_fitted()
        return np.count_nonzero(self.params_["coef"], axis=2)

    @property
    def mean_(self) -> np.ndarray:
        """``(M,)`` means removed before the regressions."""
        self._check_fitted()
        return self.params_["mu"]

    def inputs(self, mode: int, horizon: int) -> list[tuple[int, int, float]]:
        """Return the inputs of one model as ``(source mode, lag, weight)``, in order chosen.

        Parameters
        ----------
        mode : int
            Column of the forecast mode.
        horizon : int
            Horizon h in 1..H.

        Returns
        -------
        list of (int, int, float)
        """
        self._check_fitted()
        mode = check_int(mode, "mode", minimum=0, maximum=self.n_modes_ - 1)
        horizon = check_int(horizon, "horizon", minimum=1,
                            maximum=self.params_["coef"].shape[0])
        p = self.params_
        return [(int(p["src"][horizon - 1, mode, k]), int(p["lag"][horizon - 1, mode, k]),
                 float(p["coef"][horizon - 1, mode, k]))
                for k in range(p["coef"].shape[2]) if p["coef"][horizon - 1, mode, k] != 0.0]


def _fit_target(y, cy, C, Cu, alive, selection, G, penalty, est, alpha, n_surr, k_max, rng):
    """One target's inputs (columns of ``C``) and least-squares weights, or None if none.

    ``selection="ebic"`` searches the unit-column Gram ``G`` with the target's
    correlations ``cy``; otherwise the surrogate-tested greedy CMI search on ``y``.
    """
    n = C.shape[0]
    if selection == "ebic":
        chosen = [j for j, _ in greedy_gaussian_gram(G, cy, alive, n, max_inputs=k_max,
                                                     penalty=penalty)]
    else:
        shift0 = min(auto_block_length(y), n // 2)
        picked, _, _ = _greedy_search(
            y, C, Cu, alive, method="gaussian", est=est, factor=1.0, alpha=alpha,
            n_surrogates=n_surr, max_inputs=k_max, shift0=shift0, rng=rng)
        chosen = [j for j, _, _ in picked]
    if not chosen:
        return None
    return chosen, np.linalg.lstsq(C[:, chosen], y, rcond=None)[0]
