"""Compression x prediction: control only the first n modes of an ordering, with latency.

The paper (Stangalini et al., Conclusions) proposes to combine its two results: order the
modes by mutual information so that fewer modes carry the wavefront, and predict them
to beat the loop delay; compressing the basis also saves computation, which shortens the
delay. This module runs that study in the closed loop (single conjugate; the ``kaos``
preset):

* :func:`control_orderings` builds, from a no-prediction run that controls every mode,
  the orthonormal change of basis of each ordering: ``"zernike"`` (Noll order),
  ``"kl"`` (theoretical von Karman K-L modes by decreasing variance), ``"zernike-mi"``
  and ``"kl-mi"`` (the same bases in the order of :func:`modalinfo.ordering.order_modes`
  ``"mi_greedy"``, the paper's MI ordering) and ``"pca"`` (data K-L: eigenvectors of the
  run's POL covariance). The orderings are computed on the POL log, the open-loop
  equivalent turbulence that a real-time computer reconstructs and the controller
  corrects (the paper ordered a closed-loop log; the residual of a loop that controls
  every mode is nearly white across modes and says little about which modes to keep).
* :func:`simulate`'s ``control_basis`` then controls the span of the first ``n`` columns.
* :func:`rtc_compute_time` measures the per-step cost of our reconstruction and
  prediction for ``n`` modes, and :class:`LatencyModel` turns it into a loop delay:
  ``delay(n) = readout + compute(n) / rtc_speed``. The real-time computer is taken to be
  a commodity CPU core running this code (``rtc_speed = 1``): CPU real-time controllers
  serve AO systems up to 8 m class (DARC, Basden et al. 2010, Appl. Opt. 49, 6354), and
  solar AO systems of KAOS's generation run on PC hardware. The delay is rounded to the
  simulator's internal step (``time_step / oversampling``).
* :func:`compression_study` runs the grid (orderings x n x {no prediction, predictor} x
  {fixed delay, latency model}) on one atmosphere and returns a
  :class:`CompressionStudy`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from closedloop.config import SimulationConfig
from closedloop.control import predictors as cl_predictors
from closedloop.control.controller import Controller
from closedloop.result import SimulationResult
from closedloop.simulation import LoopModel, simulate
from closedloop.training import run_trained
from modalinfo.common.records import array_fields_eq
from modalinfo.common.validation import check_int, check_real

__all__ = ["ORDERINGS", "control_orderings", "rtc_compute_time", "rtc_scaling", "LatencyModel",
           "CompressionStudy", "compression_study", "predictor_screen"]

#: ordering name -> label
ORDERINGS = {
    "zernike": "Zernike, standard order",
    "kl": "K-L (theory), variance order",
    "zernike-mi": "Zernike, MI order",
    "kl-mi": "K-L (theory), MI order",
    "pca": "data K-L (PCA of the POL)",
}


def _single_dm(model: LoopModel) -> None:
    if len(model.dms) != 1 or model.dms[0].shapes is None:
        raise ValueError("the compression study needs a single modal (Zernike) DM; "
                         f"the config has {len(model.dms)} DMs.")


def control_orderings(reference: SimulationResult, *, orderings=tuple(ORDERINGS),
                      seed: int = 0, sample_budget: int = 50_000,
                      n_pixels: int = 48) -> dict[str, np.ndarray]:
    """Orthonormal change of basis of each ordering, columns in control priority.

    Parameters
    ----------
    reference : SimulationResult
        A no-prediction run that controls every mode (single Zernike DM); its POL log
        after the loop closure (and after 15 ms) is the data the orderings are built on.
    orderings : iterable of str
        Names from :data:`ORDERINGS`.
    seed : int
        Seed of the MI sampling.
    sample_budget : int
        (frame, pixel) samples of the MI estimates.
    n_pixels : int
        Pupil sampling of the mode shapes in the MI estimates.

    Returns
    -------
    dict
        name -> ``(M, M)`` orthogonal matrix ``B`` in the DM's Zernike coefficient space
        (the DM's unit-RMS Zernikes are orthonormal over its disc, so an orthogonal ``B``
        gives orthonormal mirror modes); the first ``n`` columns span the controlled
        subspace of ``n`` modes.
    """
    from modalinfo.ordering import order_modes
    from modalinfo.ordering.compare import basis_for_log

    unknown = [o for o in orderings if o not in ORDERINGS]
    if unknown:
        raise ValueError(f"`orderings` must be names from {', '.join(ORDERINGS)}; got "
                         f"{unknown[0]!r}.")
    if reference.predictor != "none" or len(reference.config.dms) != 1:
        raise ValueError("`reference` must be a no-prediction run of a single-DM config.")
    start = cl_predictors.training_start(reference)
    log = reference.logs["dm0.pol"][start:]
    dm_diameter = float(log.metadata["dm_diameter_m"])
    l0 = min(layer.outer_scale for layer in reference.config.layers)
    zb = basis_for_log("zernike", log, n_pixels=n_pixels, diameter=dm_diameter)
    m = log.n_modes
    out: dict[str, np.ndarray] = {}
    kl = None
    if any(o in ("kl", "kl-mi") for o in orderings):
        kl = basis_for_log("kl-theory", log, n_pixels=n_pixels, diameter=dm_diameter,
                           outer_scale=l0, zernike_basis=zb)
    for name in orderings:
        if name == "zernike":
            out[name] = np.eye(m)
        elif name == "kl":
            out[name] = np.array(kl.zernike_from_kl)
        elif name == "zernike-mi":
            order = order_modes(log, zb, "mi_greedy", seed=seed, sample_budget=sample_budget,
                                n_resamples=0).order
            out[name] = np.eye(m)[:, order]
        elif name == "kl-mi":
            order = order_modes(log, kl, "mi_greedy", seed=seed, sample_budget=sample_budget,
                                n_resamples=0).order
            out[name] = np.array(kl.zernike_from_kl)[:, order]
        elif name == "pca":
            # modalinfo's data K-L: eigenvectors of the POL's mean-square matrix
            out[name] = np.array(basis_for_log("kl-data", log, zernike_basis=zb)
                                 .zernike_from_kl)
    return out


def _full_reconstructor(model: LoopModel) -> np.ndarray:
    if model.reconstructor is not None:
        return model.reconstructor
    wfs = model.wfss[0]
    return wfs.reconstructor


def rtc_compute_time(model: LoopModel, basis: np.ndarray, predictor=None, *,
                     repeats: int = 2000, batches: int = 5, seed: int = 0) -> float:
    """Median wall time [s] of one real-time step for the modes ``basis`` spans.

    The step is what the real-time computer does between the WFS readout and the DM
    command for ``n`` controlled modes: the reconstruction of the ``n`` coefficients
    (one dense ``(n, n_measurements)`` matrix-vector product, the projected
    reconstructor ``B^T R``), the POL and integrator update of :class:`Controller` (with a
    MAP reconstructor's pseudo-open-loop term ``B^T R G B``, as the loop runs it), and
    the predictor's ``update`` (if any; fitted beforehand). Timed over ``repeats`` steps,
    ``batches`` times; the median batch over ``repeats``.
    """
    basis = np.asarray(basis, dtype=np.float64)
    r_n = np.ascontiguousarray(basis.T @ _full_reconstructor(model))
    loop = model.config.loop
    sensed = model.sensed_commands  # R G of a MAP reconstructor: its POL term is RTC work too
    controller = Controller(basis.shape[1], gain=loop.gain, leak=loop.leak,
                            delay_frames=loop.delay_frames,
                            integration_frames=loop.integration_frames, predictor=predictor,
                            sensed=None if sensed is None else basis.T @ sensed @ basis)
    rng = np.random.default_rng(seed)
    slopes = rng.standard_normal((64, r_n.shape[1])) * 1e-7
    return _time_steps(controller, r_n, slopes, repeats, batches)


def _time_steps(controller, reconstructor, slopes, repeats: int, batches: int) -> float:
    """Median over ``batches`` of the mean time [s] of one reconstruct + control step."""
    for k in range(50):  # warm-up (JIT, caches)
        controller.step(reconstructor @ slopes[k % len(slopes)])
    times = []
    for _ in range(batches):
        t = time.perf_counter()
        for k in range(repeats):
            controller.step(reconstructor @ slopes[k % len(slopes)])
        times.append((time.perf_counter() - t) / repeats)
    return float(np.median(times))


def rtc_scaling(n_values, *, predictor: str | None = None, measurements_per_mode: float = 2.0,
                gain: float = 0.5, seed: int = 0, repeats: int = 500) -> np.ndarray:
    """Measured RTC step time [s] for larger systems than the preset (synthetic sizes).

    The same step as :func:`rtc_compute_time` (reconstruction, integrator, predictor
    update) for ``n`` modes and ``measurements_per_mode * n`` measurements, with a random
    reconstructor and the predictor (a :data:`closedloop.control.predictors.NAMES` name, or
    None) fitted on a random AR(1) series of the length its fit requires: how the cost
    grows with the number of controlled modes, beyond the preset's modes.

    Returns
    -------
    (K,) ndarray
        Median step time [s] for each ``n``.
    """
    sizes = [check_int(n, "n_values[*]", minimum=1) for n in np.atleast_1d(
        np.asarray(n_values, dtype=object))]  # 2.7 was timed as 2 modes, 0 as a real size
    if not sizes:
        raise ValueError("`n_values` must hold at least one number of modes; got none.")
    repeats = check_int(repeats, "repeats", minimum=1)  # 0: a ZeroDivisionError
    measurements_per_mode = check_real(measurements_per_mode, "measurements_per_mode",
                                       minimum=0.0, strict_min=True)
    rng = np.random.default_rng(seed)
    out = []
    for n in sizes:
        n_meas = max(1, int(round(measurements_per_mode * n)))
        r = rng.standard_normal((n, n_meas)) / math.sqrt(n_meas)
        pred = None
        if predictor is not None:
            pred = cl_predictors.LoopPredictor.from_name(predictor).predictor
            need = getattr(pred, "_min_samples_rule", lambda k: (200, ""))(n)[0]
            length = max(int(need * 1.2), 200)
            x = np.empty((length, n))
            x[0] = rng.standard_normal(n)
            noise = rng.standard_normal((length, n))
            for k in range(1, length):
                x[k] = 0.95 * x[k - 1] + 0.3 * noise[k]
            pred.fit(x)
        controller = Controller(n, gain=gain, leak=0.0, delay_frames=1.0,
                                integration_frames=1.0, predictor=pred)
        slopes = rng.standard_normal((64, n_meas))
        out.append(_time_steps(controller, r, slopes, repeats, 3))
    return np.array(out)


@dataclass(frozen=True)
class LatencyModel:
    """Loop delay = readout + compute(n) / rtc_speed, on the simulator's time grid.

    Attributes
    ----------
    readout : float
        Delay without computation [s] (readout, transfer, DM response): the preset's delay.
    rtc_speed : float
        Speed of the real-time computer relative to this machine running our code.
    oversampling : int
        Internal simulator steps per frame: the delay is rounded to ``T / oversampling``.
    """

    readout: float
    rtc_speed: float = 1.0
    oversampling: int = 8

    def delay(self, compute_time: float, time_step: float) -> float:
        """Modelled delay [s] for a step costing ``compute_time`` [s]."""
        raw = self.readout + compute_time / self.rtc_speed
        grid = time_step / self.oversampling
        return round(raw / grid) * grid


@array_fields_eq
@dataclass(frozen=True)
class CompressionStudy:
    """Strehl ratios of the compression x prediction grid (one atmosphere).

    Keys of the result dictionaries are ``(latency, ordering, predictor)`` with
    ``latency`` False (the preset's fixed delay) or True (:class:`LatencyModel`),
    ``predictor`` ``"none"`` or the predictor's name; values are ``(len(n_values),)``
    arrays over ``n_values``.

    Attributes
    ----------
    config_name : str
    seed : int
    duration : float
        Simulated time of every run [s].
    n_values : (K,) int ndarray
        Numbers of controlled modes.
    orderings : tuple of str
    predictor : str
        The predictor beside no prediction (``closedloop.control.predictors`` name).
    strehl_peak : dict
        Mean over the window of the SR peak over the field.
    strehl_field : dict
        Mean over the window and the field grid of the SR.
    compute_time : dict
        predictor name -> ``(K,)`` measured RTC step time [s] (``rtc_compute_time``).
    delay : dict
        predictor name -> ``(K,)`` modelled delay [s] of the latency runs.
    latency : LatencyModel
    time_step : float
        Frame period [s].
    window_start : float
        Start of the averaging window [s] (the full no-prediction run's closure, >= 15 ms).
    wavelength : float
        Science wavelength [m].
    retuned_gain : dict
        Modelled delay [s] -> the gain its runs used, where the preset's gain is unstable
        at that delay (:func:`gain_for_delay`); empty when every delay kept the preset's.
    """

    config_name: str
    seed: int
    duration: float
    n_values: np.ndarray
    orderings: tuple
    predictor: str
    strehl_peak: dict
    strehl_field: dict
    compute_time: dict
    delay: dict
    latency: LatencyModel
    time_step: float
    window_start: float
    wavelength: float
    timings: dict = field(default_factory=dict)
    retuned_gain: dict = field(default_factory=dict)

    def optimum(self, ordering: str, predictor: str, *, latency: bool = True,
                field_average: bool = False) -> tuple[int, float]:
        """``(n, SR)`` where the SR (peak, or field average) is highest."""
        sr = (self.strehl_field if field_average else self.strehl_peak)[
            (latency, ordering, predictor)]
        i = int(np.nanargmax(sr))
        return int(self.n_values[i]), float(sr[i])

    def modes_to_reach(self, fraction: float, ordering: str, predictor: str = "none", *,
                       latency: bool = False) -> int | None:
        """Fewest modes whose SR peak reaches ``fraction`` of the all-mode SR peak."""
        sr = self.strehl_peak[(latency, ordering, predictor)]
        full = sr[-1]
        ok = np.flatnonzero(sr >= fraction * full)
        return int(self.n_values[ok[0]]) if ok.size else None


def _check_reference(reference, config, seed: int) -> None:
    """Refuse a given reference that is not the no-prediction run of ``config``, ``seed``.

    Its mean is the screen's "none" row and its POL the orderings' and training data: a
    run of another gain, seed or predictor was used as this loop's (audit 10, feedback,
    row screen-reference-other).
    """
    own = {"config": config, "seed": seed, "predictor": "none"}
    for key, value in own.items():
        if hasattr(reference, key) and getattr(reference, key) != value:
            raise ValueError(f"`reference` must be the no-prediction run of `config` with "
                             f"seed {seed}; its `{key}` differs.")


def predictor_screen(config: SimulationConfig, candidates, *, duration: float, seed: int = 0,
                     model: LoopModel | None = None,
                     reference: SimulationResult | None = None) -> dict[str, float]:
    """Mean SR peak of each predictor on the loop that controls every mode.

    Trained predictors are fitted on the no-prediction run (after the closure and 15
    ms, as the paper trains); the window of the means is that run's (from the closure
    and 15 ms on). ``"none"`` and ``"oracle"`` are always included, as references.
    ``reference``: that no-prediction run, if already made (same config, duration, seed).

    Returns
    -------
    dict
        name -> mean SR peak.
    """
    if model is None:
        model = LoopModel(config)
    if reference is None:
        reference = simulate(config, duration, model=model, seed=seed, progress=False)
    else:
        _check_reference(reference, config, seed)
    start = cl_predictors.training_start(reference)
    out = {"none": float(np.mean(reference.strehl_peak[start:]))}
    for name in ("oracle", *candidates):
        if name in out:
            continue
        r = run_trained(config, name, duration, seed=seed, reference=reference, model=model,
                        progress=False)
        out[name] = float(np.mean(r.strehl_peak[start:]))
    return out


def compression_study(config: SimulationConfig, *, n_values, duration: float,
                      orderings=tuple(ORDERINGS), predictor: str = "multivariate",
                      seed: int = 0, latency: LatencyModel | None = None,
                      model: LoopModel | None = None, progress=None,
                      reference: SimulationResult | None = None) -> CompressionStudy:
    """Run the compression x prediction grid on one atmosphere.

    For every ordering and every ``n`` in ``n_values``: a no-prediction run controlling
    the first ``n`` modes, the predictor fitted on that run's projected POL (after the
    closure and 15 ms, as the paper trains) and a run with it; then the same two runs
    with the delay of ``latency`` for the measured compute time of ``n`` modes. With
    ``n`` equal to every mode, all orderings span the same space: those runs are made
    once and shared.

    Parameters
    ----------
    config : SimulationConfig
        Single-DM configuration (e.g. ``presets.get("kaos")``).
    n_values : iterable of int
        Controlled mode counts, increasing, the last one may be all modes.
    duration : float
        Simulated time of each run [s].
    orderings : iterable of str
        Names from :data:`ORDERINGS`.
    predictor : str
        A name of :data:`closedloop.control.predictors.NAMES` other than "none" and "oracle".
    seed : int
    latency : LatencyModel or None
        Default: ``LatencyModel(readout=config.loop.delay)``.
    model : LoopModel or None
    progress : callable or None
        Called with a short text before every run.
    reference : SimulationResult or None
        The no-prediction run that controls every mode (same config, duration and
        seed), if already made.

    Returns
    -------
    CompressionStudy
    """
    if model is None:
        model = LoopModel(config)
    _single_dm(model)
    m = model.n_modes
    n_values = np.array(sorted({int(n) for n in n_values}), dtype=np.int64)
    if n_values.size == 0 or n_values[0] < 1 or n_values[-1] > m:
        raise ValueError(f"`n_values` must lie in 1..{m}; got {n_values.tolist()}.")
    spec = (cl_predictors.LoopPredictor.from_name(predictor)
            if predictor in cl_predictors.NAMES else None)
    if spec is None or spec.is_none or spec.oracle:
        raise ValueError(f"`predictor` must be a predictor name of "
                         f"closedloop.control.predictors.NAMES other than 'none' and 'oracle'; got "
                         f"{predictor!r}.")
    orderings = tuple(orderings)
    latency = LatencyModel(readout=config.loop.delay) if latency is None else latency
    say = progress or (lambda text: None)
    timings: dict = {}

    t0 = time.perf_counter()
    if reference is None:
        say("reference run (every mode, no prediction)")
        reference = simulate(config, duration, model=model, seed=seed, progress=False)
    else:
        _check_reference(reference, config, seed)
    start = cl_predictors.training_start(reference)
    bases = control_orderings(reference, orderings=orderings, seed=seed)
    timings["orderings"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    compute, delays = _rtc_delays(model, bases[orderings[0]], n_values, spec, reference,
                                  latency, config.loop.time_step)
    timings["compute_time"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    peak, field_sr, retuned = _grid_runs(config, model, bases, orderings, n_values, spec,
                                         delays, duration=duration, seed=seed, start=start,
                                         say=say)
    timings["runs"] = time.perf_counter() - t0
    return CompressionStudy(
        config_name=config.name, seed=seed, duration=duration, n_values=n_values,
        orderings=orderings, predictor=predictor, strehl_peak=peak, strehl_field=field_sr,
        compute_time=compute, delay=delays, latency=latency,
        time_step=config.loop.time_step, window_start=float(reference.times[start]),
        wavelength=config.wavelength, timings=timings, retuned_gain=retuned)


def gain_for_delay(loop, delay: float):
    """Return ``(loop config at `delay`, whether its gain had to change)``.

    The latency model's delay is measured (a loaded machine computes slower), and the
    preset's gain can be unstable at a long one; an operator would retune the servo. The
    gain is then scaled to keep the preset's gain margin:
    ``g' = g * g_max(delay) / g_max(preset delay)`` with ``g_max`` the integrator's
    stability limit (:func:`modalinfo.servo.max_stable_gain`, with the loop's exposure
    and leak). Stable delays keep the preset's gain (the study's fixed-delay runs are
    unchanged).
    """
    from modalinfo.servo import max_stable_gain

    new = dataclasses.replace(loop, delay=delay)
    limit = max_stable_gain(new.delay_frames, new.integration_frames, leak=new.leak)
    if loop.gain < limit * (1.0 - 1e-9):
        return new, False
    own = max_stable_gain(loop.delay_frames, loop.integration_frames, leak=loop.leak)
    return dataclasses.replace(new, gain=loop.gain * limit / own), True


def _rtc_delays(model: LoopModel, first: np.ndarray, n_values: np.ndarray,
                spec: cl_predictors.LoopPredictor, reference: SimulationResult,
                latency: LatencyModel, time_step: float) -> tuple[dict, dict]:
    """Return the RTC step time [s] per ``n``, measured, and the delay [s] it makes.

    The time does not depend on the ordering; ``latency`` models the loop delay for it.
    Keys: ``"none"`` and the predictor's name.
    """
    compute = {"none": np.empty(n_values.size), spec.name: np.empty(n_values.size)}
    for i, n in enumerate(n_values):
        b = first[:, :n]
        compute["none"][i] = rtc_compute_time(model, b)
        # the paper's training data, projected on the controlled subspace
        compute[spec.name][i] = rtc_compute_time(model, b,
                                                 spec.trained(reference, basis=b).predictor)
    delays = {k: np.array([latency.delay(c, time_step) for c in v]) for k, v in compute.items()}
    return compute, delays


def _grid_runs(config: SimulationConfig, model: LoopModel, bases: dict, orderings: tuple,
               n_values: np.ndarray, spec: cl_predictors.LoopPredictor, delays: dict, *,
               duration: float, seed: int, start: int, say) -> tuple[dict, dict, dict]:
    """Return the mean SR peak and field SR of every run of :func:`compression_study`.

    Keyed ``(latency, ordering, predictor)``, ``(len(n_values),)`` each, averaged from
    frame ``start`` on; and the retuned gains: delay [s] -> gain, where
    :func:`gain_for_delay` had to lower the preset's gain.
    """
    m = model.n_modes
    names = ("none", spec.name)
    peak: dict = {}
    field_sr: dict = {}
    retuned: dict = {}
    models = {config.loop.delay: model}

    def model_for(delay):
        if delay not in models:
            loop, changed = gain_for_delay(config.loop, delay)
            if changed:
                retuned[float(delay)] = loop.gain
            models[delay] = LoopModel(config.replace(loop=loop))
        return models[delay]

    shared: dict = {}
    fixed_runs: dict = {}
    for lat in (False, True):
        for o in orderings:
            for name in names:
                peak[(lat, o, name)] = np.full(n_values.size, np.nan)
                field_sr[(lat, o, name)] = np.full(n_values.size, np.nan)
        for i, n in enumerate(n_values):
            for o in orderings:
                b = bases[o][:, :n]
                if n == m and (lat, n) in shared:
                    for name, (p, f) in shared[(lat, n)].items():
                        peak[(lat, o, name)][i] = p
                        field_sr[(lat, o, name)][i] = f
                    continue
                summary = {}
                for name in names:
                    delay = delays[name][i] if lat else config.loop.delay
                    if lat and delay == config.loop.delay:
                        # the same run as with the fixed delay (the simulator is
                        # deterministic): reuse it
                        summary[name] = fixed_runs[(o, int(n), name)]
                        continue
                    say(f"{'latency ' if lat else ''}{o} n={n}: {name}")
                    mdl = model_for(delay)
                    # the predictor learns the turbulence (POL), not the loop: every run
                    # uses the one trained on the fixed-delay no-prediction run
                    r = run_trained(mdl.config, "none" if name == "none" else spec, duration,
                                    seed=seed, model=mdl, progress=False, control_basis=b,
                                    reference=fixed_runs.get((o, int(n), "run")))
                    summary[name] = (float(np.mean(r.strehl_peak[start:])),
                                     float(np.mean(r.strehl[start:])))
                    if not lat:
                        fixed_runs[(o, int(n), name)] = summary[name]
                        if name == "none":
                            fixed_runs[(o, int(n), "run")] = r
                for name, (p, f) in summary.items():
                    peak[(lat, o, name)][i] = p
                    field_sr[(lat, o, name)][i] = f
                if n == m:
                    shared[(lat, n)] = summary
    return peak, field_sr, retuned
