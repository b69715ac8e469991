"""The closed loop: one function that composes atmosphere, mirrors, sensors and control.

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
see :mod:`closedloop.science`). In open loop (``loop.closed = false``) every command is
replaced by zero: the DMs stay flat, and the residual and POL logs are both the open-loop
modal turbulence the WFSs see.

Everything random (screens, noise) comes from one ``numpy.random.SeedSequence(seed)``:
the same seed and thread count give the same bits.
"""

from __future__ import annotations

import dataclasses
import time
from collections import deque
from collections.abc import Callable

import numpy as np

from closedloop import _kernels
from closedloop.atmosphere import Atmosphere, AtmosphericLayer
from closedloop.config import SimulationConfig
from closedloop.control import PREDICTOR_FAULT_ACTIONS, Controller, PredictorFault
from closedloop.dm import DeformableMirror
from closedloop.geometry import Geometry
from closedloop.predictors import ORACLE, loop_predictor
from closedloop.result import SimulationResult
from closedloop.science import ScienceCamera
from closedloop.wfs import WavefrontSensor
from modalinfo._validation import check_real
from modalinfo.bases import noll_residual_variance, zernike_covariance

__all__ = ["simulate", "ORACLE", "LoopModel", "check_run"]

_NOISE_FLOOR = 1e-4
_SNR_CUT = 1.0
_RCOND = 1e-3


class LoopModel:
    """The static parts of a configuration: geometry, DMs, WFSs, science camera.

    Building the WFS operators and reconstructors is the expensive part of the set-up;
    a ``LoopModel`` can be reused for several runs of the same configuration.

    Attributes
    ----------
    prior : (n_modes,) ndarray or None
        Prior variance [rad^2 at ``r0_wavelength``] of each DM mode (DM 0 first) that the
        joint MAP reconstructor assumes: each layer's Noll variances over the disc of the
        DM nearest to it; None when there is no joint reconstructor (one DM, or a zonal
        DM).
    """

    def __init__(self, config: SimulationConfig):
        if not isinstance(config, SimulationConfig):
            raise TypeError(f"`config` must be a SimulationConfig; got {type(config).__name__}.")
        self.config = config
        self.geometry = Geometry(config)
        self.dms = [DeformableMirror(self.geometry, i) for i in range(len(config.dms))]
        self.wfss = [WavefrontSensor(self.geometry, j, self.dms[w.dm])
                     for j, w in enumerate(config.wfss)]
        self.science = ScienceCamera(self.geometry, self.geometry.directions)
        sizes = [dm.n_modes for dm in self.dms]
        self.mode_slices = [slice(a, a + n) for a, n in
                            zip(np.concatenate([[0], np.cumsum(sizes)[:-1]]), sizes, strict=True)]
        self.n_modes = int(sum(sizes))
        self.prior = None
        self.reconstructor = self._global_reconstructor()

    def _global_reconstructor(self):
        """Reconstructor of all DMs' modes from all WFSs' measurements (MAP, Fusco et al. 2001).

        Each layer-oriented WFS also sees the other DMs (blurred by its field). With one
        least-squares reconstructor per WFS-DM pair these cross-couplings make the loops
        fight (the coupled loop matrix has complex eigenvalues; table1 diverges at gain
        0.5), and a joint least-squares inverse splits the modes that several DMs share
        (tilt is the same at every altitude) evenly between them, so that off axis half
        of the ground layer's tilt goes uncorrected. The joint maximum a posteriori
        reconstructor ``R = (G^T N^-1 G + C^-1)^-1 G^T N^-1`` (Fusco, Conan, Rousset,
        Mugnier & Michau 2001, JOSA A 18, 2527) settles both: ``G`` is the full
        interaction matrix (rows: every WFS, columns: every DM's modes), ``N`` the
        measurement-noise variances and ``C`` the prior variance of each DM mode, the
        Noll/von Karman variance of the turbulence assigned to that DM (each layer to the
        nearest DM altitude) over the DM's disc. A noise-free WFS gets a floor of 1e-4 of
        the mean signal, so the prior still breaks ties. ``None`` (one reconstructor
        per WFS) with a single DM or a zonal ("ideal") DM.
        """
        if len(self.dms) == 1 or any(dm.shapes is None for dm in self.dms):
            return None
        g = self.geometry
        cfg = self.config
        full = np.block([[w.interaction_with(dm) for dm in self.dms] for w in self.wfss])
        prior = np.empty(self.n_modes)
        dm_alts = np.array([dm.altitude for dm in self.dms])
        strength = np.zeros(len(self.dms))
        for li, lay in enumerate(cfg.layers):
            d = int(np.argmin(np.abs(dm_alts - g.los(lay.altitude))))
            r0 = g.layer_r0(li)
            strength[d] += (self.dms[d].diameter / r0) ** (5.0 / 3.0)
        floor = 1e-6 * max(strength.max(), 1e-12)
        for d, dm in enumerate(self.dms):
            var = np.diag(zernike_covariance(dm.modes))
            prior[self.mode_slices[d]] = max(strength[d], floor) * var
        self.prior = prior
        noise = np.concatenate([np.full(w.n_measurements, w.noise_rms ** 2
                                        + self._model_error_variance(w))
                                for w in self.wfss])
        signal_level = np.mean(np.sum(full ** 2, axis=0) * prior) / full.shape[0]
        noise = np.maximum(noise, _NOISE_FLOOR * signal_level)
        # truncated SVD in the noise- and prior-whitened space: R G is then an exact
        # projector, so commands never drift along directions the WFSs barely see
        whitened = full * np.sqrt(prior)[None, :] / np.sqrt(noise)[:, None]
        u, sv, vt = np.linalg.svd(whitened, full_matrices=False)
        keep = sv > max(_SNR_CUT, _RCOND * sv[0])
        self.n_controlled = int(keep.sum())
        r = (np.sqrt(prior)[:, None] * vt[keep].T) @ ((u[:, keep] / sv[keep]).T)
        return r / np.sqrt(noise)[None, :]

    def _model_error_variance(self, wfs) -> float:
        """Return the extra noise per measurement the reconstructor assumes (model error).

        Neither sensor model sees only the DMs' modes: a Shack-Hartmann also measures the
        turbulence's slopes beyond them (aliasing), an ideal sensor the phase beyond them
        (generalised fitting). Left out of ``N``, these inconsistencies between the WFSs
        are fitted by wild combinations of the DMs' nearly degenerate modes that cancel on
        axis and not off axis. SH: ``loop.model_error`` (0.3) times the turbulent slope variance of
        one subaperture, the Z-tilt of a disc of the subaperture's size:
        ``16 * 0.449 (d / r0)**(5/3) / d**2`` summed over layers [(rad/m)^2]. Ideal:
        Noll's residual variance after the DM's modes, ``Delta_J (D_dm / r0)**(5/3)``
        summed over layers [rad^2].
        """
        cfg = self.config
        r0s = [self.geometry.layer_r0(i) for i in range(len(cfg.layers))]
        if wfs.kind == "shack_hartmann":
            d = wfs.pitch
            total = sum((d / r0) ** (5.0 / 3.0) for r0 in r0s)
            return cfg.loop.model_error * 16.0 * 0.449 * total / d ** 2
        dm = wfs.dm
        if dm.shapes is None:
            return 0.0
        j_max = max(dm.modes)
        return float(noll_residual_variance(j_max)) * sum(
            (dm.diameter / r0) ** (5.0 / 3.0) for r0 in r0s)

    def slopes(self, plane_maps: list[np.ndarray],
               rng: np.random.Generator | None) -> list[np.ndarray]:
        """Every WFS's measurements (with noise drawn from ``rng``, none if None)."""
        out = []
        for wfs in self.wfss:
            noise = (rng.standard_normal(wfs.n_measurements)
                     if rng is not None and wfs.noise_rms > 0 else None)
            out.append(wfs.slopes(plane_maps, noise))
        return out

    def reconstruct(self, slopes: list[np.ndarray]) -> np.ndarray:
        """Modal residual of every DM (concatenated) from every WFS's measurements."""
        if self.reconstructor is not None:
            return self.reconstructor @ np.concatenate(slopes)
        out = np.empty(self.n_modes)
        for wfs, s in zip(self.wfss, slopes, strict=True):
            out[self.mode_slices[wfs.dm.index]] = (s if wfs.reconstructor is None
                                                   else wfs.reconstructor @ s)
        return out

    def measure(self, plane_maps: list[np.ndarray], rng: np.random.Generator | None) -> np.ndarray:
        """Modal residual of every DM (concatenated) from the exposure-averaged maps."""
        return self.reconstruct(self.slopes(plane_maps, rng))

    def atmosphere(self, seed: int, duration: float) -> Atmosphere:
        """Return the configuration's layers on their planes' grids, seeded by ``seed``."""
        g = self.geometry
        cfg = self.config
        seeds = np.random.SeedSequence(seed).spawn(len(cfg.layers) + 1)
        layers = []
        for i, lay in enumerate(cfg.layers):
            plane = g.planes[g.layer_plane[i]]
            r0 = g.layer_r0(i)
            ang = np.radians(lay.wind_direction)
            layers.append(AtmosphericLayer(
                n_pixels=plane.n, pixel_scale=g.dx, r0=r0,
                velocity=(lay.wind_speed * np.cos(ang), lay.wind_speed * np.sin(ang)),
                outer_scale=lay.outer_scale, altitude=plane.altitude,
                duration_hint=duration, seed=np.random.default_rng(seeds[i])))
        return Atmosphere(layers)

    def noise_rng(self, seed: int) -> np.random.Generator:
        """Return the WFS-noise generator of a run seeded by ``seed``."""
        seeds = np.random.SeedSequence(seed).spawn(len(self.config.layers) + 1)
        return np.random.default_rng(seeds[-1])


def _fill_planes(model: LoopModel, atm: Atmosphere, views: list[np.ndarray],
                 surfaces: list[np.ndarray] | None, layer_buf: dict) -> None:
    """Residual (or, with ``surfaces=None``, turbulence) map of every plane."""
    g = model.geometry
    layers = atm.layers
    for p, plane in enumerate(g.planes):
        view = views[p]
        if not plane.layers:
            view[:] = 0.0
        else:
            # the views are the science camera's float64 C-contiguous plane maps, of
            # their layers' grid size: phase()'s checks are skipped (hot loop)
            layers[plane.layers[0]]._phase_into(view)
            for li in plane.layers[1:]:
                buf = layer_buf.setdefault(p, np.empty_like(view))
                layers[li]._phase_into(buf)
                view += buf
        if surfaces is not None:
            for d in plane.dms:
                _kernels.subtract_scatter(view, model.dms[d].pixels, surfaces[d], 1.0)


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
    predictor : closedloop.predictors.LoopPredictor, modalinfo.forecast.Predictor or None
        Forecaster of the POL coefficients of all DMs (concatenated, DM 0 first); it
        must be fitted (a ``LoopPredictor`` trained, see :func:`closedloop.run_trained`)
        and its ``horizon`` must cover the lead. The result stores its name (a bare
        ``Predictor``'s: its class name). :data:`closedloop.ORACLE` uses the
        true future (noise-free WFS measurement of the turbulence alone over the
        command's hold): the bound no predictor can beat. Must be None in open loop
        (``config.loop.closed`` False), as must ``budget_every`` and ``control_basis``.
        The string ``"oracle"`` is deprecated (a ``DeprecationWarning``); other names
        are refused (they need training: :func:`closedloop.run_trained`).
    seed : int or None
        Overrides ``config.seed``.
    progress : bool or None
        tqdm bar on stderr; None: only when stderr is a terminal.
    model : LoopModel or None
        Reuse the set-up of an earlier run of the same config.
    snapshot_every : int or None
        Every this many frames, store the residual pupil phase of ``snapshot_directions``
        (for FFT-PSF checks); an int in [1, number of frames].
    snapshot_directions : (n, 2) array or None
        Directions [arcsec] of the snapshots (default: the optical axis).
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
        study (:mod:`closedloop.compression`).
    on_predictor_fault : {"raise", "hold"}
        The predictor's output is checked at every step (shape exactly ``(horizon, M)``,
        every value finite). ``"raise"``: stop with
        ``closedloop.control.PredictorFault`` naming the predictor, the step and the
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
    duration = check_real(duration, "duration", minimum=0.0, strict_min=True)
    if not isinstance(config, SimulationConfig):
        raise TypeError(f"`config` must be a SimulationConfig; got {type(config).__name__}.")
    if on_predictor_fault not in PREDICTOR_FAULT_ACTIONS:
        raise ValueError(f"`on_predictor_fault` must be one of "
                         f"{', '.join(map(repr, PREDICTOR_FAULT_ACTIONS))}; got "
                         f"{on_predictor_fault!r}.")
    loop_pred = loop_predictor(predictor)  # the one check of `predictor`
    if loop_pred.needs_training:
        raise ValueError(f"`predictor` {loop_pred.name!r} is not trained: use "
                         "closedloop.run_trained, or LoopPredictor.trained(reference).")
    oracle = loop_pred.oracle
    predictor = "oracle" if oracle else loop_pred.predictor  # BudgetProbe's contract
    if not config.loop.closed:
        _check_open_loop(None if loop_pred.is_none else loop_pred.name, budget_every,
                         control_basis)
    check_run(config, duration, budget_every=budget_every, snapshot_every=snapshot_every)
    from closedloop.resources import check_resources

    check_resources(config, duration, limit=memory_limit, oracle=oracle,
                    budget=bool(budget_every), setup=model is None)
    if model is None:
        model = LoopModel(config)
    elif model.config != config:
        raise ValueError("`model` was built for another config.")
    seed = config.seed if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"`seed` must be a non-negative int; got {seed!r}.")
    seed = int(seed)
    loop = config.loop
    n_os = loop.oversampling
    n_int = round(loop.integration_frames * n_os)
    n_delay = round(loop.delay_frames * n_os)
    n_frames = max(1, round(duration / loop.time_step))
    dt = loop.time_step / n_os

    basis = _check_control_basis(control_basis, model.n_modes)
    if basis is not None and budget_every:
        raise ValueError("`budget_every` cannot be combined with `control_basis` (the budget "
                         "models a loop that controls every mode).")
    open_loop = not loop.closed
    n_control = model.n_modes if basis is None else basis.shape[1]
    controller = Controller(n_control, gain=loop.gain, leak=loop.leak,
                            delay_frames=loop.delay_frames,
                            integration_frames=loop.integration_frames,
                            predictor=None if oracle else predictor,
                            on_predictor_fault=on_predictor_fault)

    total = n_frames * n_os + n_delay + n_os
    atm = model.atmosphere(seed, total * dt)
    atm.reset()
    future = model.atmosphere(seed, total * dt) if oracle else None
    rng = model.noise_rng(seed)
    science = model.science
    views = science.plane_views()
    acc = [np.zeros_like(v) for v in views]
    fut_views = [np.zeros_like(v) for v in views] if oracle else None
    fut_acc = [np.zeros_like(v) for v in views] if oracle else None
    layer_buf: dict = {}
    surfaces = [np.zeros(dm.pixels.size) for dm in model.dms]
    pending: deque = deque()

    n_dir = len(science.directions)
    variance = np.empty((n_frames, n_dir))
    measured_log = np.empty((n_frames, model.n_modes))
    pol_log = np.empty((n_frames, model.n_modes))
    command_log = np.empty((n_frames, model.n_modes))
    slope_logs = [np.empty((n_frames, w.n_measurements)) for w in model.wfss]
    snaps = []
    snap_cam = None
    if snapshot_every:
        dirs = np.zeros((1, 2)) if snapshot_directions is None else snapshot_directions
        snap_cam = ScienceCamera(model.geometry, np.asarray(dirs, dtype=np.float64))
        snap_cam._flat = science._flat  # same maps, other directions

    probe = None
    if budget_every:
        from closedloop.budget import BudgetProbe

        probe = BudgetProbe(model, predictor, int(budget_every))
    bar = _progress_bar(progress, n_frames)
    scale_sci = (config.r0_wavelength / config.wavelength) ** 2
    start = time.perf_counter()
    try:
        for k in range(n_frames):
            for i in range(n_os):
                s = k * n_os + i
                while pending and pending[0][0] <= s:
                    _, command = pending.popleft()
                    for d, dm in enumerate(model.dms):
                        surfaces[d] = dm.surface(command[model.mode_slices[d]])
                atm.evolve_until(s * dt)
                _fill_planes(model, atm, views, surfaces, layer_buf)
                if probe is not None:
                    probe.step(s, atm, layer_buf, i >= n_os - n_int, _fill_planes)
                if i >= n_os - n_int:
                    for a, v in zip(acc, views, strict=True):
                        a += v
            science.measure()
            variance[k] = science.variance
            if snap_cam is not None and k % snapshot_every == 0:
                snaps.append(np.stack([snap_cam.residual_phase(d)
                                       for d in range(len(snap_cam.directions))]))
            for a in acc:
                a /= n_int
            slopes = model.slopes(acc, rng)
            measured = model.reconstruct(slopes)
            for log, sl in zip(slope_logs, slopes, strict=True):
                log[k] = sl
            for a in acc:
                a[:] = 0.0
            forecast = None
            if oracle:
                forecast = _oracle_pol(model, future, fut_views, fut_acc, layer_buf,
                                       (k + 1) * n_os + n_delay, n_os, dt)
            try:
                if basis is None:
                    command, pol, _ = controller.step(measured, forecast)
                else:
                    command_n, pol_n, _ = controller.step(
                        basis.T @ measured, None if forecast is None else basis.T @ forecast)
                    command = basis @ command_n
                    # measured + B (seen commands): the uncontrolled directions keep m
                    pol = measured + basis @ (pol_n - basis.T @ measured)
            except PredictorFault as exc:
                raise _labelled(exc, model, basis) from None
            if open_loop:
                # the controller's command is dropped and a zero one sent: the DMs stay
                # flat, the residual is the turbulence, and so is the POL
                command, pol = np.zeros(model.n_modes), measured
            if probe is not None:
                probe.frame_end(k, n_int, (k + 1) * n_os + n_delay, fut_acc)
            measured_log[k] = measured
            pol_log[k] = pol
            command_log[k] = command
            pending.append(((k + 1) * n_os + n_delay, command.copy()))
            if bar is not None:
                bar.update(1)
            if callback is not None:
                callback(k)
    finally:
        if bar is not None:
            bar.close()
    elapsed = time.perf_counter() - start
    if controller.n_faults:
        import warnings

        warnings.warn(f"predictor {loop_pred.name} returned an unusable forecast "
                      f"on {controller.n_faults} of {n_frames} frames; the last command was "
                      "held there (on_predictor_fault='hold').", RuntimeWarning, stacklevel=2)
    result = SimulationResult.from_run(
        config=config, seed=seed, model=model,
        variance=variance * scale_sci, measured=measured_log, pol=pol_log,
        commands=command_log, elapsed=elapsed, measurements=slope_logs,
        predictor_name=loop_pred.name,
        snapshots=np.array(snaps) * np.sqrt(scale_sci) if snaps else None,
        snapshot_directions=None if snap_cam is None else snap_cam.directions,
    )
    if probe is not None:
        budget = probe.result(result.residual_variance, result.closure_index, scale_sci, seed)
        result = dataclasses.replace(result, budget=budget)
    return result


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
        check_stable(loop.gain, loop.delay_frames, loop.integration_frames)
    except ValueError as exc:
        raise ValueError(str(exc).replace("`gain`", "`loop.gain`", 1)) from None
    n_frames = round(duration / loop.time_step)
    first = loop.time_step + loop.delay
    if n_frames < 1:
        raise ValueError(f"`duration` must be at least one frame (loop.time_step = "
                         f"{loop.time_step:g} s); got {duration:g} s.")
    # open loop applies no command: any whole number of frames is a valid run
    if loop.closed and n_frames * loop.time_step <= first * (1 + 1e-9):
        raise ValueError(
            f"`duration` must be longer than loop.time_step + loop.delay = {first:g} s (the "
            f"first command reaches the mirror then, so a shorter run never closes the "
            f"loop); got {duration:g} s ({n_frames} frames).")
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


def _check_open_loop(predictor, budget_every, control_basis) -> None:
    """Refuse what has no meaning when no command is applied (``loop.closed = false``)."""
    for name, value, given in (("predictor", predictor, predictor is not None),
                               ("budget_every", budget_every, bool(budget_every)),
                               ("control_basis", control_basis, control_basis is not None)):
        if given:
            shown = repr(value) if isinstance(value, str | int) else type(value).__name__
            raise ValueError(f"`{name}` must be None in open loop (`loop.closed = false`: no "
                             f"command is applied); got {shown}.")


def _check_control_basis(basis, n_modes: int) -> np.ndarray | None:
    """Validate ``control_basis``: ``(n_modes, n)`` with orthonormal columns."""
    if basis is None:
        return None
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


def _oracle_pol(model, future, views, acc, layer_buf, first_step, n_os, dt):
    """Noise-free WFS measurement of the turbulence alone, averaged over the hold window."""
    for a in acc:
        a[:] = 0.0
    for s in range(first_step, first_step + n_os):
        future.evolve_until(s * dt)
        _fill_planes(model, future, views, None, layer_buf)
        for a, v in zip(acc, views, strict=True):
            a += v
    for a in acc:
        a /= n_os
    return model.measure(acc, None)


def _progress_bar(progress, total):
    import sys

    if progress is None:
        progress = sys.stderr.isatty()
    if not progress:
        return None
    from tqdm import tqdm

    return tqdm(total=total, unit="frame", desc="closedloop", file=sys.stderr, leave=False)
