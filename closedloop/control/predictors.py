"""Predictors inside the loop: one type, :class:`LoopPredictor`, for every shape of one.

A predictor in the loop is what ``closedloop run --predictor NAME`` asks for: no
prediction (:data:`NO_PREDICTION`, name ``"none"``), the true future (:data:`ORACLE`,
``"oracle"``: the bound no predictor can beat), or a :mod:`modalinfo.forecast` predictor
that is fitted on a no-prediction run before use, as in the paper (not ``persistence``,
which fits nothing: :meth:`LoopPredictor.ready` gives it the loop's mode count). The paper
trains its ARMA and neural net on "the standard MFoV MCAO simulation" (the run without
prediction, same conditions), after the loop closure: the NN on 10 patterns of 10 values
taken after 15 ms, the ARMA(2,3) from the autocovariance. :meth:`LoopPredictor.trained`
does that with the POL coefficients of a no-prediction :class:`SimulationResult` (every
DM's modes side by side), and :func:`closedloop.training.run_trained` runs that reference,
trains and simulates.

Names (:data:`NAMES`, checked once, by :meth:`LoopPredictor.from_name`): ``none``,
``persistence``, ``oracle`` and the keys of :data:`modalinfo.forecast.presets.PRESETS`:
the paper's configurations (``linear``: a = 2, b = -1; ``arma``: ARMA(2,3); ``nn-paper``:
10 patterns) beside the working defaults of :mod:`modalinfo.forecast` (``nn``,
``arma-aic``, ``multivariate``, ...). A run's result keeps the name given (``arma-aic``,
not the class name); a fitted predictor handed over directly is named by its class.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from modalinfo.common.quiet import caller_stacklevel, warn
from modalinfo.forecast import PersistencePredictor
from modalinfo.forecast.presets import PRESETS

if TYPE_CHECKING:
    from closedloop.result import SimulationResult

__all__ = ["NAMES", "LoopPredictor", "NO_PREDICTION", "ORACLE", "check_trained_for",
           "fitted_conditions", "loop_predictor", "training_conditions", "training_data",
           "training_start"]

#: every name ``closedloop run --predictor`` accepts (the forecast presets' list, plus
#: the three that are not forecast presets)
NAMES: tuple[str, ...] = ("none", "persistence", "oracle", *PRESETS)

#: how a predictor is trained: fitted on the POL of the no-prediction run of the same
#: conditions, after the loop closure and after 15 ms (the paper's way; see
#: :func:`training_start` for a run that did not close)
REFERENCE_POL = "reference-pol"

#: the paper trains after the loop closure, from t > 15 ms
_PAPER_TRAINING_START = 15e-3


@dataclass(frozen=True)
class LoopPredictor:
    """A predictor in the loop: its name, its forecaster and how it is trained.

    Make one with :meth:`from_name` (a name of ``closedloop.control.predictors.NAMES``, the one
    place names are checked) or :meth:`from_fitted` (a fitted :mod:`modalinfo.forecast`
    predictor); the two without a forecaster are the sentinels ``NO_PREDICTION`` and
    ``ORACLE``.

    Attributes
    ----------
    name : str
        The name the user gave (``"arma-aic"``); a run's result stores it.
    predictor : modalinfo.forecast.Predictor or None
        The forecaster of the POL coefficients of every DM (DM 0 first); None for no
        prediction and for the oracle.
    training : str or None
        ``REFERENCE_POL``: must be fitted on a no-prediction run before use
        (:meth:`trained`); None: ready to run.
    oracle : bool
        The true future instead of a forecast (only ``ORACLE``).
    trained_on : dict or None
        ``training_conditions`` of the reference run it was fitted on (set by
        :meth:`trained`; ``simulate`` refuses a config with other conditions); None for a
        forecaster fitted elsewhere (:meth:`from_fitted`).
    fitted_log : dict or None
        For a forecaster fitted on a ``ModalLog`` (:meth:`from_fitted`): that log's
        ``rate``, ``units``, ``wavelength``, ``labels`` and ``quantity`` (residual, pol,
        commands where its source says), which ``simulate`` checks against what the
        loop feeds it (``fitted_log``); None otherwise.
    """

    name: str
    predictor: Any = None
    training: str | None = None
    oracle: bool = False
    trained_on: dict | None = field(default=None, compare=False)
    fitted_log: dict | None = field(default=None, compare=False)

    @classmethod
    def from_name(cls, name: str) -> LoopPredictor:
        """Return the predictor called ``name`` (unfitted, with a fresh forecaster).

        Raises
        ------
        ValueError
            If ``name`` is not one of ``closedloop.control.predictors.NAMES``.
        """
        if not isinstance(name, str) or name not in NAMES:
            raise ValueError(f"`predictor` must be one of {', '.join(NAMES)}; got {name!r}.")
        if name == "none":
            return NO_PREDICTION
        if name == "oracle":
            return ORACLE
        if name == "persistence":
            # fits nothing: no reference run to train on, and --train-seed is refused
            # with it (round 37 PART b, CL01 / CL02); ``ready`` gives it its mode count
            return cls(name=name, predictor=PersistencePredictor())
        return cls(name=name, predictor=PRESETS[name][1](), training=REFERENCE_POL)

    @classmethod
    def from_fitted(cls, predictor, name: str | None = None) -> LoopPredictor:
        """Wrap a fitted forecaster (named by its class unless ``name`` is given).

        A forecaster fitted on a closed-loop run's log (``Predictor.fit(result.logs[
        "dm0.pol"])``, its ``training_metadata_`` holding the run's config) carries that
        run's ``training_conditions`` as ``trained_on``, so ``simulate`` refuses it in
        a loop of other conditions as it refuses a :meth:`trained` one (fix54-b, round
        53 PART a C16 / C22), and so does one fitted on a run's AOT export (its config read
        back, fix57-d). One fitted on any ``ModalLog`` is refused where that log is not
        what the loop feeds: another series (the residual, the commands), rate, units,
        wavelength or mode labels (``fitted_log``, round 55 PART b, X43-X65). One fitted
        on an array carries none: ``simulate`` then checks only what it can without them
        (``Predictor.check_fed``: the scale of its training data against the loop's POL;
        fix56-b).

        Raises
        ------
        TypeError
            If ``predictor`` has no ``update`` (not a :mod:`modalinfo.forecast` predictor).
        """
        if not hasattr(predictor, "update") or not hasattr(predictor, "reset"):
            raise TypeError("`predictor` must have reset() and update(x) (a modalinfo.forecast "
                            f"Predictor); got {type(predictor).__name__}.")
        return cls(name=type(predictor).__name__ if name is None else name,
                   predictor=predictor, trained_on=fitted_conditions(predictor),
                   fitted_log=fitted_log(predictor))

    @property
    def is_none(self) -> bool:
        """True for no prediction (the loop's plain integrator)."""
        return self.predictor is None and not self.oracle

    @property
    def needs_training(self) -> bool:
        """Whether :meth:`trained` must run before the loop can use it."""
        return self.training is not None

    @property
    def _shape_only(self) -> bool:
        """A persistence not yet fitted: its fit records the mode count, nothing else."""
        return (isinstance(self.predictor, PersistencePredictor)
                and getattr(self.predictor, "n_modes_", None) is None)

    def ready(self, n_modes: int) -> LoopPredictor:
        """Return this predictor ready for a loop that feeds it ``n_modes`` values.

        A persistence from :meth:`from_name` is fitted here on zeros: its parameters
        (``x_hat[n + h] = x[n]``) are those of any data, so no reference run is made
        for it (round 37 PART b, CL01 / CL02). Any other predictor is returned as is.
        """
        if not self._shape_only:
            return self
        forecaster = copy.deepcopy(self.predictor).fit(np.zeros((2, int(n_modes))))
        return dataclasses.replace(self, predictor=forecaster)

    def trained(self, reference: SimulationResult,
                basis: np.ndarray | None = None) -> LoopPredictor:
        """Return this predictor fitted on the no-prediction run ``reference``.

        Parameters
        ----------
        reference : SimulationResult
            The run without prediction (same conditions): its POL after the loop closure
            and after 15 ms (``closedloop.control.predictors.training_data``) is the training set.
        basis : (M, n) array or None
            Fit on the projection ``POL @ basis`` (a run with this ``control_basis``
            feeds the predictor ``B^T p``); None: every mode.

        Returns
        -------
        LoopPredictor
            A new one, ready to run (``training`` None); ``self`` is unchanged (its
            forecaster is copied before fitting). Itself when nothing is to train.

        Notes
        -----
        Short reference runs of smooth modes ask for unit roots: on the loop tests' 0.15 s
        run (135 training frames) the ARMA(2, 3) holds the AR roots of 18 of 55 modes at
        its ``root_margin`` limit (their least-squares AR(2) radii 0.9992-1.034; fix57-a).
        The fit records it (the trained forecaster's ``roots_held_``) and nothing warns
        here: the loop uses its point forecasts a delay ahead and states no interval, the
        number the clamp makes wrong; ``forecast_std`` / ``predict_interval`` /
        ``evaluate`` of that forecaster say it (``RootLimitWarning``).
        """
        if not (self.needs_training or self._shape_only):
            return self
        data = training_data(reference)
        if basis is not None:
            data = data @ basis
        forecaster = copy.deepcopy(self.predictor)
        forecaster.fit(data)
        config = getattr(reference, "config", None)
        known = all(hasattr(config, k) for k in ("telescope", "layers", "dms", "wfss", "loop",
                                                   "r0_wavelength"))
        trained_on = None
        if known:
            trained_on = {**training_conditions(config), "control_basis": _digest(basis)}
        return dataclasses.replace(self, predictor=forecaster, training=None,
                                   trained_on=trained_on)

    def __repr__(self) -> str:
        state = ", untrained" if self.needs_training else ""
        return f"LoopPredictor({self.name!r}{state})"


def training_conditions(config) -> dict:
    """Return what shapes the POL a predictor learns: the parts a reference run must share.

    The turbulence (telescope, layers, ``r0_wavelength``), what is measured and corrected
    (sensors, mirrors and their modes) and the frame clock (``loop.time_step``,
    ``loop.integration_time``): a forecaster's lags count frames. The controller
    (gain, leak, delay, reconstructor), the seed, the science wavelength and the field
    may differ: the POL estimates the turbulence whatever the loop does (the
    compression study trains once for every delay).
    """
    return {"telescope": config.telescope, "layers": config.layers, "dms": config.dms,
            "wfss": config.wfss, "loop.time_step": config.loop.time_step,
            "loop.integration_time": config.loop.integration_time,
            "r0_wavelength": config.r0_wavelength}


def fitted_conditions(predictor) -> dict | None:
    """Return the ``training_conditions`` of the run a bare forecaster was fitted on, or None.

    Read from ``predictor.training_metadata_`` (``Predictor.fit`` of a ``ModalLog``
    keeps the log's metadata): a closed-loop log's ``"config"`` (``source`` "closedloop",
    ``SimulationResult.from_run``; a run's AOT export read by ``modalinfo.io.load`` since
    fix57-d). None for a forecaster fitted on an array or on another source's log: what
    it was trained on is unknown here.

    Raises
    ------
    ValueError
        The log's config is not one this version reads (an export of an older version
        with a renamed key): its conditions cannot be compared.
    """
    meta = getattr(predictor, "training_metadata_", None)
    if not isinstance(meta, dict) or meta.get("source") != "closedloop" or not isinstance(
            meta.get("config"), dict):
        return None
    from closedloop.config import SimulationConfig

    try:
        config = SimulationConfig.from_dict(meta["config"])
    except (TypeError, ValueError) as exc:
        raise ValueError(
            "`predictor` was fitted on a closedloop log whose run config this version does "
            f"not read ({exc}): its training conditions cannot be checked; fit it on a log "
            "of a run of this version") from None
    return training_conditions(config)


#: What the loop feeds a forecaster, in the messages of its checks (``check_fitted_log``,
#: ``closedloop.simulation``'s scale check).
LOOP_POL = "the loop's POL [rad at r0_wavelength]"


def fitted_log(predictor) -> dict | None:
    """Return what the ``ModalLog`` a bare forecaster was fitted on was, or None.

    ``rate`` [Hz], ``units``, ``wavelength`` [m] (``Predictor.fit``'s
    ``training_log_``), ``labels`` (its ``columns_``) and ``quantity``: closedloop's
    word for the series (``"residual"``, ``"pol"``, ``"commands"``; the log's
    ``coefficient_quantity`` as the AOT and HDF5 readers set it, else its ``quantity``
    where its ``source`` is closedloop), None when not said. None for a forecaster
    fitted on an array or a DataFrame: nothing is known of it.
    """
    log = getattr(predictor, "training_log_", None)
    if not isinstance(log, dict):
        return None
    meta = getattr(predictor, "training_metadata_", None)
    meta = meta if isinstance(meta, dict) else {}
    quantity = meta.get("coefficient_quantity")
    if quantity is None and meta.get("source") == "closedloop":
        quantity = meta.get("quantity")
    labels = getattr(predictor, "columns_", None)
    return {**log, "labels": None if labels is None else [str(c) for c in labels],
            "quantity": quantity if isinstance(quantity, str) else None}


def check_fitted_log(predictor: LoopPredictor, config, labels=None) -> None:
    """Refuse a forecaster fitted on a log unlike the POL this loop feeds it.

    The loop feeds the pseudo-open-loop coefficients of every DM, in rad at
    ``config.r0_wavelength``, one frame per ``config.loop.time_step``, labelled
    ``labels`` (every DM's modes, DM 0 first; None: not checked, as under a
    ``control_basis``). A forecaster fitted on the run's residual lost the loop (SR 0.004
    to 0.02 against 0.56-0.61), one fitted on the POL in nm halved its SR (its intercept
    and training mean in nm), and one fitted on a run's AOT export (no config in its
    metadata then, so :func:`fitted_conditions` knew nothing; read back since fix57-d)
    ran at twice its rate without a word (round 55 PART b, X43-X65).
    """
    log = predictor.fitted_log
    if not log:
        return
    who = f"`predictor` {predictor.name!r}"
    quantity = log.get("quantity")
    if quantity in ("residual", "commands"):
        raise ValueError(
            f"{who} was fitted on a run's {quantity} log, but the loop feeds it the "
            "pseudo-open loop (POL): fit it on the POL log (result.logs['dm0.pol'], or "
            "--loop dm0.pol of the AOT export), or use LoopPredictor.trained(reference).")
    # the clock and units: the forecaster's own check (Predictor.check_fed, fix56-b),
    # which simulate's scale check calls too
    if hasattr(predictor.predictor, "check_fed"):
        try:
            predictor.predictor.check_fed(None, rate=1.0 / config.loop.time_step,
                                          units="rad", wavelength=config.r0_wavelength,
                                          name=LOOP_POL)
        except ValueError as exc:
            raise ValueError(f"{who}: {exc}") from None
    fitted = log.get("labels")
    if labels is not None and fitted is not None and list(fitted) != list(labels):
        shown = ", ".join(fitted[:4]) + (", ..." if len(fitted) > 4 else "")
        fed = ", ".join(labels[:4]) + (", ..." if len(labels) > 4 else "")
        raise ValueError(
            f"{who} was fitted on modes ({shown}) but the loop feeds it ({fed}) by "
            "position: fit it on the POL's modes in the loop's order "
            "(log.select(modes=...), Noll convention).")


def _digest(basis) -> str | None:
    """SHA-256 of a control basis's float64 values and shape (None: every mode)."""
    if basis is None:
        return None
    b = np.ascontiguousarray(np.asarray(basis, dtype=np.float64))
    return hashlib.sha256(repr(b.shape).encode() + b.tobytes()).hexdigest()


def check_trained_for(predictor: LoopPredictor, config, control_basis=None) -> None:
    """Refuse a predictor trained on a reference run of other ``training_conditions``.

    A forecaster trained on a run at half the frame rate or four times the wind was run
    in this loop without a word (audit 10, feedback, rows rt-ref-other-rate,
    rt-ref-other-wind, sim-trained-other-rate): its weights model another series.
    """
    own = predictor.trained_on
    if own is None:
        return
    here = training_conditions(config)
    if "control_basis" in own and own["control_basis"] != _digest(control_basis):
        # fitted on POL @ B1 and fed POL @ B2 of the same width: another series
        raise ValueError(
            f"`predictor` {predictor.name!r} was trained on the POL projected on another "
            "control basis than `control_basis` (or on every mode): train it with this "
            "basis (LoopPredictor.trained(reference, basis=control_basis)).")
    for key, value in here.items():
        if own.get(key) != value:
            shown = (f"{own.get(key)!r} vs {value!r}" if isinstance(value, float)
                     else "they differ")
            raise ValueError(
                f"`predictor` {predictor.name!r} was trained on a reference run whose "
                f"`{key}` is not this config's ({shown}): train it on a run of this config "
                "(a reference may differ only in the controller: gain, leak, delay, "
                "reconstructor; and in seed, science wavelength and field).")


#: no prediction: the loop's integrator alone
NO_PREDICTION = LoopPredictor(name="none")
#: the true future POL (noise-free measurement of the turbulence over the command's hold)
ORACLE = LoopPredictor(name="oracle", oracle=True)


def loop_predictor(predictor) -> LoopPredictor:
    """Read a ``predictor`` argument of :func:`closedloop.simulate` (the one place it is read).

    A :class:`LoopPredictor` is returned as is; None is :data:`NO_PREDICTION`; a fitted
    :mod:`modalinfo.forecast` predictor is wrapped (named by its class); the string
    ``"oracle"`` is :data:`ORACLE` with a ``DeprecationWarning`` (pass
    ``closedloop.ORACLE``). Other names need training: they are refused, pointing to
    :func:`closedloop.run_trained` and :meth:`LoopPredictor.from_name`.

    Raises
    ------
    ValueError
        A string other than ``"oracle"``.
    TypeError
        Anything else that is not a predictor.
    """
    if isinstance(predictor, LoopPredictor):
        return predictor
    if predictor is None:
        return NO_PREDICTION
    if isinstance(predictor, str):
        if predictor == "oracle":
            warn("simulate(predictor='oracle') is deprecated; pass closedloop.ORACLE.",
                 DeprecationWarning, stacklevel=caller_stacklevel())
            return ORACLE
        raise ValueError(f"`predictor` must be a LoopPredictor, a fitted Predictor or None; "
                         f"got the name {predictor!r} (a name is trained first: "
                         "closedloop.run_trained(config, name, ...) or "
                         "LoopPredictor.from_name(name).trained(reference)).")
    return LoopPredictor.from_fitted(predictor)


def training_start(result: SimulationResult) -> int:
    """First frame a predictor is trained from: the run's averaging window, after 15 ms.

    The paper trains after the loop closure, from t > 15 ms. The closure is the run's
    :attr:`~closedloop.SimulationResult.averaging_start` (the one window of every average
    of a run, docs/CLOSEDLOOP.md): the detected closure if the loop closed; the second
    half if it did not close or is still converging (its ``closure_index`` is then no
    closure: 0 for an SR that never rose, which would train on the open-loop start); the
    whole run in open loop. The POL (commands plus the measured residual) estimates the
    turbulence whether the loop closed or not, so a stable run that did not close still
    trains, on its latest frames, those nearest to what the loop settles to.

    Raises
    ------
    ValueError
        If the run diverged: its POL then holds the loop's own growing error (or is not
        finite), not the turbulence a predictor should learn.
    """
    if result.diverged:
        raise ValueError(f"the reference run {result.loop_status}; a predictor cannot be "
                         "trained on its POL (fix the loop first: a lower gain, a shorter "
                         "delay).")
    return max(int(result.averaging_start),
               int(np.searchsorted(result.times, _PAPER_TRAINING_START, side="right")))


def training_data(reference: SimulationResult) -> np.ndarray:
    """POL coefficients ``(T, M)`` of every DM from :func:`training_start` on.

    After the loop closure (the second half of a run that did not close) and after 15 ms.
    """
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
