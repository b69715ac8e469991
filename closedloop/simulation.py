"""The closed loop: one function that composes atmosphere, mirrors, sensors and control.

The parts share one protocol (:mod:`closedloop.parts`); the static ones live in a
:class:`~closedloop.model.LoopModel`, the time-varying ones in a
:class:`~closedloop.state.LoopState`, and :func:`simulate` is the loop over them. Its
options are small parts of their own here: the oracle (:class:`_Oracle`), the
control-basis projection and open loop (:class:`_Control`), the snapshots
(:class:`_Snapshots`) and the error-budget probe (:class:`closedloop.budget.BudgetProbe`).

:func:`simulate` runs the loop on an internal grid ``oversampling`` times finer than the
frame (so that a fractional delay or exposure is exact, as in :mod:`modalinfo.servo`):

at every internal step ``s`` (time ``t_s``)
    1. a command whose time has come is put on its DM (one matrix product per DM),
    2. the layers move to ``t_s`` (frozen flow), and each plane's residual map is its
       layers' phase minus its DMs' surfaces,
    3. inside the exposure window the maps are accumulated for the WFSs;
at the last step of frame ``k``
    4. the science camera takes the piston-removed residual variance in every direction,
    5. each WFS measures the exposure-averaged maps (plus noise) and reconstructs its
       DM's modal residual; the controller forms the POL, asks the predictor, and
       computes the command, which waits for ``delay`` before it is applied.

The science camera therefore samples the residual once per frame, at the frame's last
internal step (an instantaneous Strehl, not one averaged over the frame's internal steps;
see ``closedloop.optics.science``). In open loop (``loop.closed = false``) every command is
replaced by zero: the DMs stay flat, and the residual and POL logs are both the open-loop
modal turbulence the WFSs see.

Everything random (screens, noise) comes from one ``numpy.random.SeedSequence(seed)``:
the same seed and thread count give the same bits.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import pickle
import time
from collections import deque
from collections.abc import Callable

import numpy as np

from closedloop.budget import BudgetProbe, noise_variance
from closedloop.config import MAX_SEED, LoopConfig, SimulationConfig
from closedloop.control.controller import PREDICTOR_FAULT_ACTIONS, Controller, PredictorFault
from closedloop.control.predictors import (
    LOOP_POL,
    ORACLE,
    LoopPredictor,
    check_fitted_log,
    check_trained_for,
    loop_predictor,
)
from closedloop.model import LoopModel
from closedloop.optics.products import FLOAT32_MIN_BYTES
from closedloop.optics.science import ScienceCamera
from closedloop.result import SimulationResult
from closedloop.state import LoopState
from modalinfo.common.validation import check_real
from modalinfo.forecast import PersistencePredictor

#: noise draws of the noise floor loop_status judges by (the budget's term uses 64)
_FLOOR_DRAWS = 16

__all__ = ["simulate", "ORACLE", "LoopModel", "check_run"]


def _one_run_per_model(func):
    """Run ``func`` (``simulate``) holding its ``model`` (:meth:`LoopModel.running`)."""
    @functools.wraps(func)
    def wrapper(config, duration, *args, model=None, **kwargs):
        if model is None or not isinstance(model, LoopModel):  # a new model, or refused
            return func(config, duration, *args, model=model, **kwargs)
        with model.running():
            return func(config, duration, *args, model=model, **kwargs)

    return wrapper



@_one_run_per_model
def simulate(
    config: SimulationConfig,
    duration: float,
    *,
    predictor=None,
    seed: int | None = None,
    progress: bool | None = None,
    model: LoopModel | None = None,
    snapshot_every: int | None = None,
    snapshot_directions: np.ndarray | None = None,
    callback: Callable[[int], None] | None = None,
    budget_every: int | None = None,
    control_basis: np.ndarray | None = None,
    on_predictor_fault: str = "raise",
    memory_limit: float | None = None,
) -> SimulationResult:
    """Run the closed loop for ``duration`` seconds.

    Parameters
    ----------
    config : SimulationConfig
    duration : float
        Simulated time [s] (a whole number of frames is run: ``round(duration / T)``);
        longer than ``T + loop.delay`` (the first command reaches the mirror then).
    predictor : closedloop.control.predictors.LoopPredictor, modalinfo.forecast.Predictor or None
        Forecaster of the POL coefficients of all DMs (concatenated, DM 0 first); it
        must be fitted (a ``LoopPredictor`` trained, see :func:`closedloop.run_trained`)
        and its ``horizon`` must cover the lead. The result stores its name (a bare
        ``Predictor``'s: its class name). :data:`closedloop.ORACLE` uses the
        true future (noise-free WFS measurement of the turbulence alone over the
        command's hold): the bound no predictor can beat. Must be None in open loop
        (``config.loop.closed`` False), as must ``budget_every`` and ``control_basis``.
        The string ``"oracle"`` is deprecated (a ``DeprecationWarning``); other names
        are refused (they need training: :func:`closedloop.run_trained`). A predictor
        trained on a run of other ``training_conditions`` (telescope, layers, sensors,
        mirrors, frame clock) is refused: a trained ``LoopPredictor``, and a bare
        ``Predictor`` fitted on a run's ``ModalLog`` (``result.logs["dm0.pol"]``, whose
        metadata holds the run's config; fix54-b). A bare ``Predictor`` fitted on any
        ``ModalLog`` (an AOT export's too) is refused where that log is not what the loop
        feeds: a run's residual or commands, another frame rate, units other than rad,
        another wavelength than ``r0_wavelength``, other mode labels
        (``closedloop.control.predictors.check_fitted_log``, round 55 PART b). One fitted
        on a bare array (or on a log that is no run's) carries no conditions: before the
        loop it is checked against what the loop will feed it (``Predictor.check_fed``:
        the rms per mode of its training data against 16 frames of this run's turbulence
        sensed with its WFS noise, refused beyond x10 either way, x30 on fewer than 4
        modes: data in nm, um or m fed rad; fix56-b), and every log's
        ``metadata["predictor_check"]`` says that its conditions were not checked and
        what was.
    seed : int or None
        Overrides ``config.seed``; in ``[0, 2**63 - 1]``, as ``config.seed`` (the result
        file stores it as a 64-bit integer).
    progress : bool or None
        tqdm bar on stderr; None: only when stderr is a terminal.
    model : LoopModel or None
        Reuse the set-up of an earlier run of the same config.
    snapshot_every : int or None
        Every this many frames, store the residual pupil phase of ``snapshot_directions``
        (for FFT-PSF checks); an int in [1, number of frames].
    snapshot_directions : (n, 2) array or None
        Directions [arcsec] of the snapshots (default: the optical axis), inside the
        science field (``|x|, |y| <= field.size / 2``); only with ``snapshot_every``.
    callback : callable or None
        Called with the frame index after every frame.
    budget_every : int or None
        Estimate the error budget (:mod:`closedloop.budget`) every this many frames;
        ``result.budget`` then holds it (None otherwise). Costs about one more loop. An
        int in [1, ceil(frames / 2)], so that frames after the loop closure are probed.
    control_basis : (M, n) array or None
        Control only the span of these ``n`` orthonormal columns of the space of every
        DM's mode coefficients (``M = model.n_modes``, DM 0 first): the reconstructed
        residual is projected, ``m_n = B^T m``, the integrators and the predictor run on
        the ``n`` coefficients (the predictor sees ``B^T p``), and the command is
        ``B c_n``. The logs keep all ``M`` modes (the POL of an uncontrolled direction is
        its measured residual). None: every mode (``B = I``). Used by the compression
        study (``closedloop.studies.compression``).
    on_predictor_fault : {"raise", "hold"}
        The predictor's output is checked at every step (shape exactly ``(horizon, M)``,
        every value finite). ``"raise"``: stop with
        ``closedloop.control.controller.PredictorFault`` naming the predictor, the step and the
        mode. ``"hold"``: keep the last command for that frame and go on; a
        ``RuntimeWarning`` at the end says how many frames were held.
    memory_limit : float or None
        Refuse (``MemoryError``, before any work) a run whose estimated memory
        (``closedloop.resources.estimate``) exceeds this many bytes; None: half the
        machine's available memory.

    Returns
    -------
    SimulationResult
    """
    duration, loop_pred = _check_arguments(config, duration, predictor, on_predictor_fault,
                                           budget_every, control_basis, snapshot_every,
                                           progress, callback)
    snapshot_directions = _check_snapshot_directions(snapshot_directions, snapshot_every,
                                                     config.field)
    oracle = loop_pred.oracle
    from closedloop.resources import check_resources

    check_resources(config, duration, limit=memory_limit, oracle=oracle,
                    budget=bool(budget_every), setup=model is None)
    model = _model_for(config, model)
    seed = _check_seed(config.seed if seed is None else seed)
    basis = _check_control_basis(control_basis, model.n_modes, budget_every)
    loop_pred = _ready_predictor(loop_pred, config, model, basis)
    clock = _Clock.of(config.loop, duration)
    state = LoopState(model, model.atmosphere(seed, clock.run_time),
                      model.science.plane_views())
    note = _check_fed(loop_pred, model, state, clock, seed, basis)  # then state.reset()
    forecaster = _run_copy(loop_pred.predictor)  # None for the oracle and without prediction
    control = _Control(model, config.loop, forecaster, basis, on_predictor_fault)
    future = _Oracle(model, seed, clock) if oracle else None
    probe = (BudgetProbe(model, forecaster, int(budget_every), oracle=oracle)
             if budget_every else None)
    exposure, logs = _Exposure(state.maps), _Logs(model, clock.n_frames)
    snapshots = _Snapshots(model.science, snapshot_every, snapshot_directions)
    rng, pending = model.noise_rng(seed), deque()
    bar = _progress_bar(progress, clock.n_frames)
    start = time.perf_counter()
    try:
        for k in range(clock.n_frames):
            for i in range(clock.n_os):
                s = k * clock.n_os + i
                while pending and pending[0][0] <= s:  # a command whose time has come
                    state.apply(pending.popleft()[1])
                state.evolve_until(s * clock.dt)
                state.forward()
                if probe is not None:
                    probe.step(s, state, clock.in_exposure(i))
                if clock.in_exposure(i):
                    exposure.add(state.maps)
            logs.variance[k] = model.science.forward()
            snapshots.take(k)
            measurements = model.measure(exposure.mean(clock.n_int), rng)
            measured = model.reconstruct(measurements)
            exposure.clear()
            forecast = None if future is None else future.forecast(clock.apply_step(k))
            command, pol = control.step(measured, forecast)
            if probe is not None:
                probe.frame_end(k, clock.n_int, clock.apply_step(k),
                                None if future is None else future.maps)
            logs.record(k, measured, pol, command, measurements)
            pending.append((clock.apply_step(k), command.copy()))
            if bar is not None:
                bar.update(1)
            if callback is not None:
                callback(k)
    finally:
        if bar is not None:
            bar.close()
    elapsed = time.perf_counter() - start
    _warn_held(control.controller, loop_pred.name, clock.n_frames)
    return _assemble(config, seed, model, logs, snapshots, probe, elapsed, loop_pred.name, note)


def _ready_predictor(loop_pred: LoopPredictor, config: SimulationConfig, model: LoopModel,
                     basis) -> LoopPredictor:
    """Return the predictor ready for this loop's modes, checked against its feed.

    Its mode count (:func:`_check_predictor_modes`), and, without a control basis, the
    log it was fitted on: the series, clock, units and the modes by label
    (``check_fitted_log``, round 55 PART b, X63 / X64). Kept out of :func:`simulate`,
    which reads in a page.
    """
    loop_pred = loop_pred.ready(model.n_modes if basis is None else basis.shape[1])
    _check_predictor_modes(loop_pred.predictor, model.n_modes, basis)
    if basis is None:
        check_fitted_log(loop_pred, config, [
            label for dm in model.dms
            for label in ([f"Z{j}" for j in dm.modes] if dm.modes else list(dm.labels))])
    return loop_pred


def check_run(config: SimulationConfig, duration: float, *, budget_every: int | None = None,
              snapshot_every: int | None = None) -> None:
    """Refuse, before any set-up, a run :func:`simulate` would refuse (cheap).

    The loop gain must be stable (:func:`modalinfo.servo.check_stable`), the run longer
    than ``time_step + delay`` (when the first command reaches the mirrors), and the
    intervals inside the run (see :func:`simulate`). Raises ``ValueError`` naming the
    argument or config key, the rule and the value.
    """
    from modalinfo.servo import check_stable

    loop = config.loop
    try:  # before any set-up: an unstable gain costs nothing
        check_stable(loop.gain, loop.delay_frames, loop.integration_frames, leak=loop.leak)
    except ValueError as exc:
        raise ValueError(str(exc).replace("`gain`", "`loop.gain`", 1)
                         .replace("leak=", "loop.leak=", 1)) from None
    from closedloop.resources import MAX_FRAMES

    if not duration / loop.time_step < MAX_FRAMES:  # 1e308 s: round() of inf overflowed
        raise ValueError(f"`duration` must be at most {MAX_FRAMES:g} frames (loop.time_step = "
                         f"{loop.time_step:g} s); got {duration:g} s.")
    n_frames = round(duration / loop.time_step)
    first = loop.time_step + loop.delay
    if n_frames < 1:
        raise ValueError(f"`duration` must be at least one frame (loop.time_step = "
                         f"{loop.time_step:g} s); got {duration:g} s.")
    # open loop applies no command: any whole number of frames is a valid run
    if loop.closed and n_frames * loop.time_step <= first * (1 + 1e-9):
        # the rule as applied: the run is whole frames, round(duration / time_step); state
        # them, and the fewest that close the loop (fixes 45-c, round 45 PART b T106:
        # 0.0010001 s was refused as not longer than 0.001 s, the 2 frames it rounds to)
        least = math.floor(first * (1 + 1e-9) / loop.time_step) + 1
        raise ValueError(
            f"`duration` must be longer than loop.time_step + loop.delay = {first:g} s (the "
            f"first command reaches the mirror then, so a shorter run never closes the "
            f"loop); got {duration:g} s, which rounds to {n_frames} frame(s) of "
            f"loop.time_step = {loop.time_step:g} s ({n_frames * loop.time_step:g} s): give "
            f"{least} frames or more ({least * loop.time_step:g} s).")
    for name, value, high, why in (
            ("budget_every", budget_every, n_frames - n_frames // 2,
             "at most half the run, so that the budget averages frames after the loop "
             "closure"),
            ("snapshot_every", snapshot_every, n_frames, "at most the run")):
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or not (
                1 <= value <= high):
            raise ValueError(f"`{name}` must be None or an int in [1, {high}] frames ({why}, "
                             f"{n_frames} frames); got {value!r}.")


def _labelled(exc: PredictorFault, model: LoopModel, basis) -> PredictorFault:
    """Return ``exc`` with the DM and Zernike mode of its mode index in the message."""
    if exc.mode is None or basis is not None:
        return exc
    for d, sl in enumerate(model.mode_slices):
        if sl.start <= exc.mode < sl.stop:
            label = model.dms[d].labels[exc.mode - sl.start]
            text = str(exc).replace(f"for mode {exc.mode} ",
                                    f"for mode {exc.mode} (dm{d} {label}) ", 1)
            return PredictorFault(text, step=exc.step, mode=exc.mode)
    return exc


def _run_copy(predictor):
    """Return the run's own copy of the caller's predictor (None stays None).

    A run resets and updates its forecaster at every frame: runs in several threads
    sharing one fitted predictor interleaved their updates (Strehl ratios off the serial
    runs', audit 10-state, row thr-sim-shared-pred), and a run left the caller's own
    online stream advanced. A deep copy of a fitted predictor forecasts the same bits
    (tests/forecast/test_copy_round9.py); an object that cannot be deep-copied is used
    as given.
    """
    if predictor is None:
        return None
    try:
        return copy.deepcopy(predictor)
    except (TypeError, AttributeError, copy.Error, pickle.PicklingError):
        return predictor


def _check_open_loop(predictor, budget_every, control_basis) -> None:
    """Refuse what has no meaning when no command is applied (``loop.closed = false``)."""
    for name, value, given in (("predictor", predictor, predictor is not None),
                               ("budget_every", budget_every, bool(budget_every)),
                               ("control_basis", control_basis, control_basis is not None)):
        if given:
            shown = repr(value) if isinstance(value, str | int) else type(value).__name__
            raise ValueError(f"`{name}` must be None in open loop (`loop.closed = false`: no "
                             f"command is applied); got {shown}.")


#: Frames of the turbulence, spread over the run, that a forecaster fitted without
#: known conditions is compared with before the loop (``_check_fed``): 16 sensings cost
#: 16 frames' WFS measurement, and 16 frames x the loop's modes give the median ratio
#: of the rms per mode within x0.6-x1.6 on the simulator (docs/ADVERSARIAL.md, fix56-b).
FED_SAMPLE_FRAMES = 16


def _check_fed(loop_pred: LoopPredictor, model: LoopModel, state: LoopState, clock: _Clock,
               seed: int, basis) -> str | None:
    """Check a forecaster against what the loop will feed it; return the result's note.

    Leaves ``state`` reset (``t = 0``, flat mirrors), ready for the loop, whatever it
    did (:func:`_fed_note`).
    """
    try:
        return _fed_note(loop_pred, model, state, clock, seed, basis)
    finally:
        state.reset()


def _fed_note(loop_pred: LoopPredictor, model: LoopModel, state: LoopState, clock: _Clock,
              seed: int, basis) -> str | None:
    """:func:`_check_fed`'s check and note.

    A forecaster trained on a run of known conditions was checked by
    ``check_trained_for``. One fitted elsewhere (a bare array, another source's log)
    carries no conditions: ``Predictor.check_fed`` refuses a training log's other rate
    or units, and training data whose rms per mode is not this loop's POL's (x10
    either way: other units, fix56-b), compared with ``FED_SAMPLE_FRAMES`` sensings of
    the run's own turbulence (with the WFS noise, a generator of its own: the run's
    draws are unchanged) spread over the run. The note says that the conditions were
    not checked and what was. None without a forecaster.
    """
    forecaster = loop_pred.predictor
    if forecaster is None or not hasattr(forecaster, "check_fed"):
        return None
    if loop_pred.trained_on is not None:
        return ("trained on a run of this config's training conditions (telescope, "
                "layers, sensors, mirrors, frame clock): checked")
    if loop_pred._shape_only or isinstance(forecaster, PersistencePredictor):
        return "persistence: fits nothing, nothing to check"
    sample = None
    if hasattr(forecaster, "training_rms_"):
        n = min(FED_SAMPLE_FRAMES, clock.n_frames)
        maps = [np.empty((p.n, p.n)) for p in model.geometry.planes]
        rng = np.random.default_rng(
            np.random.SeedSequence(seed).spawn(len(model.config.layers) + 2)[-1])
        rows = []
        for k in np.linspace(0, clock.n_frames - 1, n).round().astype(int):
            state.evolve_until(int(k) * clock.n_os * clock.dt)  # frame k's start
            rows.append(model.sense(state.turbulence(maps), rng))
        sample = np.array(rows)
        if basis is not None:
            sample = sample @ basis
    try:
        checked = forecaster.check_fed(sample, rate=1.0 / model.config.loop.time_step,
                                       units="rad", wavelength=model.config.r0_wavelength,
                                       name=LOOP_POL)
    except ValueError as exc:
        raise ValueError(f"`predictor` {loop_pred.name!r}: {exc}") from None
    return ("fitted on data of unknown conditions (an array, or a log that is no run's): "
            "its training conditions were not checked; checked: its mode count"
            + (f", {checked}" if checked else ""))


def _check_predictor_modes(predictor, n_modes: int, basis) -> None:
    """Refuse a fitted predictor whose mode count is not what this loop feeds it.

    Before, the mismatch was refused only at step 0, naming the internal ``x_t`` (round
    9, row c-fitted-wrong-modes).
    """
    fitted = getattr(predictor, "n_modes_", None)
    fed = n_modes if basis is None else basis.shape[1]
    if fitted is not None and fitted != fed:
        where = "control_basis columns" if basis is not None else "every DM's modes"
        raise ValueError(f"`predictor` was fitted on {fitted} mode(s); this loop feeds it "
                         f"{fed} ({where}): fit it on the POL of a run of this config "
                         "(LoopPredictor.trained).")


def _check_control_basis(basis, n_modes: int, budget_every=None) -> np.ndarray | None:
    """Validate ``control_basis``: ``(n_modes, n)`` with orthonormal columns."""
    if basis is None:
        return None
    if budget_every:
        raise ValueError("`budget_every` cannot be combined with `control_basis` (the budget "
                         "models a loop that controls every mode).")
    b = np.asarray(basis, dtype=np.float64)
    if b.ndim != 2 or b.shape[0] != n_modes or not 1 <= b.shape[1] <= n_modes:
        raise ValueError(f"`control_basis` must have shape ({n_modes}, n) with 1 <= n <= "
                         f"{n_modes}; got {b.shape}.")
    if not np.all(np.isfinite(b)):
        raise ValueError("`control_basis` must be finite.")
    err = float(np.abs(b.T @ b - np.eye(b.shape[1])).max())
    if err > 1e-8:
        raise ValueError("`control_basis` must have orthonormal columns (B^T B = I); "
                         f"largest deviation {err:.3g}.")
    return np.ascontiguousarray(b)


def _check_arguments(config, duration, predictor, on_predictor_fault, budget_every,
                     control_basis, snapshot_every, progress,
                     callback) -> tuple[float, LoopPredictor]:
    """Refuse what :func:`simulate` refuses before any set-up.

    Returns the checked duration and the run's predictor (the one check of ``predictor``).
    """
    if progress is not None and not isinstance(progress, bool | np.bool_):  # "no" was True
        raise TypeError(f"`progress` must be None or a bool; got {progress!r}.")
    if callback is not None and not callable(callback):  # else a TypeError at frame 0
        raise TypeError(f"`callback` must be callable or None; got {callback!r}.")
    duration = check_real(duration, "duration", minimum=0.0, strict_min=True)
    if not isinstance(config, SimulationConfig):
        raise TypeError(f"`config` must be a SimulationConfig; got {type(config).__name__}.")
    if on_predictor_fault not in PREDICTOR_FAULT_ACTIONS:
        raise ValueError(f"`on_predictor_fault` must be one of "
                         f"{', '.join(map(repr, PREDICTOR_FAULT_ACTIONS))}; got "
                         f"{on_predictor_fault!r}.")
    loop_pred = loop_predictor(predictor)
    if loop_pred.needs_training:
        raise ValueError(f"`predictor` {loop_pred.name!r} is not trained: use "
                         "closedloop.run_trained, or LoopPredictor.trained(reference).")
    check_trained_for(loop_pred, config, control_basis)
    check_fitted_log(loop_pred, config)  # its series, rate, units: before any set-up
    if not config.loop.closed:
        _check_open_loop(None if loop_pred.is_none else loop_pred.name, budget_every,
                         control_basis)
    check_run(config, duration, budget_every=budget_every, snapshot_every=snapshot_every)
    return duration, loop_pred


def _check_snapshot_directions(directions, snapshot_every, field) -> np.ndarray | None:
    """Validate ``snapshot_directions``: ``(n, 2)`` finite, inside the science field.

    The planes' grids reach the science grid's corners (``plane_layout``), so a direction
    beyond ``field.size / 2`` on either axis (any but the axis for a one-point field)
    reads past a plane's edge: an IndexError after the whole run (audit 9). Given without
    ``snapshot_every`` it would be ignored: refused.
    """
    if directions is None:
        return None
    if not snapshot_every:
        raise ValueError("`snapshot_directions` needs `snapshot_every` (an int: how often to "
                         "store the snapshots); got snapshot_every=None.")
    try:
        d = np.asarray(directions, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"`snapshot_directions` must be an (n, 2) array of directions "
                        f"[arcsec]; got {type(directions).__name__}.") from None
    if d.ndim != 2 or d.shape[1] != 2 or d.shape[0] < 1:
        raise ValueError(f"`snapshot_directions` must have shape (n, 2) with n >= 1 "
                         f"[arcsec]; got shape {d.shape}.")
    if not np.all(np.isfinite(d)):
        raise ValueError("`snapshot_directions` must be finite [arcsec].")
    half = field.size / 2.0 if field.n_points > 1 else 0.0
    worst = float(np.abs(d).max())
    if worst > half * (1 + 1e-12):
        raise ValueError(f"`snapshot_directions` must lie in the science field, |x|, |y| <= "
                         f"field.size / 2 = {half:g} arcsec (the planes are sized for it; 0 "
                         f"for a one-point field); got {worst:g}.")
    return d


def _model_for(config: SimulationConfig, model: LoopModel | None) -> LoopModel:
    """Return ``model`` if it was built for ``config``, else a new one."""
    if model is None:
        return LoopModel(config)
    if model.config != config:
        raise ValueError("`model` was built for another config.")
    return model


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"`seed` must be a non-negative int; got {seed!r}.")
    if seed > MAX_SEED:
        # the limit of `SimulationConfig.seed`: 2**100 ran, then the result's save raised
        # h5py's "Object dtype dtype('O') has no native HDF5 equivalent" (round 38 PART a)
        raise ValueError(f"`seed` must be at most 2**63 - 1 = {MAX_SEED} (the result file "
                         f"stores it as a 64-bit integer); got {seed}.")
    return int(seed)


@dataclasses.dataclass(frozen=True)
class _Clock:
    """The run's internal steps: ``n_os`` per frame, ``dt`` apart [s].

    Attributes
    ----------
    n_os, n_int, n_delay : int
        Internal steps per frame, per exposure, and of the loop delay.
    n_frames : int
    dt : float
        Internal step [s].
    """

    n_os: int
    n_int: int
    n_delay: int
    n_frames: int
    dt: float

    @classmethod
    def of(cls, loop: LoopConfig, duration: float) -> _Clock:
        n_os = loop.oversampling
        return cls(n_os=n_os, n_int=round(loop.integration_frames * n_os),
                   n_delay=round(loop.delay_frames * n_os),
                   n_frames=max(1, round(duration / loop.time_step)),
                   dt=loop.time_step / n_os)

    @property
    def run_time(self) -> float:
        """Time [s] the atmosphere must cover (the run, the delay, the oracle's last hold)."""
        return (self.n_frames * self.n_os + self.n_delay + self.n_os) * self.dt

    def in_exposure(self, i: int) -> bool:
        """Whether internal step ``i`` of a frame is inside the WFS exposure (its end)."""
        return i >= self.n_os - self.n_int

    def apply_step(self, k: int) -> int:
        """Return the internal step at which frame ``k``'s command reaches the mirrors."""
        return (k + 1) * self.n_os + self.n_delay


class _Exposure:
    """Sum of the plane maps over a WFS exposure (in place, no allocation per step).

    The first step after :meth:`clear` is copied rather than added to zeros: the same
    numbers (``0 + v = v``; only an exact ``-0.0`` keeps its sign) for one pass over the
    planes less (the zeroing), ~1 ms a frame on ``est-mcao``'s 60" planes.
    """

    def __init__(self, maps: list[np.ndarray]):
        self.maps = [np.zeros_like(v) for v in maps]
        self._empty = True

    def add(self, maps: list[np.ndarray]) -> None:
        if self._empty:
            for a, v in zip(self.maps, maps, strict=True):
                np.copyto(a, v)
            self._empty = False
            return
        for a, v in zip(self.maps, maps, strict=True):
            a += v

    def mean(self, n: int) -> list[np.ndarray]:
        """Divide the sums by ``n`` steps (in place) and return them."""
        for a in self.maps:
            if self._empty:  # nothing added since the last clear: the sums are zero
                a[:] = 0.0
            a /= n
        return self.maps

    def clear(self) -> None:
        """Start a new sum (the next :meth:`add` overwrites the maps)."""
        self._empty = True


class _Oracle:
    """The true future: the noise-free sensing of the turbulence alone over a command's hold.

    Runs its own copy of the run's atmosphere (same seed), so it reads ahead of the loop.
    """

    def __init__(self, model: LoopModel, seed: int, clock: _Clock):
        self.model = model
        self.clock = clock
        self.state = LoopState(model, model.atmosphere(seed, clock.run_time))
        self.exposure = _Exposure(self.state.maps)

    @property
    def maps(self) -> list[np.ndarray]:
        """Turbulence maps averaged over the last forecast's hold window."""
        return self.exposure.maps

    def forecast(self, first_step: int) -> np.ndarray:
        """Modal turbulence of every DM averaged over internal steps ``first_step + [0, n_os)``."""
        self.exposure.clear()
        for s in range(first_step, first_step + self.clock.n_os):
            self.state.evolve_until(s * self.clock.dt)
            self.exposure.add(self.state.turbulence(self.state.maps))
        return self.model.sense(self.exposure.mean(self.clock.n_os), None)


def _projector(model: LoopModel, basis: np.ndarray | None, predictor) -> np.ndarray | None:
    """Return the controller's projector onto the observed commands, in its coordinates."""
    if predictor is None:
        return None
    p = model.controlled_projector
    if p is None or basis is None:
        return p
    return basis.T @ p @ basis


def _sensed(model: LoopModel, basis: np.ndarray | None) -> np.ndarray | None:
    """Return ``R G`` of a MAP reconstructor in the controller's coordinates (else None)."""
    s = model.sensed_commands
    if s is None or basis is None:
        return s
    return basis.T @ s @ basis


def _float32_from(model: LoopModel) -> float:
    """Size [bytes] from which the controller's ``(M, M)`` products run in float32.

    :data:`closedloop.optics.products.FLOAT32_MIN_BYTES` in a loop with a mirror that asks
    for large products (the actuator DM: the MAP's ``R G`` of ``est-mcao`` is 190 MB in
    float64), else ``inf`` (every other loop keeps its bits).
    """
    return FLOAT32_MIN_BYTES if any(dm.large_products for dm in model.dms) else math.inf


class _Control:
    """The controller as the loop uses it: control-basis projection, open loop, fault labels."""

    def __init__(self, model: LoopModel, loop: LoopConfig, predictor, basis: np.ndarray | None,
                 on_predictor_fault: str):
        n_control = model.n_modes if basis is None else basis.shape[1]
        self.controller = Controller(n_control, gain=loop.gain, leak=loop.leak,
                                     delay_frames=loop.delay_frames,
                                     integration_frames=loop.integration_frames,
                                     predictor=predictor, on_predictor_fault=on_predictor_fault,
                                     projector=_projector(model, basis, predictor),
                                     sensed=_sensed(model, basis),
                                     float32_from=_float32_from(model))
        self.model = model
        self.basis = basis
        self.open_loop = not loop.closed

    def step(self, measured: np.ndarray, forecast: np.ndarray | None) -> tuple:
        """Return the command and the POL ``(n_modes,)`` of a frame from its modal residual."""
        basis = self.basis
        try:
            if basis is None:
                command, pol, _ = self.controller.step(measured, forecast)
            else:
                command_n, pol_n, _ = self.controller.step(
                    basis.T @ measured, None if forecast is None else basis.T @ forecast)
                command = basis @ command_n
                # measured + B (seen commands): the uncontrolled directions keep m
                pol = measured + basis @ (pol_n - basis.T @ measured)
        except PredictorFault as exc:
            raise _labelled(exc, self.model, basis) from None
        if self.open_loop:
            # the controller's command is dropped and a zero one sent: the DMs stay
            # flat, the residual is the turbulence, and so is the POL
            command, pol = np.zeros(self.model.n_modes), measured
        return command, pol


class _Logs:
    """Per-frame arrays of a run (science variance, modal residual, POL, commands, WFSs)."""

    def __init__(self, model: LoopModel, n_frames: int):
        self.variance = np.empty((n_frames, len(model.science.directions)))
        self.measured = np.empty((n_frames, model.n_modes))
        self.pol = np.empty((n_frames, model.n_modes))
        self.commands = np.empty((n_frames, model.n_modes))
        self.measurements = [np.empty((n_frames, w.n_measurements)) for w in model.wfss]

    def record(self, k: int, measured, pol, command, measurements) -> None:
        self.measured[k] = measured
        self.pol[k] = pol
        self.commands[k] = command
        for log, m in zip(self.measurements, measurements, strict=True):
            log[k] = m


class _Snapshots:
    """Residual pupil phase in some directions every ``every`` frames (FFT-PSF checks)."""

    def __init__(self, science: ScienceCamera, every: int | None, directions):
        self.every = every
        self.frames: list[np.ndarray] = []
        self.camera = None
        if every:
            dirs = np.zeros((1, 2)) if directions is None else directions
            self.camera = science.looking_at(np.asarray(dirs, dtype=np.float64))

    def take(self, k: int) -> None:
        cam = self.camera
        if cam is not None and k % self.every == 0:
            self.frames.append(np.stack([cam.residual_phase(d)
                                         for d in range(len(cam.directions))]))

    @property
    def directions(self) -> np.ndarray | None:
        return None if self.camera is None else self.camera.directions


def _assemble(config, seed, model, logs: _Logs, snapshots: _Snapshots, probe, elapsed,
              predictor: str, predictor_note: str | None = None) -> SimulationResult:
    """Return the run's result (science numbers at the science wavelength)."""
    scale_sci = (config.r0_wavelength / config.wavelength) ** 2
    snaps = snapshots.frames
    # the residual the WFS noise alone leaves (the budget's noise term, fewer draws: a
    # level to judge the loop by, loop_status), on the budget's camera or, after the run,
    # the loop's own (its planes are refilled at every step of a run)
    cam = model.science if probe is None else probe.cam
    floor = float(noise_variance(model, cam, seed, draws=_FLOOR_DRAWS).mean()) * scale_sci
    result = SimulationResult.from_run(
        config=config, seed=seed, model=model,
        variance=logs.variance * scale_sci, measured=logs.measured, pol=logs.pol,
        commands=logs.commands, elapsed=elapsed, measurements=logs.measurements,
        predictor_name=predictor, predictor_note=predictor_note,
        snapshots=np.array(snaps) * np.sqrt(scale_sci) if snaps else None,
        snapshot_directions=snapshots.directions, noise_floor=floor,
    )
    if probe is not None:
        budget = probe.result(result.residual_variance, result.averaging_start, scale_sci,
                              seed)
        result = dataclasses.replace(result, budget=budget)
    return result


def _warn_held(controller: Controller, predictor: str, n_frames: int) -> None:
    """Say at the end how many frames kept their last command (``on_predictor_fault="hold"``)."""
    if controller.n_faults:
        from modalinfo.common.quiet import warn

        warn(f"predictor {predictor} returned an unusable forecast "
             f"on {controller.n_faults} of {n_frames} frames; the last command was "
             "held there (on_predictor_fault='hold').", RuntimeWarning, stacklevel=3)


def _progress_bar(progress, total):
    import sys

    if progress is None:
        progress = sys.stderr.isatty()
    if not progress:
        return None
    from tqdm import tqdm

    return tqdm(total=total, unit="frame", desc="closedloop", file=sys.stderr, leave=False)
