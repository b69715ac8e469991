"""Solar sensing in the loop: the correlation's latency and how the answer moves with it.

The paper's premise (Stangalini et al., Introduction and Conclusions): on granulation
"wavefront sensing requires real-time correlation techniques which, in addition to the
larger integration time needed, increase the time delay". This module puts numbers on it
for the correlating Shack-Hartmann of ``closedloop`` (``kind = "correlating"``, preset
``table1-solar``).

Latency
    :func:`correlation_compute_time` measures, on this machine, what one frame of a
    correlating WFS costs: :func:`closedloop.optics.shifts.measure_shifts` (the same
    numba kernels the sensor uses) on a batch of granulation subaperture images of the
    WFS's size (its field of view over its pixel scale) and count (its valid
    subapertures), each against one subaperture of the same frame, as solar systems do.
    :func:`solar_latency` adds it over the config's correlating WFSs and turns it into a
    loop delay with Figure 6's :class:`~closedloop.studies.compression.LatencyModel`:
    ``delay = readout + compute / rtc_speed``, rounded to the simulator's internal step.
    The real-time computer is a :class:`SolarRTC` (:data:`RTC_PRESETS`).

Sensitivity
    :func:`solar_sensitivity` runs the base config (``table1-solar``) and one change at a
    time of the photon flux (``signal``), the granulation contrast (``contrast``), the
    subaperture size (``n_subapertures``) and the compute latency (``loop.delay`` from
    :func:`solar_latency` with slower and faster RTCs), for no prediction and ARMA (and any
    other predictor named), on one atmosphere; it returns a :class:`SolarSensitivity` with
    SR peak, field-mean SR, corrected FoV and the on-axis error budget (its noise and
    temporal terms) per run. The number of runs is bounded (``max_runs``) and checked
    before any work.

    python -m closedloop.studies.solar [--quick] [--knobs signal,rtc] [--duration S] [--seed N]

The real-time computer. Solar AO systems correlate every subaperture image against a
reference subaperture each frame, on workstation CPUs (the Swedish 1-m Solar Telescope's
85-electrode AO runs its cross-correlations and control at 2 kHz on one Intel PC
workstation "with very low latency": Scharmer et al. 2024, arXiv:2311.13690) or on
dedicated DSP/FPGA hardware (Rimmele & Marino 2011, Living Rev. Sol. Phys. 8, 2, Sect. 5
on the correlating SH and its computing load). The presets below are documented
choices, not one instrument's specification:

``"workstation"``
    readout 0.5 ms (table1's delay: camera readout and transfer; the paper's Table 1) and
    ``rtc_speed = 32``: a 32-core workstation running these kernels in parallel over the
    subapertures, each core as fast as one core of this machine (the SST's approach).
``"fpga"``
    readout 0.5 ms and ``rtc_speed = 256``: dedicated pipelined hardware (FPGA/GPU) that
    correlates as the pixels stream in; the correlation then adds little to the readout.
``"this-machine"``
    readout 0.5 ms and ``rtc_speed = 1``: our code on one core of this machine (the
    pessimistic end; for table1's 60" fields it is far slower than a frame).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from closedloop.config import SimulationConfig
from closedloop.optics.correlating_sensor import MAX_SHIFT as CORRELATING_MAX_SHIFT
from closedloop.studies.compression import LatencyModel
from modalinfo.common.cli import Parser
from modalinfo.common.quiet import quiet
from modalinfo.common.records import array_fields_eq
from modalinfo.common.validation import check_real

__all__ = ["SolarRTC", "RTC_PRESETS", "correlation_compute_time", "correlating_wfs_sizes",
           "correlating_compute_time",
           "solar_latency", "SolarSensitivity", "solar_variations", "solar_sensitivity",
           "markdown", "DEFAULT_PIXEL_SCALE", "MAX_RUNS"]

#: detector pixel [arcsec] of the timed scene (the WFS default; the cost does not depend on it)
DEFAULT_PIXEL_SCALE = 0.5
#: default bound on the number of closed-loop runs of :func:`solar_sensitivity`
MAX_RUNS = 60
#: the SDF search of the loop's sensor (Loefdahl 2010's choice; its range is the sensor's)
_METHOD = "sdf"
_MAX_SHIFT = CORRELATING_MAX_SHIFT


@dataclass(frozen=True)
class SolarRTC:
    """A solar real-time computer: what the correlations add to the loop delay.

    Attributes
    ----------
    name : str
    readout : float
        Delay without computation [s] (camera readout, transfer, DM response).
    rtc_speed : float
        Speed relative to one core of this machine running our kernels (> 0).
    source : str
        Where the numbers come from.
    """

    name: str
    readout: float
    rtc_speed: float
    source: str = ""

    def __post_init__(self):
        # validation.check_real (the one copy): a 0-d array or NumPy scalar is its number,
        # bool / complex / str refused; its Python float is kept (frozen: records, JSON)
        for attr in ("readout", "rtc_speed"):
            object.__setattr__(self, attr, check_real(
                getattr(self, attr), f"SolarRTC.{attr}", minimum=0.0,
                strict_min=attr == "rtc_speed"))

    def latency_model(self, oversampling: int = 8) -> LatencyModel:
        """Figure 6's :class:`LatencyModel` with this RTC's readout and speed."""
        return LatencyModel(readout=float(self.readout), rtc_speed=float(self.rtc_speed),
                            oversampling=int(oversampling))


#: documented RTC presets (module docstring)
RTC_PRESETS: dict[str, SolarRTC] = {
    "workstation": SolarRTC(
        "workstation", 0.5e-3, 32.0,
        "32-core workstation, one correlation thread per core (SST AO: Scharmer et al. "
        "2024, arXiv:2311.13690); readout 0.5 ms as table1"),
    "fpga": SolarRTC(
        "fpga", 0.5e-3, 256.0,
        "pipelined FPGA/GPU correlator (Rimmele & Marino 2011, Living Rev. Sol. Phys. 8, 2); "
        "readout 0.5 ms as table1"),
    "this-machine": SolarRTC(
        "this-machine", 0.5e-3, 1.0, "our kernels on one core of this machine"),
}


def _rtc(rtc) -> SolarRTC:
    if isinstance(rtc, SolarRTC):
        return rtc
    if isinstance(rtc, str) and rtc in RTC_PRESETS:
        return RTC_PRESETS[rtc]
    raise ValueError(f"`rtc` must be a SolarRTC or one of {sorted(RTC_PRESETS)}; got {rtc!r}.")


def _positive_int(name: str, value, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"`{name}` must be an int >= {minimum}; got {value!r}.")
    return int(value)


def correlation_compute_time(n_subapertures: int, image_pixels: int, *, method: str = _METHOD,
                             max_shift: int = _MAX_SHIFT, repeats: int = 5, seed: int = 0,
                             clock: Callable[[], float] = time.process_time) -> float:
    """CPU time [s] to measure the shifts of one frame of a correlating WFS on this machine.

    ``n_subapertures`` granulation images of ``image_pixels`` x ``image_pixels`` (cut from
    one seeded scene at :data:`DEFAULT_PIXEL_SCALE`, with photon noise), each measured
    against the first image (the same-frame reference) by
    :func:`closedloop.optics.shifts.measure_shifts` in one batch; the fastest of
    ``repeats`` batches after one warm-up batch (numba compilation, caches). The clock is
    this process's CPU time (``time.process_time``): the work one core does, which is
    what ``rtc_speed`` scales, and which other processes on a shared machine do not
    inflate as they inflate wall time (measured here: 5-11x at a load average of 10 on 2
    cores); the minimum of the batches removes what cache contention remains.

    Parameters
    ----------
    n_subapertures : int
        Subaperture images per frame, >= 1.
    image_pixels : int
        Pixels across one subaperture image, >= ``2 max_shift + 5``.
    method : {"sdf", "adf2", "cfi"}
        Shift measurement (:func:`measure_shifts`).
    max_shift : int
        Search range [pixels].
    repeats : int
        Timed batches, >= 1.
    seed : int
        Scene and noise.
    clock : callable
        Seconds counter (``time.process_time``: CPU seconds of this process).

    Returns
    -------
    float
        CPU time of the fastest batch [s] on this machine.
    """
    from closedloop.optics.granulation import granulation_scene
    from closedloop.optics.shifts import measure_shifts

    n = _positive_int("n_subapertures", n_subapertures)
    size = _positive_int("image_pixels", image_pixels, 2 * _positive_int("max_shift", max_shift)
                         + 5)
    repeats = _positive_int("repeats", repeats)
    # a scene twice the image (at least 16 px, 2 granules) and n crops at random offsets
    side = max(2 * size, 16)
    scene = granulation_scene(side, DEFAULT_PIXEL_SCALE, seed=seed)
    rng = np.random.default_rng(seed)
    offsets = rng.integers(0, side, (n, 2))
    rows = (offsets[:, 0, None] + np.arange(size)) % side
    cols = (offsets[:, 1, None] + np.arange(size)) % side
    images = scene[rows[:, :, None], cols[:, None, :]] * 15_000.0
    images += rng.standard_normal(images.shape) * math.sqrt(15_000.0)
    reference = images[0]
    times = []
    with quiet(UserWarning):  # the cfi bias warning: only its time is read here
        measure_shifts(reference, images, method=method, max_shift=max_shift)  # warm-up
        for _ in range(repeats):
            t = clock()
            measure_shifts(reference, images, method=method, max_shift=max_shift)
            times.append(clock() - t)
    return float(min(times))


def correlating_wfs_sizes(config: SimulationConfig, model=None) -> list[tuple[int, int, int]]:
    """``(wfs index, valid subapertures, pixels across an image)`` of each correlating WFS.

    The image covers the WFS's field of view at its pixel scale (``field_of_view /
    pixel_scale``, at least ``2 max_shift + 5`` pixels); the valid subapertures are those
    of the loop's sensor (a :class:`closedloop.LoopModel` is built if none is given).

    Raises
    ------
    ValueError
        The config has no ``kind = "correlating"`` WFS.
    """
    idx = [i for i, w in enumerate(config.wfss) if w.kind == "correlating"]
    if not idx:
        raise ValueError(f"`config` ({config.name!r}) has no WFS of kind 'correlating' "
                         f"(kinds: {[w.kind for w in config.wfss]}); there is no correlation "
                         "to time.")
    if model is None:
        from closedloop.simulation import LoopModel

        model = LoopModel(config)
    out = []
    for i in idx:
        w = config.wfss[i]
        # the sensor's own image size (CorrelatingShackHartmann: round(field / pixel))
        pixels = max(int(round(w.field_of_view / w.pixel_scale)), 2 * _MAX_SHIFT + 5)
        out.append((i, int(model.wfss[i].n_valid_subapertures), pixels))
    return out


def correlating_compute_time(config: SimulationConfig, model=None, *, repeats: int = 5,
                             seed: int = 0,
                             timer: Callable[[int, int], float] | None = None) -> float:
    """One frame's shift measurement of every correlating WFS of ``config`` on this machine [s].

    Each correlating WFS measures its valid subapertures and its correlation tracker's
    image (``n_valid + 1`` images of its size, :func:`correlating_wfs_sizes`);
    :func:`correlation_compute_time` times them (or ``timer(n_images, image_pixels)``, a
    stored measurement), and the WFSs' times add up (one real-time computer).
    """
    sizes = correlating_wfs_sizes(config, model)
    if timer is None:
        def timer(n, pixels):
            return correlation_compute_time(n, pixels, repeats=repeats, seed=seed)
    return float(sum(timer(n + 1, pixels) for _, n, pixels in sizes))


def solar_latency(config: SimulationConfig, *, rtc: str | SolarRTC = "workstation", model=None,
                  compute_time: float | None = None, repeats: int = 5, seed: int = 0,
                  timer: Callable[[int, int], float] | None = None) -> tuple[float, float]:
    """Measured correlation time of ``config``'s correlating WFSs, and the loop delay it gives.

    Parameters
    ----------
    config : SimulationConfig
        With at least one ``kind = "correlating"`` WFS.
    rtc : str or SolarRTC
        A :data:`RTC_PRESETS` name or an RTC.
    model : closedloop.LoopModel, optional
        The config's model (for the valid subapertures); built if not given.
    compute_time : float, optional
        A measurement of :func:`correlating_compute_time` already made [s] (else measured).
    repeats, seed, timer
        Passed to :func:`correlating_compute_time`.

    Returns
    -------
    compute_time : float
        Sum over the correlating WFSs of one frame's shift measurement on this machine [s].
    delay : float
        ``rtc.readout + compute_time / rtc.rtc_speed`` rounded to ``time_step /
        loop.oversampling`` (at least 8 steps per frame) [s].

    Raises
    ------
    ValueError
        No correlating WFS; an unknown ``rtc``; a delay beyond the loop's stability limit
        at the config's gain (naming the RTC and the largest stable gain).
    """
    from modalinfo.servo import max_stable_gain

    r = _rtc(rtc)
    if compute_time is None:
        compute = correlating_compute_time(config, model, repeats=repeats, seed=seed,
                                           timer=timer)
    else:
        compute = check_real(compute_time, "compute_time", minimum=0.0)  # [s]
    loop = config.loop
    oversampling = max(8, loop.oversampling)
    delay = r.latency_model(oversampling).delay(compute, loop.time_step)
    limit = max_stable_gain(delay / loop.time_step, loop.integration_frames,
                            leak=loop.leak)
    if loop.gain >= limit:
        raise ValueError(
            f"`rtc` {r.name!r} (readout {r.readout * 1e3:g} ms, rtc_speed {r.rtc_speed:g}) "
            f"gives a delay of {delay * 1e3:.3f} ms ({compute * 1e3:.2f} ms of correlation on "
            f"this machine): the loop gain {loop.gain:g} is beyond the largest stable gain "
            f"{limit:.3f} there; use a faster RTC or a lower gain.")
    return compute, float(delay)


# ------------------------------------------------------------------ sensitivity
def _wfs_change(attr: str, value) -> Callable[[SimulationConfig], SimulationConfig]:
    def change(c: SimulationConfig) -> SimulationConfig:
        return c.replace(wfss=tuple(dataclasses.replace(w, **{attr: value}) for w in c.wfss))
    return change


def _delay_change(delay: float) -> Callable[[SimulationConfig], SimulationConfig]:
    def change(c: SimulationConfig) -> SimulationConfig:
        return c.replace(loop=dataclasses.replace(c.loop, delay=delay))
    return change


#: (knob, values) of the full study; the base config's own value is its first row
FULL_VALUES = {
    "signal": (1500.0, 150.0),          # e- per pixel per frame (default ~15 000)
    "contrast": (0.06, 0.03),           # rms granulation contrast (default ~0.18 at 500 nm)
    "n_subapertures": (8, 24),          # across the meta-pupil (table1: 16)
    "rtc": ("fpga", "workstation"),     # the delay of these RTCs (solar_latency)
}
#: ``quick``: one value of each knob
QUICK_VALUES = {"signal": (150.0,), "contrast": (0.03,), "n_subapertures": (8,),
                "rtc": ("workstation",)}
_UNITS = {"signal": " e-", "contrast": "", "n_subapertures": ""}
KNOB_LABELS = {"signal": "photon flux (signal, e-/px/frame)",
               "contrast": "granulation contrast",
               "n_subapertures": "subapertures across (size)",
               "rtc": "compute latency (loop.delay)"}


def _check_values(values) -> dict:
    values = FULL_VALUES if values is None else values
    if not isinstance(values, dict):
        raise TypeError(f"`values` must be a dict knob -> values; got {values!r}.")
    unknown = sorted(set(values) - set(FULL_VALUES))
    if unknown:
        raise ValueError(f"`values` keys must be among {sorted(FULL_VALUES)}; got {unknown}.")
    for knob, vals in values.items():
        if isinstance(vals, (str, bytes)) or not hasattr(vals, "__len__"):
            raise TypeError(f"`values[{knob!r}]` must be a tuple of values; got {vals!r}.")
        if knob == "rtc":
            for v in vals:
                _rtc(v)
    return values


def solar_variations(base: SimulationConfig, values: dict | None = None, *, model=None,
                     latency: dict | None = None) -> tuple[list[tuple], dict]:
    """One-at-a-time variations ``[(knob, label, change)]`` and the RTC latencies used.

    The ``"rtc"`` knob sets ``loop.delay`` to :func:`solar_latency`'s delay for each RTC
    named (the correlations timed once here, :func:`correlating_compute_time`; ``latency``
    maps an RTC name to a stored ``(compute, delay)``); an RTC whose delay would make the
    loop unstable is left out and reported in the returned dict as ``(compute, nan)``.
    """
    values = _check_values(values)
    latency = dict(latency or {})
    measured: list[float] = [c for c, _ in latency.values() if math.isfinite(c)]
    out = []
    for knob, vals in values.items():
        for v in vals:
            if knob == "rtc":
                r = _rtc(v)
                if r.name not in latency:
                    if not measured:  # one measurement serves every RTC
                        measured.append(correlating_compute_time(base, model))
                    try:
                        latency[r.name] = solar_latency(base, rtc=r, compute_time=measured[0])
                    except ValueError:
                        latency[r.name] = (measured[0], float("nan"))
                compute, delay = latency[r.name]
                if not math.isfinite(delay):
                    continue
                out.append((knob, f"{r.name}: {delay * 1e3:.3f} ms", _delay_change(delay)))
            else:
                label = (f"{v:g}{_UNITS[knob]}" if isinstance(v, float) else f"{v}")
                out.append((knob, label, _wfs_change(knob, v)))
    return out, latency


@array_fields_eq  # NaN fields equal after a round trip (audit 10-state)
@dataclass(frozen=True)
class SolarSensitivity:
    """How SR, corrected FoV and the error budget move with the solar knobs.

    Attributes
    ----------
    config_name : str
    seed : int
    duration : float
        Simulated time of every run [s].
    predictors : tuple of str
    rows : tuple of dict
        One per run: ``knob`` ("base" for the base config), ``value`` (label),
        ``predictor``, ``delay`` [s], ``strehl_peak``, ``strehl_field``, ``fov_arcmin``,
        and the on-axis budget of the no-prediction run ``fitting``, ``aliasing``,
        ``temporal``, ``noise``, ``measured`` [rad^2 at the science wavelength].
    latency : dict
        RTC name -> ``(compute_time, delay)`` [s] measured for the ``rtc`` knob (delay NaN:
        the loop would be unstable).
    elapsed : float
        Wall time [s].
    """

    config_name: str
    seed: int
    duration: float
    predictors: tuple
    rows: tuple
    latency: dict
    elapsed: float = 0.0

    def row(self, knob: str, value: str, predictor: str = "none") -> dict:
        """Return the row of one run (``knob`` "base" and ``value`` "" for the base config)."""
        for r in self.rows:
            if r["knob"] == knob and r["value"] == value and r["predictor"] == predictor:
                return r
        raise KeyError(f"no run {knob!r} = {value!r} with {predictor!r}")


def solar_sensitivity(base: SimulationConfig | None = None, *, values: dict | None = None,
                      predictors: tuple[str, ...] = ("none", "arma"), duration: float = 0.3,
                      seed: int = 0, budget_every: int | None = 5, max_runs: int = MAX_RUNS,
                      latency: dict | None = None, model=None, base_results: dict | None = None,
                      progress: bool | None = False,
                      log: Callable[[str], None] | None = None) -> SolarSensitivity:
    """Run ``base`` and each one-at-a-time variation for every predictor.

    Parameters
    ----------
    base : SimulationConfig or None
        Default ``presets.get("table1-solar")``.
    values : dict or None
        Knob -> values (:data:`FULL_VALUES`, :data:`QUICK_VALUES`).
    predictors : tuple of str
        ``"none"`` always runs (the predictors train on it, and it carries the budget).
    duration : float
        Simulated time of each run [s].
    seed : int
        One atmosphere for every run.
    budget_every : int or None
        Error budget of each no-prediction run every this many frames.
    max_runs : int
        Largest number of closed-loop runs allowed; checked before any work.
    latency : dict or None
        Stored ``{rtc: (compute, delay)}`` for the ``rtc`` knob (else measured).
    model : closedloop.LoopModel, optional
        The base config's model (built if not given).
    base_results : dict or None
        Predictor name -> :class:`closedloop.SimulationResult` of ``base`` already run with
        this ``duration`` and ``seed`` (the no-prediction one with its budget): reused as
        the base rows instead of running them again. Runs not given are made.
    progress : bool or None
        Progress bars of the runs.
    log : callable or None
        Receives one line per run.
    """
    from closedloop import presets
    from closedloop.control.predictors import NAMES
    from closedloop.simulation import LoopModel
    from closedloop.studies.sensitivity import _row
    from closedloop.training import run_trained

    start = time.perf_counter()
    base = presets.get("table1-solar") if base is None else base
    if isinstance(predictors, str):
        raise TypeError(f"`predictors` must be a tuple of names; got the string {predictors!r}.")
    bad = [p for p in predictors if p not in NAMES]
    if bad:
        raise ValueError(f"`predictors` must be names of {sorted(NAMES)}; got {bad}.")
    names = ("none", *[p for p in dict.fromkeys(predictors) if p != "none"])
    max_runs = _positive_int("max_runs", max_runs)
    values = _check_values(values)
    n_values = sum(len(v) for v in values.values())
    n_runs = (1 + n_values) * len(names)
    if n_runs > max_runs:
        raise ValueError(f"`max_runs` = {max_runs} is below the {n_runs} runs asked "
                         f"(({n_values} variations + base) x {len(names)} predictors); "
                         "give fewer values or predictors, or raise max_runs.")
    given = dict(base_results or {})
    for name, res in given.items():
        if res.config != base or res.seed != seed or abs(res.times[-1] - duration) > \
                0.5 * base.loop.time_step:
            raise ValueError(f"`base_results[{name!r}]` is not a run of the base config with "
                             f"seed {seed} and duration {duration:g} s.")
        if getattr(res, "predictor", name) != name:  # its row: another predictor's numbers
            raise ValueError(f"`base_results[{name!r}]` is a run of predictor "
                             f"{res.predictor!r}, not {name!r}.")
    model = LoopModel(base) if model is None else model
    variations, lat = solar_variations(base, values, model=model, latency=latency)
    rows = []
    for knob, label, change in [("base", "", None), *variations]:
        cfg = base if change is None else change(base)
        # each variation changes the config, so it needs its own model (shared by its runs)
        m = model if change is None else LoopModel(cfg)
        ref = None
        for name in names:
            if change is None and name in given:
                res = given[name]
            else:
                res = run_trained(cfg, name, duration, seed=seed, model=m, reference=ref,
                                  progress=progress,
                                  budget_every=budget_every if name == "none" else None)
            if name == "none":
                ref = res
            # the SR of every predictor of a knob value from its no-prediction run's closure,
            # the window of Figure 2's and Figure 7's main tables (round 43 PART b, R33)
            row = _row(knob, label, res, start=ref.averaging_start)
            row.update(knob=knob, predictor=name, delay=float(cfg.loop.delay))
            if name != "none":  # the budget belongs to the no-prediction run
                for term in ("fitting", "aliasing", "temporal", "noise", "measured"):
                    row.pop(term, None)
            rows.append(row)
            if log is not None:
                log(f"[solar] {knob} {label or '(base)'} {name}: SR peak "
                    f"{row['strehl_peak']:.3f}, FoV {row['fov_arcmin']:.2f}'"
                    + (f", noise {row['noise']:.4f}" if "noise" in row else ""))
    return SolarSensitivity(config_name=base.name, seed=int(seed), duration=float(duration),
                            predictors=names, rows=tuple(rows), latency=lat,
                            elapsed=time.perf_counter() - start)


def markdown(study: SolarSensitivity) -> str:
    """Return the study as a Markdown table (SR per predictor, budget of no prediction)."""
    names = study.predictors
    head = ("| knob | value | delay [ms] | "
            + " | ".join(f"SR peak {n}" for n in names) + " | "
            + " | ".join(f"FoV d {n} [']" for n in names)
            + " | fitting | aliasing | temporal | noise | measured (on axis, rad^2) |")
    lines = [head, "|" + "---|" * (3 + 2 * len(names) + 5)]
    seen = []
    for r in study.rows:
        key = (r["knob"], r["value"])
        if key not in seen:
            seen.append(key)
    for knob, value in seen:
        none = study.row(knob, value, "none")
        srs = " | ".join(f"{study.row(knob, value, n)['strehl_peak']:.3f}" for n in names)
        fovs = " | ".join(f"{study.row(knob, value, n)['fov_arcmin']:.2f}" for n in names)
        terms = " | ".join(f"{none[t]:.4f}" if t in none else "" for t in
                           ("fitting", "aliasing", "temporal", "noise", "measured"))
        label = "(base)" if knob == "base" else KNOB_LABELS.get(knob, knob)
        lines.append(f"| {label} | {value} | {none['delay'] * 1e3:.3f} | {srs} | {fovs} | "
                     f"{terms} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    """Print the latency of ``table1-solar`` and its sensitivity table as Markdown."""
    ap = Parser(prog="python -m closedloop.studies.solar",
                                 description="Sensitivity of table1-solar to the solar knobs.")
    ap.add_argument("--duration", type=float, default=0.3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--quick", action="store_true", help="one value per knob")
    ap.add_argument("--knobs", default=None,
                    help=f"comma list of knobs to vary (default all: {','.join(FULL_VALUES)})")
    args = ap.parse_args(argv)
    values = QUICK_VALUES if args.quick else FULL_VALUES
    if args.knobs is not None:
        knobs = [k.strip() for k in args.knobs.split(",") if k.strip()]
        bad = [k for k in knobs if k not in FULL_VALUES]
        if not knobs or bad:
            sys.stderr.write(f"solar: error: --knobs must be a comma list of "
                             f"{','.join(FULL_VALUES)}; got '{args.knobs}'\n")
            return 2
        values = {k: values[k] for k in knobs}
    try:
        study = solar_sensitivity(values=values,
                                  duration=args.duration, seed=args.seed,
                                  log=lambda s: print(s, file=sys.stderr, flush=True))
    except (ValueError, TypeError) as exc:
        sys.stderr.write(f"solar: error: {str(exc).splitlines()[0]}\n")
        return 2
    lat = "; ".join(f"{k}: correlation {c * 1e3:.2f} ms on this machine -> "
                    + (f"delay {d * 1e3:.3f} ms" if math.isfinite(d) else "unstable loop")
                    for k, (c, d) in study.latency.items())
    sys.stdout.write(f"{study.config_name} sensitivity: seed {study.seed}, {study.duration:g} s "
                     f"per run, one knob changed at a time ({study.elapsed:.0f} s). "
                     f"Latency: {lat}.\n\n")
    sys.stdout.write(markdown(study) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
