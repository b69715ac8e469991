"""The :class:`Predictor` interface shared by every wavefront forecaster.

A predictor is an sklearn-style estimator: hyper-parameters are stored unchanged by
``__init__``, :meth:`Predictor.fit` sets the fitted attributes (trailing ``_``), and
using an unfitted predictor raises :class:`NotFittedError`. It forecasts the
``H = horizon`` samples following the end of a history, offline with
:meth:`Predictor.predict` and online with :meth:`Predictor.reset` /
:meth:`Predictor.update`, which the closed-loop simulator calls every loop step.

Online and offline agree exactly
--------------------------------
Every predictor is a fixed-size recursion (the last few samples, innovations, RLS
matrices) run by a numba kernel of :mod:`modalinfo.forecast._kernels`. ``predict``
starts from the reset state and feeds the whole history to the kernel in one block;
``update`` feeds one sample. The operations and their order are the same, so
``predict(history)[h]`` equals, bit for bit, the output of the last
``update`` after ``reset()`` and one ``update`` per sample of ``history``.

Refit policy
------------
With ``refit_every=R`` the parameters are re-estimated every ``R`` samples from the
last ``window=W`` samples (``W`` defaults to the length of the history given to
``fit``): after the ``n``-th sample since ``reset`` (``n % R == 0`` and ``n >= W``)
the model is refitted on samples ``n - W .. n - 1``. The forecasts returned for
sample ``n`` use the parameters in force when it arrived; the new ones apply from
sample ``n + 1``. Online, a ring buffer of the last ``W`` samples is kept only when
a refit policy is set; the per-step cost is otherwise constant and the refit cost is
paid once every ``R`` steps. ``predict`` replays the same schedule, so both paths
still agree exactly. The recursion's state carries over a refit whose parameters keep
its layout (every fixed order); where a refit changes it (ARMA with ``order="aic"`` or
``"bic"`` selecting other p, q), the state is rebuilt by feeding the window, the
samples the refit saw, through the new recursion from the reset state (adversarial
round 34 PART a: the old layout was kept, and the kernel read it wrongly or wrote past
its end).

Hyper-parameters changed after ``fit``
--------------------------------------
``horizon``, ``refit_every`` and ``window`` changed by :meth:`Predictor.set_params` (or
by assignment) after ``fit`` apply to the next ``predict`` and the next ``reset``, as if
the predictor had been built with them (the fitted parameters do not depend on them).
An online pass already begun was built for the old values: ``update`` refuses to go on,
naming the change, until ``reset()`` starts a pass with the new ones (adversarial round
35 PART a: ``update`` kept the old horizon while ``predict`` used the new one, raised a
TypeError once ``refit_every`` became None, and a ``window`` set after ``fit`` was
ignored).

The other hyper-parameters define the model (``order``, ``fit_weights``, ``alpha``, ...):
the fitted parameters were estimated with the values in force at ``fit``. Changed after
``fit``, ``predict``, ``predict_interval``, ``reset`` and ``update`` raise a ValueError
naming them until ``fit()`` re-estimates the model (or the old value is set back); they
forecast with the old model while ``get_params()`` reported the new one, and a refit
policy switched models at its first refit (adversarial round 43 PART a, S03, S37, S38,
S57). Settings read at forecast time only (ARMA's ``level``, the neural net's
``warm_start``) are exempt (``_fit_free_params``).
"""

from __future__ import annotations

import contextlib
import contextvars
import copy
import inspect
import operator
from collections.abc import Iterator
from typing import Any

import numpy as np

from modalinfo.common.quiet import caller_stacklevel, warn
from modalinfo.common.validation import SQUARE_FLOOR as _SQUARE_FLOOR
from modalinfo.common.validation import (
    as_float_array,
    check_int,
    check_memory,
    check_real_dtype,
    check_square_floor,
    check_square_range,
    unmasked,
)

__all__ = ["Predictor", "NotFittedError"]


#: Smallest range [the data's units] of a varying column that can be forecast and scored:
#: below ``sqrt(tiny) / eps`` (6.7e-139) a forecast error of one ulp of the range has a
#: square below the smallest normal float64 (2.2e-308), so squared errors, variances and
#: least-squares normal equations underflow to subnormals or 0 (an RMSE of 0 on 1e-300
#: data, a singular fit). IEEE 754 binary64 limits, numpy.finfo(float64).
SQUARE_FLOOR = _SQUARE_FLOOR  # defined in common.validation (fitting_error uses it too)

# check_square_floor (imported above, used by evaluate too) lives in common.validation:
# the data K-L and the autocovariance refuse with it as well (round 40 PART a)


#: The columns of the history being fitted whose level step the calibration-event
#: warning named (a fit's own model-specific level rule, ``ARMAPredictor``'s
#: ``LevelStepWarning``, leaves them out: one word per event); None outside a judged fit.
#: Set by ``Predictor.fit`` around its estimate, and by :func:`training_events_judged`
#: (the caller judged the training frames once: ``evaluate`` fits every predictor on
#: them, and ``fit`` then runs no pass of its own).
_LEVELS_NAMED: contextvars.ContextVar[frozenset | None] = contextvars.ContextVar(
    "modalinfo_training_levels_named", default=None)


@contextlib.contextmanager
def training_events_judged(named: frozenset = frozenset()) -> Iterator[None]:
    """Within: ``Predictor.fit`` leaves the calibration-event check to the caller.

    ``named``: the columns whose level step the caller's warning named
    (:func:`warn_training_events`' return).
    """
    token = _LEVELS_NAMED.set(frozenset(named))
    try:
        yield
    finally:
        _LEVELS_NAMED.reset(token)


def levels_named() -> frozenset:
    """Columns whose level step the calibration-event warning of this fit named."""
    return _LEVELS_NAMED.get() or frozenset()


def warn_training_events(X, labels, caller: str) -> frozenset:
    """Warn (``CalibrationEventWarning``) where the training frames hold a calibration event.

    The quality pass's level, spread and innovation-scale steps
    (``telemetry.quality.calibration_events``: its ``mode_events`` at
    ``CALIBRATION_LEVEL_P``, none on fewer than ``CALIBRATION_MIN_FRAMES`` frames), the one
    detector ``order_modes`` names too (fix53-a). The scale rule was left out until
    fix56-b (it named blocks of stationary simulator POLs, fix54-b); since fix55-b's
    near-white gate it names none of 50 + 50 + 50 + 50 stationary AR(1) 0.9 / 0.99,
    ``kaos_like`` closed- and open-loop logs nor of 20 simulator POLs, and names a x10
    first 5 % (the loop closing, L39) in 20 of 20 logs where the level and spread rules
    name none (docs/ADVERSARIAL.md, fix56-b). A level step or gain jump inside the
    history is fitted as dynamics (persistence, a spread the model takes for
    turbulence), without a word before
    fix54-b (round 53 PART a, C23). ``X`` (T, M) the training frames, ``labels`` their
    ``M`` names, ``caller`` the message's start. Returns the columns whose level step
    (``"the mean steps or drifts ..."``) was named.
    """
    from modalinfo.telemetry.quality import (
        CalibrationEventWarning,
        calibration_event_list,
        calibration_events,
    )

    # every rule of the pass, as order_modes (one detector; the scale rule's near-white
    # gate, fix55-b, keeps it off stationary simulator POLs: fix56-b)
    events = calibration_events(np.asarray(X))
    if not events:
        return frozenset()
    modes = sorted({j for j, *_ in events})
    warn(f"{caller}: the quality pass (assess_quality) finds a calibration event in "
         f"{len(modes)} of the {X.shape[1]} modes of the training history "
         f"({calibration_event_list(events, labels)}): the fitted model pools both sides "
         "of the event (a new reference, a gain or unit change, modes re-mapped, the loop "
         "closing), which it reads as dynamics or turbulence; fit each stretch of steady "
         "conditions on its own.", CalibrationEventWarning, stacklevel=caller_stacklevel())
    return frozenset(j for j, _, _, words in events if words.startswith("the mean steps"))


#: Largest relative difference between a predictor's training rate and the rate of the
#: data it is fed (``Predictor.check_fed``): 1 % moves a lag of 10 frames by 0.1 frame,
#: and a log's rate from jittered timestamps is within 1e-5 of the nominal (audit 10),
#: far below the factors of 2 of a loop run at another rate (round 55 PART b, X01 / X50).
RATE_TOLERANCE = 0.01

#: Largest relative difference of the wavelengths of phase in rad (``check_fed``).
WAVELENGTH_TOLERANCE = 1e-6

#: Largest factor, either way, between the rms of the data a predictor is fed and of the
#: data it was fitted on, as the median over the modes of their ratio
#: (``Predictor.check_fed``). A unit mix-up is a factor 80 (nm against rad at 500 nm),
#: 12.6 (um) or 1e7-1e8 (m); seeing moves the phase's rms as r0^(-5/6), x10 for r0 15
#: times smaller. Measured on the simulator (docs/ADVERSARIAL.md, fix56-b): 16 frames
#: spread over runs of 0.01-0.3 s read x0.53-x1.1 of a reference run's POL's rms on 27
#: modes, x0.21-x2.6 on 2 (tip and tilt, the slowest modes: the median of fewer modes
#: scatters more), hence ``SCALE_FACTOR_FEW`` below ``SCALE_FEW_MODES`` modes.
SCALE_FACTOR = 10.0
SCALE_FACTOR_FEW = 30.0
SCALE_FEW_MODES = 4


def rms_per_mode(X: np.ndarray) -> np.ndarray:
    """Root mean square about 0 of each column of ``X`` (T, M) [X's units], shape (M,)."""
    X = np.asarray(X, dtype=np.float64)
    return np.sqrt(np.einsum("ij,ij->j", X, X) / max(X.shape[0], 1))


def scale_ratio(fed: np.ndarray, trained: np.ndarray) -> tuple[float | None, int]:
    """Median over the modes of ``fed / trained`` (both (M,) rms), and how many modes.

    Taken as the exponential of the median of the log ratios, over the modes where both
    are finite and positive (a zeroed mode has no scale); None where none is.
    """
    ok = np.isfinite(fed) & np.isfinite(trained) & (fed > 0) & (trained > 0)
    if not ok.any():
        return None, 0
    return float(np.exp(np.median(np.log(fed[ok]) - np.log(trained[ok])))), int(ok.sum())


class NotFittedError(ValueError, AttributeError):
    """Raised when a predictor is used before :meth:`Predictor.fit`."""


#: Longest forecast horizon [frames] a predictor takes: 10**6 frames is 17 minutes at
#: 1 kHz, far beyond any correlation time of the turbulence. Before round 15 PART a (f27)
#: ``predict(x, horizon=10**9)`` passed the memory check on a 23 GB machine and ran for
#: minutes (or died with MemoryError under a smaller limit).
MAX_HORIZON = 10**6


def check_horizon(value: Any, name: str = "horizon") -> int:
    """Return a forecast horizon as ``int`` in ``[1, MAX_HORIZON]`` frames, naming it."""
    return check_int(value, name, minimum=1, maximum=MAX_HORIZON)


def _check_forecast_memory(horizon: int, n_modes: int) -> None:
    """Refuse a horizon whose forecast arrays (two of H x M float64) cannot be held."""
    # horizon=10**30 reached NumPy as "Maximum allowed dimension exceeded" (audit 9)
    check_memory(2.0 * 8.0 * horizon * max(int(n_modes), 1), "horizon", horizon,
                 f"the forecasts of {n_modes} mode(s)")


class _Run:
    """Running state of one forecast pass (online, or one offline ``predict``).

    Attributes
    ----------
    params : dict
        Parameters in force (replaced at refits).
    state : dict
        Kernel state arrays (fixed size).
    horizon : int
    n_seen : int
        Samples processed since reset.
    ring : numpy.ndarray or None
        ``(W, M)`` ring buffer of the last samples (only with a refit policy).
    """

    __slots__ = ("params", "state", "horizon", "n_seen", "ring", "ring_pos", "out", "status",
                 "x", "step", "refit", "window", "config", "settings")

    def __init__(self, params, state, horizon, n_modes, window, refit=None, refit_window=None,
                 config=None):
        self.params = params
        self.state = state
        self.horizon = horizon
        # the refit policy in force for this pass (``refit_every``, its window ``W``) and
        # the hyper-parameters ``(horizon, refit_every, window)`` it was built from: a
        # ``set_params`` during an online pass is refused at the next ``update`` instead
        # of half-applied (round 35 PART a: T1, S1, S2)
        self.refit = refit
        self.window = refit_window
        self.config = config
        self.settings = None  # ``operator.attrgetter`` of every hyper-parameter (update's check)
        self.n_seen = 0
        self.ring = None if window is None else np.zeros((window, n_modes))
        self.ring_pos = 0
        self.out = np.zeros((1, horizon, n_modes))
        self.status = np.zeros(1, dtype=np.int64)
        self.x = np.zeros((1, n_modes))
        self.step = None

    # ``step`` is a closure over this run's arrays: it is not pickled (a local function) and
    # a deep copy would keep it bound to the original's arrays, so a copied predictor
    # advanced the original's state (adversarial round 9, rows f-deepcopy, pk-*); the
    # owner rebinds it (:meth:`Predictor.__setstate__`)
    def __getstate__(self):
        return {k: getattr(self, k) for k in self.__slots__ if k != "step"}

    def __setstate__(self, state):
        for k, v in state.items():
            setattr(self, k, v)
        self.step = None



def user_defined(cls: type, name: str) -> bool:
    """Whether ``cls``'s attribute ``name`` is a user's: defined outside the modalinfo package.

    A user's predictor (a subclass written outside the package) is a plug-in: its hooks
    get read-only samples and its parameters are checked (round 44 PART a), and
    :func:`~modalinfo.forecast.evaluate` refuses one whose public ``predict`` / ``update``
    it would not call.
    """
    for klass in cls.__mro__:
        if name in vars(klass):
            return not str(getattr(klass, "__module__", "")).startswith("modalinfo.")
    return False


def _read_only(a: np.ndarray) -> np.ndarray:
    """Return a read-only view of ``a``: what a user's ``_fit_params`` / ``_filter`` is given."""
    from modalinfo.information.methods import read_only

    return read_only(a)


def _frame_columns(history, attr: str = "columns", ndim: int = 2) -> list | None:
    """Column names of a 2-D DataFrame-like ``history``, None for arrays or 0, 1, ... names.

    ``attr="index", ndim=1``: the mode names of one sample (a Series, a DataFrame row).
    """
    columns = getattr(history, attr, None)
    if columns is None or getattr(history, "ndim", None) != ndim:
        return None
    names = list(columns)
    return None if names == list(range(len(names))) else names


class Predictor:
    """Base class of the wavefront forecasters.

    Subclasses define ``__init__`` (keyword hyper-parameters stored unchanged),
    ``_fit_params(X, previous)`` returning a dict of kernel-ready parameter arrays,
    ``_init_state(params, horizon)`` returning a dict of state arrays and
    ``_filter(params, state, X, out, status)`` calling the kernel.

    Parameters
    ----------
    horizon : int
        Number of steps ``H`` forecast by ``update`` and by default by ``predict``,
        ``1 <= H <= 10**6`` (``MAX_HORIZON``; a ValueError naming ``horizon`` beyond).
    refit_every : int or None
        Re-estimate the parameters every this many samples (see the module notes).
    window : int or None
        Length of the sliding window used at refits; default: the length of the
        history given to ``fit``.
    """

    #: whether modes are modelled jointly (multivariate) or one model per mode
    _multivariate: bool = False
    #: hyper-parameters read at forecast time only, free to change after ``fit`` besides
    #: ``horizon`` / ``refit_every`` / ``window`` (see the module notes)
    _fit_free_params: tuple[str, ...] = ()

    def __init__(self, *, horizon: int = 10, refit_every: int | None = None,
                 window: int | None = None):
        self.horizon = horizon
        self.refit_every = refit_every
        self.window = window

    # ------------------------------------------------------------------ sklearn API
    @classmethod
    def _param_names(cls) -> list[str]:
        sig = inspect.signature(cls.__init__)
        return [p.name for p in sig.parameters.values()
                if p.name != "self" and p.kind != p.VAR_KEYWORD]

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """Return the hyper-parameters as a dict (scikit-learn convention).

        Parameters
        ----------
        deep : bool
            Accepted for scikit-learn compatibility; predictors hold no sub-estimators.

        Returns
        -------
        dict
            ``{name: value}`` for every ``__init__`` keyword.
        """
        names = self._param_names()
        missing = [name for name in names if not hasattr(self, name)]
        if missing:  # round 44 PART a, E09: AttributeError from inside evaluate's clone
            listed = ", ".join(f"`{name}`" for name in missing)
            raise TypeError(
                f"{type(self).__name__}.__init__ takes {listed} but the object has no "
                f"attribute of that name: a predictor stores each __init__ argument "
                f"unchanged under its own name (the scikit-learn convention), which "
                f"get_params(), clone() and evaluate() read.")
        return {name: getattr(self, name) for name in names}

    def set_params(self, **params) -> Predictor:
        """Set hyper-parameters; fitted attributes are left untouched until ``fit``.

        ``horizon``, ``refit_every`` and ``window`` apply to the next ``predict`` and
        ``reset``; ``update`` refuses to continue an online pass begun before they
        changed. A model setting changed after ``fit`` (``order``, ``fit_weights``, ...)
        makes ``predict``, ``reset`` and ``update`` refuse until ``fit()`` (see the
        module notes).

        Parameters
        ----------
        **params
            ``__init__`` keywords and their new values (not validated until ``fit``).

        Returns
        -------
        Predictor
            ``self``.

        Raises
        ------
        ValueError
            If a name is not a hyper-parameter of this class.
        """
        valid = self._param_names()
        for key, value in params.items():
            if key not in valid:
                raise ValueError(
                    f"`{key}` is not a parameter of {type(self).__name__}; "
                    f"valid parameters: {', '.join(valid)}."
                )
            setattr(self, key, value)
        return self

    def clone(self, **params) -> Predictor:
        """Return an unfitted copy with the same (optionally updated) hyper-parameters.

        Parameters
        ----------
        **params
            Hyper-parameters to change in the copy (see :meth:`set_params`).

        Returns
        -------
        Predictor
            A new instance of the same class; hyper-parameters are deep-copied.
        """
        new = type(self)(**copy.deepcopy(self.get_params()))
        return new.set_params(**params)

    def __repr__(self) -> str:
        defaults = {p.name: p.default for p in inspect.signature(type(self).__init__).parameters
                    .values() if p.name != "self"}
        shown = [f"{k}={v!r}" for k, v in self.get_params().items()
                 if not _same(defaults.get(k, inspect.Parameter.empty), v)]
        return f"{type(self).__name__}({', '.join(shown)})"

    # ------------------------------------------------------------------ validation
    def _check_common(self, n_modes: int = 1) -> tuple[int, int | None, int | None]:
        horizon = check_horizon(self.horizon)
        refit = None if self.refit_every is None else check_int(
            self.refit_every, "refit_every", minimum=1)
        window = None if self.window is None else check_int(
            self.window, "window", minimum=self._min_samples(n_modes))
        if window is not None and refit is not None:  # the refit ring buffer (window, M)
            check_memory(8.0 * window * n_modes, "window", window,
                         f"the refit ring buffer of {n_modes} mode(s)")
        return horizon, refit, window

    def _min_samples(self, n_modes: int = 1) -> int:
        """Fewest samples ``fit`` accepts for ``n_modes`` modes (see :meth:`min_samples`)."""
        return self._min_samples_rule(n_modes)[0]

    def _min_samples_rule(self, n_modes: int) -> tuple[int, str]:
        """``(fewest samples, the rule in words)``; subclasses with parameters raise it."""
        return 1, "no parameters to estimate"

    def min_samples(self, n_modes: int = 1) -> int:
        """Fewest samples ``fit`` (and a refit window) accepts.

        Each class states its rule in its docstring (derived from the number of
        parameters it estimates); the error raised for a shorter history repeats it.

        Parameters
        ----------
        n_modes : int
            Number of modes (columns) of the history (it matters for the
            multivariate predictors only).

        Returns
        -------
        int
            The minimum number of samples along axis 0.
        """
        return self._min_samples(check_int(n_modes, "n_modes", minimum=1))

    def _check_history(self, history, name: str = "history",
                       min_length: int = 1) -> tuple[np.ndarray, bool]:
        arr = as_float_array(history, name, ndim=(1, 2))
        scalar = arr.ndim == 1
        X = arr.reshape(-1, 1) if scalar else arr
        if X.shape[0] < min_length:
            raise ValueError(
                f"`{name}` needs at least {min_length} samples along axis 0 for "
                f"{type(self).__name__}; got {X.shape[0]}."
            )
        if X.shape[1] < 1:
            raise ValueError(f"`{name}` must have at least one mode (column); got shape "
                             f"{arr.shape}.")
        return np.ascontiguousarray(X), scalar

    def _check_fitted(self) -> None:
        if not hasattr(self, "params_"):
            raise NotFittedError(
                f"This {type(self).__name__} is not fitted yet; call `fit(history)` first."
            )

    @staticmethod
    def _constant_columns(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Columns treated as constant, and the constant of each column.

        A column is constant when its range is at most ``1e-12`` times its largest
        magnitude (a zeroed piston, a dead mode). No model parameter can be
        estimated from it, and none is needed: every predictor forecasts such a
        column as its median over the fitting samples, which is exactly the
        constant (so it is as exact as persistence).

        Returns
        -------
        constant : numpy.ndarray of bool, shape (M,)
        value : numpy.ndarray, shape (M,)
            Median of each column (meaningful where ``constant``).
        """
        with np.errstate(over="ignore", invalid="ignore"):
            spread = np.ptp(X, axis=0)
            constant = spread <= 1e-12 * np.abs(X).max(axis=0)
        return constant, np.median(X, axis=0)

    # ------------------------------------------------------------------ fitting
    def fit(self, history) -> Predictor:
        """Estimate the parameters from a history.

        Parameters
        ----------
        history : array_like, shape (T,) or (T, M), or ModalLog
            Past samples, time along axis 0. Univariate predictors fit one model per
            mode (column); multivariate ones model the modes jointly. A ``ModalLog`` is
            fitted on its ``coeffs``; its labels become ``columns_`` and its metadata
            ``training_metadata_`` (what the log says of its source: a closed-loop run's
            config, which ``closedloop.simulate`` checks against the loop's, fix54-b), its
            rate [Hz], units and wavelength [m] ``training_log_`` (``predict`` of a
            ``ModalLog`` and ``closedloop.simulate`` refuse another frame clock or units).

        Returns
        -------
        Predictor
            ``self``, fitted; the online state is reset.

        Warns
        -----
        CalibrationEventWarning
            Where the quality pass finds a level step, a spread step or a change of the
            innovations' scale (a new reference, a gain jump, the loop closing) in a mode
            of a history of at least 2,000 frames (the rules ``order_modes`` names,
            ``warn_training_events``): the parameters pool both sides of the event.
        """
        from modalinfo.telemetry.log import ModalLog

        log = history if isinstance(history, ModalLog) else None
        if log is not None:  # its values, labels and source (fix54-b, C22)
            history = log.coeffs
        X, scalar = self._check_history(history, "history", 1)
        n_min, rule = self._min_samples_rule(X.shape[1])
        if X.shape[0] < n_min:
            raise ValueError(
                f"`history` needs at least {n_min} samples along axis 0 for "
                f"{type(self).__name__} ({rule}); got {X.shape[0]}."
            )
        _, _, window = self._check_common(X.shape[1])
        check_square_range(X, "history")
        check_square_floor(X, "history")
        names = _frame_columns(history) if log is None else [str(c) for c in log.labels]
        named = _LEVELS_NAMED.get()
        if named is None:  # the quality pass's events (fix54-b, C23), unless judged already
            named = warn_training_events(X, [str(c) for c in names] if names is not None else [
                f"column {j}" for j in range(X.shape[1])], f"{type(self).__name__}.fit")
        with training_events_judged(named):
            self.params_ = self._estimate(X, None, "history")
        self.n_modes_ = X.shape[1]
        self.n_samples_fit_ = X.shape[0]
        if names is None:
            self.__dict__.pop("columns_", None)
        else:
            self.columns_ = names
        self.scalar_input_ = scalar
        if log is None:
            self.__dict__.pop("training_metadata_", None)
            self.__dict__.pop("training_log_", None)
        else:
            self.training_metadata_ = copy.deepcopy(dict(log.metadata))
            # what a later log must share to be forecast by these parameters: the frame
            # clock (lags count frames) and the values' units (an intercept, a training
            # mean, a network's scaling are in them) (round 55 PART b, X01 / X45);
            # ``check_fed`` compares them
            self.training_log_ = {"rate": log.rate, "units": log.units,
                                  "wavelength": log.wavelength}
        # the scale check_fed compares the data it is later fed with (fix56-b): each
        # mode's rms (an array states no clock nor units: training_log_ is absent)
        self.training_rms_ = rms_per_mode(X)
        self.window_ = X.shape[0] if window is None else window
        # the model settings the parameters were estimated with (round 43 PART a, S03)
        self._fit_settings_ = {name: _snapshot(getattr(self, name))
                               for name in self._model_params()}
        self.reset()
        return self

    @classmethod
    def _model_params(cls) -> list[str]:
        """Hyper-parameters the fitted parameters depend on (see the module notes)."""
        free = ("horizon", "refit_every", "window", *cls._fit_free_params)
        return [name for name in cls._param_names() if name not in free]

    def _model_changes(self) -> list[str]:
        """``"`name` old -> new"`` for each model setting changed since ``fit``."""
        fitted = self.__dict__.get("_fit_settings_", {})
        return [f"`{name}` {old!r} -> {getattr(self, name)!r}"
                for name, old in fitted.items() if not _same_setting(old, getattr(self, name))]

    def _refuse_model_changed(self) -> None:
        """Refuse to forecast with a model fitted under other settings (round 43 PART a)."""
        changed = self._model_changes()
        if changed:
            raise ValueError(
                f"{', '.join(changed)} changed since fit(): {type(self).__name__} still holds "
                "the model fitted with the old value(s); call fit() to re-estimate it, or "
                "set the old value(s) back.")

    def fit_bytes(self, n_samples: int, n_modes: int) -> int:
        """Upper estimate of the memory ``fit`` allocates at its peak [bytes].

        Besides the history itself. The base counts 2 float64 copies of the history:
        tracemalloc's peak of the fits of the linear, ARMA and neural-net predictors
        is 1.0-1.1 copies at 1,500-8,000 samples of 10-27 modes (left19-est);
        predictors with a larger design override it. The model's estimate only: on a
        history of ``CALIBRATION_MIN_FRAMES`` (2,000) frames or more, ``fit`` first runs
        the quality pass for calibration events (fix54-b), whose peak
        (``telemetry.quality.quality_memory``) comes and is freed before the estimate's.

        Parameters
        ----------
        n_samples, n_modes : int
            Shape ``(T, M)`` of the history the fit will see.

        Returns
        -------
        int
            Bytes.
        """
        return 2 * 8 * n_samples * n_modes

    def fit_seconds(self, n_samples: int, n_modes: int) -> float:
        """Estimated CPU seconds of one ``fit`` (or refit), a lower bound [s].

        The base says 0 (not estimated): the predictors whose fits are slow at thousands
        of modes override it (``ARMAPredictor``). ``evaluate`` sums it over the fit and
        the refits of every predictor and refuses or warns before any work.
        ``(n_samples, n_modes)`` is the shape ``(T, M)`` of the history, as ``fit_bytes``'.
        """
        return 0.0

    # subclass hooks -------------------------------------------------------------
    def _memory(self, params: dict) -> int:
        """Past samples the recursion forecasts from (its lags); 0: none."""
        return 0

    def _fit_params(self, X: np.ndarray, previous: dict | None, name: str) -> dict:
        raise NotImplementedError

    def _estimate(self, X: np.ndarray, previous: dict | None, name: str) -> dict:
        """``_fit_params``, checked where it is a user's (:func:`user_defined`).

        A user's ``_fit_params`` gets a read-only view of the samples (it wrote zeros into
        the log ``evaluate`` was given) and its parameters are checked: a dict of finite
        values (NaN ones gave a table of NaN rmse) whose layout the recursion reads
        (:meth:`_check_layout`: parameters of one mode for a 3-mode log made the kernel
        write past its arrays, a SIGABRT; round 44 PART a, E04 - E06).
        """
        if not user_defined(type(self), "_fit_params"):
            return self._fit_params(X, previous, name)
        params = self._fit_params(_read_only(X), previous, name)
        who = f"{type(self).__name__}._fit_params"
        if not isinstance(params, dict):
            raise TypeError(f"{who} must return a dict of parameter arrays; got "
                            f"{type(params).__name__}.")
        for key, value in params.items():
            arr = np.asarray(value) if isinstance(value, np.ndarray | float | int) else None
            if arr is not None and arr.dtype.kind in "fc" and not np.all(np.isfinite(arr)):
                raise ValueError(f"{who} returned a non-finite value in parameter {key!r} "
                                 f"(fitted on `{name}` of shape {X.shape}); the forecasts "
                                 "would be NaN.")
        self._check_layout(params, X.shape[1], who)
        return params

    def _check_layout(self, params: dict, n_modes: int, who: str) -> None:
        """Refuse parameters whose shapes the recursion cannot read (a kind's own rule)."""

    def _filter_samples(self, X: np.ndarray) -> np.ndarray:
        """``X`` as ``_filter`` gets it: a read-only view where the hook is a user's.

        A user's ``_filter`` wrote into the blocks it was given, i.e. into the user's log
        (round 44 PART a, E07); the built-ins get ``X`` itself.
        """
        return _read_only(X) if user_defined(type(self), "_filter") else X

    def _init_state(self, params: dict, horizon: int) -> dict:
        raise NotImplementedError

    def _filter(self, params: dict, state: dict, X: np.ndarray, out: np.ndarray,
                status: np.ndarray) -> None:
        raise NotImplementedError

    def _step_function(self, params: dict, state: dict, out: np.ndarray,
                       status: np.ndarray):
        """Return ``step(X)`` running the kernel on a block with bound arguments.

        Subclasses may bind the kernel arguments in a closure to shave the per-call
        overhead of ``update``.
        """
        def step(X):
            self._filter(params, state, X, out, status)

        return step

    # ------------------------------------------------------------------ running
    def _new_run(self, horizon: int) -> _Run:
        # the refit policy is read here, from the hyper-parameters in force: ``window``
        # set after ``fit`` was ignored (the fit's ``window_`` kept) while ``refit_every``
        # set the same way applied at once (round 35 PART a, S2)
        self._refuse_model_changed()
        _, refit, window = self._check_common(self.n_modes_)
        _check_forecast_memory(horizon, self.n_modes_)
        W = self.n_samples_fit_ if window is None else window
        ring = W if refit is not None else None
        if ring is not None:  # the ring buffer of the last `window` samples
            check_memory(8.0 * ring * self.n_modes_, "window", ring,
                         f"the refit ring buffer of {self.n_modes_} mode(s)")
        self.window_ = W
        settings = operator.attrgetter(*self._param_names())
        run = _Run(self.params_, self._init_state(self.params_, horizon), horizon,
                   self.n_modes_, ring, refit, W, settings(self))
        run.settings = settings
        return run

    def _raise_nonfinite(self, status: np.ndarray, offset: int, name: str) -> None:
        if status[0]:
            index = offset + int(status[0]) - 1
            raise ValueError(f"`{name}` must be finite; got a NaN or infinite value at "
                             f"sample {index}.")

    def _feed(self, run: _Run, X: np.ndarray, out: np.ndarray, name: str,
              begin: int = 0, end: int | None = None) -> list:
        """Feed samples ``X[begin:end]`` to ``run`` (refits included).

        ``run`` must have seen exactly ``X[:begin]`` (so sample indices are absolute
        and refit windows are read from ``X``). The forecasts made after the last
        ``out.shape[0]`` samples of the range go to ``out``. Returns the list of
        ``(sample_index, params)`` of the refits made.
        """
        refit = run.refit
        end = X.shape[0] if end is None else end
        n_out = out.shape[0]
        start = begin
        refits = []
        while start < end:
            stop = end
            if refit is not None:
                # next refit point: smallest n > n_seen with n % R == 0 and n >= W
                n_next = (run.n_seen // refit + 1) * refit
                while n_next < run.window:
                    n_next += refit
                stop = min(end, start + n_next - run.n_seen)
            lo = start - end + n_out
            hi = stop - end + n_out
            sub_out = out[:0] if hi <= 0 else out[max(lo, 0):hi]
            block = self._filter_samples(X[start:stop])
            self._filter(run.params, run.state, block, sub_out, run.status)
            self._raise_nonfinite(run.status, start, name)
            run.n_seen += stop - start
            if (refit is not None and run.n_seen % refit == 0
                    and run.n_seen >= run.window):
                window_data = np.ascontiguousarray(X[stop - run.window:stop])
                self._refit_run(run, window_data, name)
                refits.append((run.n_seen - 1, run.params))
            start = stop
        return refits

    def _forecast_path(self, X: np.ndarray, horizon: int) -> tuple[np.ndarray, list]:
        """Forecasts after every sample of ``X`` from the reset state.

        Returns ``(path (T, H, M), refits)``; ``path[t, h - 1]`` forecasts
        ``X[t + h]`` from ``X[:t + 1]``.
        """
        run = self._new_run(horizon)
        out = np.zeros((X.shape[0], horizon, X.shape[1]))
        refits = self._feed(run, X, out, "history")
        return out, refits

    def predict(self, history, horizon: int | None = None) -> np.ndarray:
        """Forecast the samples following the end of ``history``.

        The history is fed to the recursion from the reset state (with the fitted
        parameters, and the refit schedule if one is set), exactly as ``reset``
        followed by one ``update`` per sample would.

        Parameters
        ----------
        history : array_like, shape (T,) or (T, M), or ModalLog
            Samples up to the forecast origin, with as many modes as at ``fit``. A
            ``ModalLog`` is read by its labels, rate and units: refused where they are
            not those of the log the predictor was fitted on (``columns_``,
            ``training_log_``); an array is read by position.
        horizon : int, optional
            Number of steps ``H``; default ``self.horizon``.

        Returns
        -------
        numpy.ndarray
            ``(H,)`` for 1-D input, else ``(H, M)``: forecasts for h = 1..H.
        """
        self._check_fitted()
        from modalinfo.telemetry.log import ModalLog

        if isinstance(history, ModalLog):
            # refused before with "(use log.coeffs)", whose array drops the labels, the
            # rate and the units that tell another log (round 55 PART b, X01-X07)
            self._check_log(history, "history")
            history = history.coeffs
        H = self._check_common()[0] if horizon is None else check_horizon(horizon)
        X, scalar = self._check_history(history, "history", 1)
        self._check_n_modes(X.shape[1], "history")
        self._check_columns(history, "history")
        memory = self._memory(self.params_)
        if X.shape[0] < memory:
            # the recursion starts from zeros (the online warm-up): the lags missing from
            # a short history were taken as 0, a forecast of another series without a word
            # (audit 10, feedback, rows pr-predict-short, pr-predict-1, mv-predict-1)
            raise ValueError(
                f"`history` must hold at least {memory} samples along axis 0: "
                f"{type(self).__name__} forecasts from its last {memory} (its lags); got "
                f"{X.shape[0]}.")
        run = self._new_run(H)
        out = np.zeros((1, H, X.shape[1]))
        self._feed(run, X, out, "history")
        return out[0, :, 0].copy() if scalar else out[0].copy()

    def _check_log(self, log, name: str) -> None:
        """Refuse a ``ModalLog`` unlike the one the predictor was fitted on.

        Its mode count and labels (``columns_``), then its rate and units against
        ``training_log_`` (set by ``fit`` of a ``ModalLog``): parameters fitted at 2 kHz
        forecast another series at 1 kHz (their lags count frames), and an intercept or
        training mean in nm is wrong on values in rad (round 55 PART b, X01-X07).
        """
        self._check_n_modes(log.n_modes, name)
        self._check_columns(None, name, [str(c) for c in log.labels],
                            select=f"{name}.select(modes=predictor.columns_)")
        # its clock and units: the one check of a fitted predictor's data (fix56-b)
        self.check_fed(None, rate=log.rate, units=log.units, wavelength=log.wavelength,
                       name=f"`{name}`")

    def _check_columns(self, history, name: str, names: list | None = None,
                       select: str = "history[predictor.columns_]") -> None:
        """Refuse a DataFrame whose column names differ from those of the fitted one.

        Fitted on columns ``Z2 .. Z7`` and given them as ``Z4, Z2, ...``, ``predict``
        read them by position and returned each forecast under another mode's name
        (adversarial round 42 PART a, M17; scikit-learn refuses this too). Arrays, and
        DataFrames when the fit had no column names, are read by position as before.
        ``names``: the names to check instead of ``history``'s columns (``update``'s
        sample, a Series whose index names the modes; fixes 42).
        """
        fitted = self.__dict__.get("columns_")
        if names is None:
            names = _frame_columns(history)
        if fitted is None or names is None or names == fitted:
            return
        shown = ", ".join(str(c) for c in names[:4]) + (", ..." if len(names) > 4 else "")
        expected = ", ".join(str(c) for c in fitted[:4]) + (", ..." if len(fitted) > 4 else "")
        raise ValueError(
            f"`{name}` has columns ({shown}) but {type(self).__name__} was fitted on "
            f"columns ({expected}): forecasts are made by position; select the columns in "
            f"the fitted order ({select}) or pass an array.")

    def _check_n_modes(self, n_modes: int, name: str) -> None:
        if n_modes != self.n_modes_:
            raise ValueError(
                f"`{name}` must have {self.n_modes_} mode(s) as the fitted history; "
                f"got {n_modes}."
            )

    def _learns_from_data(self) -> bool:
        """Whether the fitted parameters depend on the training data's values.

        False for a model of fixed weights (persistence, the paper's linear a = 2,
        b = -1): ``check_fed`` has no scale to compare for it, any data serve.
        """
        return True

    def check_fed(self, sample=None, *, rate: float | None = None, units: str | None = None,
                  wavelength: float | None = None, name: str = "the data") -> str:
        """Refuse data this fitted predictor was certainly not trained for; say what was checked.

        What a predictor fitted on a bare array can be checked against without its
        training conditions (fix56-b: ``closedloop.simulate`` checks a forecaster fitted
        on a run's log against the run's config, one fitted on an array ran unchecked):

        - the clock: a log's ``rate`` at ``fit`` against ``rate`` (lags count frames; more
          than ``RATE_TOLERANCE`` apart is refused);
        - the units: a log's stated units against ``units`` (refused when they differ),
          and phase in rad or waves at another ``wavelength`` (``WAVELENGTH_TOLERANCE``);
          ``"rad"`` without a wavelength is ``ModalLog``'s default, not a statement, and
          is not compared (``predict`` / ``update`` of a ``ModalLog`` and
          ``closedloop.simulate`` call this check; round 55 PART b, fix56-b);
        - the scale: the rms of each mode of ``sample`` against the training data's
          (``training_rms_``), as the median over the modes of their ratio; beyond
          ``SCALE_FACTOR`` either way (``SCALE_FACTOR_FEW`` on fewer than
          ``SCALE_FEW_MODES`` modes; data in nm fed rad: x80 at 500 nm; in m: 1e-7) the
          data are not of the series it was fitted on. Not compared for a model of fixed
          weights (persistence, ``LinearPredictor`` without ``fit_weights``): any data
          serve it.

        Parameters
        ----------
        sample : array_like, shape (n, M), or None
            Values of the data it will be fed (``M = n_modes_``), a few frames spread
            over the data (their rms about 0 is compared); None: no scale check.
        rate : float or None
            The data's frame rate [Hz]; None: not compared.
        units : str or None
            The data's units ("rad", "nm", "um" or "waves"); None: not compared.
        wavelength : float or None
            Wavelength [m] of the data's phase in rad; None: not compared.
        name : str
            The data's name in the messages.

        Returns
        -------
        str
            What was compared, in words (for a result's notes).

        Raises
        ------
        ValueError
            A rate, units or scale other than the training data's, naming both.
        """
        self._check_fitted()
        who = type(self).__name__
        said = []
        trained = self.__dict__.get("training_log_") or {}
        own_rate = trained.get("rate")
        if own_rate is not None and rate is not None:
            if abs(rate / own_rate - 1.0) > RATE_TOLERANCE:
                raise ValueError(
                    f"{who} was fitted on frames at {own_rate:.6g} Hz; {name} is at "
                    f"{rate:.6g} Hz: its lags count frames, so it forecasts another series "
                    "there; fit it on data at this rate.")
            said.append(f"rate {own_rate:.6g} Hz")
        u, wl = trained.get("units"), trained.get("wavelength")
        # "rad" without a wavelength is ModalLog's default, not a statement
        if u is not None and units is not None and (u != "rad" or wl is not None):
            if u != units:
                raise ValueError(f"{who} was fitted on a log in {u}; {name} is in {units}: "
                                 "convert one to the other's units before fitting.")
            # rad and waves scale as 1 / wavelength (round 55 PART b's predict check)
            if u in ("rad", "waves") and wl is not None and wavelength is not None and abs(
                    wavelength / wl - 1.0) > WAVELENGTH_TOLERANCE:
                raise ValueError(
                    f"{who} was fitted on phase [{u}] at {wl:.6g} m; {name} is phase at "
                    f"{wavelength:.6g} m ({u} scale as 1 / wavelength): convert the "
                    "training log to this wavelength before fitting.")
            said.append(f"units {u}" + (f" at {wl:.6g} m" if wl is not None else ""))
        own_rms = getattr(self, "training_rms_", None)
        if sample is not None and own_rms is not None and not self._learns_from_data():
            said.append("no scale (its parameters do not depend on the data it was fitted on)")
        elif sample is not None and own_rms is not None:
            arr = as_float_array(sample, "sample", ndim=(1, 2))
            arr = arr.reshape(-1, 1) if arr.ndim == 1 else arr
            if arr.shape[1] != own_rms.size:
                raise ValueError(f"`sample` must have {own_rms.size} mode(s) (columns) as "
                                 f"the fitted history; got shape {arr.shape}.")
            fed = rms_per_mode(arr)
            ratio, n_used = scale_ratio(fed, own_rms)
            if ratio is not None:
                limit = SCALE_FACTOR if n_used >= SCALE_FEW_MODES else SCALE_FACTOR_FEW
                if not 1.0 / limit <= ratio <= limit:
                    raise ValueError(
                        f"{name} has {ratio:.3g} times the rms of the data {who} was fitted "
                        f"on (median over {n_used} modes of the ratio of their rms; beyond x"
                        f"{limit:g} either way): not the series it was fitted on (other "
                        "units: nm against rad is x80 at 500 nm, m x1e-7?); fit it on data in "
                        f"the units of {name}.")
                said.append(f"scale x{ratio:.2g} of its training data's rms")
        return ", ".join(said)

    def __copy__(self) -> Predictor:
        # copy.copy shared the running state: the copy's update() advanced the original's
        # forecasts (audit 10-state, rows copy-shallow-*); a copy owns its pass (the fitted
        # parameters are replaced, never written in place, at refits)
        new = type(self).__new__(type(self))
        state = dict(self.__dict__)
        if state.get("_run") is not None:
            state["_run"] = copy.deepcopy(state["_run"])
        new.__setstate__(state)
        return new

    def __setstate__(self, state: dict) -> None:
        # a pickled or deep-copied predictor: rebind its run's step to its own arrays
        self.__dict__.update(state)
        run = state.get("_run")
        if run is not None:
            run.step = self._step_function(run.params, run.state, run.out, run.status)

    # ------------------------------------------------------------------ online
    def reset(self) -> None:
        """Start a new online pass: clear the state, restore the fitted parameters."""
        self._check_fitted()
        run = self._new_run(self._check_common()[0])
        run.step = self._step_function(run.params, run.state, run.out, run.status)
        self._run = run

    def update(self, x_t) -> np.ndarray:
        """Ingest the newest sample and forecast the next ``horizon`` samples.

        Constant cost per step: the fixed-size state is updated in place by a numba
        kernel (plus, with a refit policy, one ring-buffer write and a refit every
        ``refit_every`` steps).

        Parameters
        ----------
        x_t : float or array_like, shape (M,), or ModalLog of one frame
            The sample (one value per mode) measured at the current step; a one-frame
            ``ModalLog`` is checked as ``predict`` checks a log.

        Returns
        -------
        numpy.ndarray
            ``(H, M)`` forecasts of the next ``H`` samples (``(H,)`` for a scalar
            sample).
        """
        try:
            run = self._run
        except AttributeError:
            self._check_fitted()
            self.reset()
            run = self._run
        try:  # identical objects compare equal without calling their __eq__
            changed = run.settings(self) != run.config
        except (TypeError, ValueError):  # an array replaced by another: look closer
            changed = True
        if changed:
            self._refuse_changed(run)
        x = run.x
        if type(x_t) is float:
            if x.shape[1] != 1:
                self._check_n_modes(1, "x_t")
            x[0, 0] = x_t
            scalar = True
        else:
            if type(x_t) is np.ndarray and x_t.dtype == np.float64:  # the loop's case: as is
                arr = x_t
            else:  # complex lost its imaginary part, dates and strings were cast
                from modalinfo.telemetry.log import ModalLog

                if isinstance(x_t, ModalLog):
                    # one frame of a log, checked as predict checks a log: it was read
                    # as x_t[0], "a ModalLog is indexed by a frame slice ...; got 0", an
                    # indexing the caller never wrote (round 55 PART b, X09)
                    if x_t.n_frames != 1:
                        raise ValueError(f"`x_t` must be one sample; got a ModalLog of "
                                         f"{x_t.n_frames} frames (predict takes a history).")
                    self._check_log(x_t, "x_t")
                    x_t = x_t.coeffs[0]
                self._check_columns(x_t, "x_t", _frame_columns(x_t, "index", 1))
                arr = np.asarray(unmasked(x_t, "x_t"))
                check_real_dtype(arr, "x_t", x_t)
            scalar = arr.ndim == 0
            if scalar:
                if x.shape[1] != 1:
                    self._check_n_modes(1, "x_t")
                x[0, 0] = arr
            else:
                if arr.shape != (x.shape[1],):
                    raise ValueError(f"`x_t` must have shape ({x.shape[1]},); got "
                                     f"{arr.shape}.")
                x[0] = arr
        run.step(x)
        if run.status[0]:
            raise ValueError("`x_t` must be finite; got a NaN or infinite value.")
        run.n_seen += 1
        if run.ring is not None:
            self._online_refit(run, x)
        return run.out[0, :, 0].copy() if scalar else run.out[0].copy()

    def _refuse_changed(self, run: _Run) -> None:
        """Refuse an ``update`` after a hyper-parameter changed mid-pass.

        The online pass was built (ring buffer, forecast rows, refit schedule) from the
        hyper-parameters in force at the last ``reset`` or ``fit``; ``update`` kept the
        old horizon while ``predict`` used the new one, and raised a TypeError once
        ``refit_every`` became None (round 35 PART a, T1 and S1). A model setting
        changed since ``fit`` is refused as by ``predict`` (round 43 PART a, S37, S38);
        a forecast-time one (``_fit_free_params``) or an equal value lets the pass go on.
        """
        self._refuse_model_changed()
        old_config = dict(zip(self._param_names(), run.config, strict=True))
        names = ("horizon", "refit_every", "window")
        changed = [f"`{n}` {old_config[n]!r} -> {getattr(self, n)!r}"
                   for n in names if not _same_setting(old_config[n], getattr(self, n))]
        if not changed:
            run.config = run.settings(self)
            return
        raise ValueError(
            f"{', '.join(changed)} changed after the online pass began (the last reset() "
            "or fit()); call reset() to start a pass with the new value(s)."
        )

    def _refit_run(self, run: _Run, window_data: np.ndarray, name: str) -> None:
        """Refit ``run``'s parameters on ``window_data`` and keep its state valid for them.

        Where the new parameters keep the state's layout (a fixed order: every built-in
        predictor but ARMA with ``order="aic"`` / ``"bic"``), the recursion carries on
        from its state, bit for bit as before. Where they change it (the selected p, q
        of an ARMA refit), the state is rebuilt by feeding the window, the samples the
        refit saw, through the new recursion from the reset state: the old state was
        too short (the kernel wrote past its end: heap corruption, "malloc(): unaligned
        tcache chunk detected") or laid out for other orders (old AR lags read as
        innovations; adversarial round 34 PART a, L01-L02). The layout is told by the
        shapes of the parameters as well as of the state: ARMA(2, 4) -> ARMA(3, 3) keeps
        the state's p + q + 1 columns but not which are AR lags (fix52-d).
        """
        old = run.params
        run.params = self._estimate(window_data, run.params, name)
        fresh = self._init_state(run.params, run.horizon)
        if (all(np.shape(fresh[key]) == np.shape(run.state[key]) for key in fresh)
                and all(np.shape(value) == np.shape(old.get(key))
                        for key, value in run.params.items())):
            return
        scratch = np.zeros((0, run.horizon, window_data.shape[1]))
        self._filter(run.params, fresh, self._filter_samples(window_data), scratch,
                     run.status)
        run.state = fresh

    def _online_refit(self, run: _Run, x: np.ndarray) -> None:
        W = run.ring.shape[0]
        run.ring[run.ring_pos] = x[0]
        run.ring_pos = (run.ring_pos + 1) % W
        if run.n_seen % run.refit == 0 and run.n_seen >= W:
            window_data = np.concatenate([run.ring[run.ring_pos:], run.ring[:run.ring_pos]])
            self._refit_run(run, window_data, "x_t")
            run.step = self._step_function(run.params, run.state, run.out, run.status)


def _snapshot(value):
    """Return a copy of a hyper-parameter that later in-place changes of it do not reach."""
    if isinstance(value, (list, dict, set, np.ndarray)):
        return copy.deepcopy(value)
    return value


def _same_setting(a, b) -> bool:
    """Whether two hyper-parameter values are the same (arrays by content)."""
    if a is b:
        return True
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        try:
            return bool(np.array_equal(np.asarray(a), np.asarray(b)))
        except (TypeError, ValueError):
            return False
    try:
        return bool(a == b)
    except (TypeError, ValueError):
        return False


def _same(a, b) -> bool:
    try:
        return bool(a == b) if not isinstance(a, np.ndarray) else False
    except Exception:  # noqa: BLE001 - arrays or odd objects: show them
        return False
