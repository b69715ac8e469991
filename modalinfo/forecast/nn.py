"""Sliding-window neural-network forecaster (the paper's three-layer network).

The paper trains, per Zernike coefficient, a three-layer network (10 inputs: the last
10 samples; 10 hidden neurons; one output: the next sample) on 10 training patterns.
Here the network is scikit-learn's :class:`~sklearn.neural_network.MLPRegressor`;
after training its weights are copied into a numba kernel that runs the forward
pass online (``update``) and offline (``predict``) with the same arithmetic, so both
agree exactly (and agree with ``MLPRegressor.predict`` to rounding). Forecasts for
h > 1 feed the network its own outputs.

Configurations
--------------
- :meth:`NeuralNetPredictor.paper`: the paper's 10-10-1 network on 10 patterns, trained
  without regularisation (scikit-learn's default ``alpha = 1e-4``, as the paper's plain
  back-propagation). It is reported as published; on smooth or closed-loop-like series
  it is typically several times worse than persistence, with a wide spread over seeds
  (10 patterns cannot constrain 121 weights).
- The default: the same 10-10-1 architecture trained on 2000 patterns with L-BFGS on
  standardised inputs (mean and standard deviation of the training series) and an L2
  penalty ``alpha = 1``, which actually learns the dynamics. Measured on the KAOS-like
  closed-loop log (6 modes, 7000 training frames): one-step gain over persistence
  1.13-1.18 with ``alpha = 1`` against 0.99-1.09 with ``alpha = 1e-4`` (over-fitting),
  and 5x faster training. L-BFGS stops at ``max_iter = 100`` iterations (early
  stopping; it was 500): on the same 6 modes the one-step gain is 1.157 against 1.139
  with 500, and the evaluation 7.3x faster (5.9 s against 43.1 s on a loaded 2-core
  machine, ``benchmarks/bench_forecast_nn.py``); on all 27 modes of the 8000-frame log
  (``modalinfo forecast``'s default split) the NN took 44 s against 212 s, gains
  1.167 / 1.148 at h = 1.

``ConvergenceWarning`` from scikit-learn (L-BFGS stopping at ``max_iter``) is caught
during training and recorded in ``converged_`` instead of being raised: a network
stopped at ``max_iter`` is still a valid (early-stopped) predictor. A stop *before*
``max_iter`` with that warning (L-BFGS's "ABNORMAL" line search) is a failed training:
``fit`` warns once (a ``ConvergenceWarning`` naming the columns and iterations), as it
does when ``standardize=False`` trains on a column whose root mean square exceeds 5
(round 45 PART a, N45 / N32).
"""

from __future__ import annotations

import copy
import warnings

import numpy as np

from modalinfo.common.quiet import caller_stacklevel, catching_warnings, warn
from modalinfo.common.validation import check_choice, check_int, check_memory, check_real
from modalinfo.forecast._kernels import mlp_filter
from modalinfo.forecast.base import Predictor

__all__ = ["NeuralNetPredictor"]

_ACTIVATIONS = {"identity": 0, "relu": 1, "tanh": 2, "logistic": 3}
#: ``standardize=False``: a column whose root mean square exceeds this warns (tanh is
#: 0.9999 at 5)
_SCALE_LIMIT = 5.0


class NeuralNetPredictor(Predictor):
    """One-hidden-layer perceptron on a sliding window, one network per mode.

    Parameters
    ----------
    n_inputs : int
        Window length ``K`` (input neurons).
    n_hidden : int
        Hidden neurons.
    n_patterns : int or None
        Training patterns: the last ``n_patterns`` (window, next sample) pairs of the
        history; ``None`` uses every available pair.
    activation : {"relu", "tanh", "logistic", "identity"}
        Hidden activation.
    solver : {"lbfgs", "adam", "sgd"}
        scikit-learn solver.
    alpha : float
        L2 penalty (scikit-learn's ``alpha``, on standardised data).
    max_iter : int
        Training iterations.
    standardize : bool
        Standardise inputs and output with the training mean and standard deviation.
    warm_start : bool
        At refits, start from the previous weights.
    random_state : int
        Seed of the weight initialisation (same for every mode).
    horizon : int
        Number of steps forecast by ``update``.
    refit_every, window : int or None
        Refit (retraining) policy.

    Minimum samples: ``n_inputs`` + one training pattern per weight of the network,
    ``n_hidden (n_inputs + 2) + 1`` (131 for the default 10-10-1), or + ``n_patterns``
    when fewer patterns are asked for (the paper's deliberately under-determined 10:
    20 samples). The network trains on ``min(n_patterns, T - n_inputs)`` patterns.
    A constant column (range at most 1e-12 of its magnitude) gets no network: it is
    forecast as the constant (``models_`` holds ``None`` for it).

    Attributes
    ----------
    models_ : list of sklearn.neural_network.MLPRegressor or None
        The trained network of each mode (``None`` for a constant mode).
    converged_ : numpy.ndarray of bool, shape (M,)
        Whether each training stopped before ``max_iter``.
    """

    #: ``warm_start`` only chooses where later fits start from
    _fit_free_params = ("warm_start",)

    def __init__(self, *, n_inputs: int = 10, n_hidden: int = 10,
                 n_patterns: int | None = 2000, activation: str = "tanh",
                 solver: str = "lbfgs", alpha: float = 1.0, max_iter: int = 100,
                 standardize: bool = True, warm_start: bool = True, random_state: int = 0,
                 horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)
        self.n_inputs = n_inputs
        self.n_hidden = n_hidden
        self.n_patterns = n_patterns
        self.activation = activation
        self.solver = solver
        self.alpha = alpha
        self.max_iter = max_iter
        self.standardize = standardize
        self.warm_start = warm_start
        self.random_state = random_state

    @classmethod
    def paper(cls, **overrides) -> NeuralNetPredictor:
        """Return the paper's configuration: 10 inputs, 10 hidden neurons, 10 patterns.

        The paper does not give the activation, training algorithm or scaling; this
        uses the defaults of this class for those (tanh, L-BFGS, standardised) and no
        regularisation (``alpha = 1e-4``, scikit-learn's default).

        Parameters
        ----------
        **overrides
            Any other hyper-parameter (e.g. ``random_state``, ``horizon``).

        Returns
        -------
        NeuralNetPredictor
        """
        params = {"n_inputs": 10, "n_hidden": 10, "n_patterns": 10, "alpha": 1e-4}
        params.update(overrides)
        return cls(**params)

    def fit_bytes(self, n_samples: int, n_modes: int) -> int:
        """Upper estimate of the memory ``fit`` allocates at its peak [bytes].

        2 float64 copies of the history, and 3 x ``patterns x (n_inputs + n_hidden +
        1)`` float64 for one mode's training (patterns, activations, L-BFGS work).
        tracemalloc's peak: 1.10 and 1.07 MB at 3,000 and 6,000 samples of 10 modes
        (0.48 and 0.96 MB a copy; the default network, left19-est).
        """
        patterns = n_samples if self.n_patterns is None else min(self.n_patterns, n_samples)
        width = self.n_inputs + self.n_hidden + 1
        return 2 * 8 * n_samples * n_modes + 3 * 8 * patterns * width

    def _min_samples_rule(self, n_modes: int) -> tuple[int, str]:
        k = check_int(self.n_inputs, "n_inputs", minimum=1)
        n_weights = check_int(self.n_hidden, "n_hidden", minimum=1) * (k + 2) + 1
        if self.n_patterns is not None:
            n_pat = check_int(self.n_patterns, "n_patterns", minimum=1)
            if n_pat < n_weights:
                return k + n_pat, (f"n_inputs {k} + the n_patterns = {n_pat} training "
                                   "patterns asked for")
        return k + n_weights, (f"n_inputs {k} + one training pattern per weight x "
                               f"{n_weights} weights")

    def _fit_params(self, X, previous, name):
        # scikit-learn only trains; imported here so that importing modalinfo.forecast
        # (e.g. for ARMA alone) does not pay its ~0.4 s import
        from sklearn.exceptions import ConvergenceWarning
        from sklearn.neural_network import MLPRegressor

        k = check_int(self.n_inputs, "n_inputs", minimum=1)
        n_hidden = check_int(self.n_hidden, "n_hidden", minimum=1)
        check_choice(self.activation, "activation", tuple(_ACTIVATIONS))
        check_choice(self.solver, "solver", ("lbfgs", "adam", "sgd"))
        alpha = check_real(self.alpha, "alpha", minimum=0.0)
        max_iter = check_int(self.max_iter, "max_iter", minimum=1)
        # scikit-learn's own bound (a numpy legacy seed): above it MLPRegressor raised
        # InvalidParameterError naming itself and suggesting a RandomState or None, which
        # this class refuses (round 38 PART a, R41 / R83)
        seed = check_int(self.random_state, "random_state", minimum=0, maximum=2**32 - 1)
        constant, value = self._constant_columns(X)
        n, n_modes = X.shape
        n_pat = n - k if self.n_patterns is None else min(int(self.n_patterns), n - k)
        # the weights of every mode, and per fit scikit-learn's hidden activations and
        # their gradients (n_patterns x n_hidden, 3 copies) and its L-BFGS memory (10
        # pairs of weight vectors, 2 more for the gradient): bytes of float64
        n_weights = n_hidden * (k + 2) + 1
        check_memory(8.0 * (n_modes * n_weights + 3 * n_pat * n_hidden + 22 * n_weights),
                     "n_hidden", n_hidden, "the network's weights and activations")
        if self.standardize:
            x_mean = X.mean(axis=0)
            x_scale = X.std(axis=0)
        else:
            x_mean = np.zeros(n_modes)
            x_scale = np.ones(n_modes)
        # a constant column has no network: zero weights give y = 0, so the forecast
        # is x_mean = the constant
        x_mean = np.where(constant, value, x_mean)
        x_scale = np.where(constant, 1.0, x_scale)
        w1 = np.empty((n_modes, k, n_hidden))
        b1 = np.empty((n_modes, n_hidden))
        w2 = np.empty((n_modes, n_hidden))
        b2 = np.empty(n_modes)
        models = []
        converged = np.ones(n_modes, dtype=bool)
        targets = np.arange(n - n_pat, n)
        abnormal = []
        scale_note = None if self.standardize else self._scale_note(X, constant)
        for m in range(n_modes):
            if constant[m]:
                w1[m], b1[m], w2[m], b2[m] = 0.0, 0.0, 0.0, 0.0
                models.append(None)
                continue
            z = (X[:, m] - x_mean[m]) / x_scale[m]
            inputs = np.stack([z[t - k : t] for t in targets])
            use_prev = (previous is not None and self.warm_start and "models" in previous
                        and previous["models"][m] is not None)
            if use_prev:
                model = copy.deepcopy(previous["models"][m])
                model.set_params(warm_start=True)
            else:
                model = MLPRegressor(hidden_layer_sizes=(n_hidden,),
                                     activation=self.activation, solver=self.solver,
                                     alpha=alpha, max_iter=max_iter, random_state=seed,
                                     tol=1e-6)
            with catching_warnings(record=True) as caught:  # one at a time
                warnings.simplefilter("always", ConvergenceWarning)
                model.fit(inputs, z[targets])
            converged[m] = not any(issubclass(w.category, ConvergenceWarning)
                                   for w in caught)
            # a stop before max_iter with scikit-learn's ConvergenceWarning is L-BFGS's
            # failed line search ("ABNORMAL"), not the early stop at max_iter: the
            # network did not train (round 45 PART a, N45 / N32)
            if not converged[m] and model.n_iter_ < max_iter:
                abnormal.append((m, int(model.n_iter_)))
            for w in caught:
                if not issubclass(w.category, ConvergenceWarning):
                    warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            models.append(model)
            w1[m] = model.coefs_[0]
            b1[m] = model.intercepts_[0]
            w2[m] = model.coefs_[1][:, 0]
            b2[m] = model.intercepts_[1][0]
        if abnormal or scale_note:
            parts = []
            if abnormal:
                shown = ", ".join(f"column {m} after {it}" for m, it in abnormal[:5])
                more = f" and {len(abnormal) - 5} more" if len(abnormal) > 5 else ""
                parts.append(
                    f"the training of {len(abnormal)} mode(s) stopped before max_iter = "
                    f"{max_iter} iterations with scikit-learn's ConvergenceWarning ({shown}"
                    f"{more} iteration(s)): the {self.solver} solver failed (an abnormal "
                    "line search), so the network did not learn")
            if scale_note:
                parts.append(scale_note)
            advice = ("train on standardised inputs (standardize=True, the default) or "
                      "rescale the data to unit scale" if not self.standardize else
                      "the inputs were standardised: check the log for outliers or steps, "
                      "or change alpha or solver")
            warn(f"NeuralNetPredictor.fit: {'; '.join(parts)}; {advice}.",
                 ConvergenceWarning, stacklevel=caller_stacklevel())
        return {"x_mean": x_mean, "x_scale": x_scale, "w1": w1, "b1": b1, "w2": w2,
                "b2": b2, "activation": _ACTIVATIONS[self.activation], "models": models,
                "converged": converged}

    @staticmethod
    def _scale_note(X, constant) -> str | None:
        """Return the note where ``standardize=False`` trains on a column far from unit scale.

        The network sees the raw values: beyond ~5 in magnitude tanh and logistic
        saturate and L-BFGS stops without learning (an AR(2) log in nm, std 349 nm,
        one-step RMSE 257 nm against persistence's 106 nm; round 45 PART a, N45 / N32).
        The rule: a non-constant column's root mean square above ``_SCALE_LIMIT``.
        """
        rms = np.sqrt(np.mean(np.square(X), axis=0))
        bad = [(m, float(rms[m])) for m in range(X.shape[1])
               if not constant[m] and rms[m] > _SCALE_LIMIT]
        if not bad:
            return None
        shown = ", ".join(f"column {m}: {r:.3g}" for m, r in bad[:5])
        more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
        return (f"standardize=False and the root mean square of {len(bad)} training "
                f"column(s) exceeds {_SCALE_LIMIT:g} ({shown}{more}): the network sees the "
                "raw values and its hidden units saturate")

    def _memory(self, params):
        return int(params["w1"].shape[1])

    def _init_state(self, params, horizon):
        n_modes, k, _ = params["w1"].shape
        return {"values": np.zeros((n_modes, k)), "work": np.zeros(horizon + k)}

    def _filter(self, params, state, X, out, status):
        mlp_filter(X, params["x_mean"], params["x_scale"], params["w1"], params["b1"],
                   params["w2"], params["b2"], params["activation"], state["values"],
                   state["work"], out, status)

    @property
    def models_(self) -> list:
        """The trained ``MLPRegressor`` of each mode."""
        self._check_fitted()
        return self.params_["models"]

    @property
    def converged_(self) -> np.ndarray:
        """``(M,)`` whether each training converged before ``max_iter``."""
        self._check_fitted()
        return self.params_["converged"]
