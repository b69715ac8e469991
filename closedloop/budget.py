"""Error budget of a run, per science direction, from independent estimates of each term.

:func:`closedloop.simulate` with ``budget_every=N`` runs, beside the real loop and on the
same atmosphere, the estimates below every N frames; :class:`ErrorBudget` adds them up
and compares the sum with the residual the loop really left in the same frames. The
terms are estimated separately, not as differences from the measured residual, so the
comparison can fail; cross terms between them are neglected (the usual assumption of
an error budget).

fitting (with generalised fitting and anisoplanatism)
    The residual of the best the mirrors can do with what their WFSs see: the
    instantaneous turbulence projected, noise-free, by *ideal* layer-oriented sensors
    (the field-averaged phase on each DM's disc) onto all DMs' modes with the joint MAP
    reconstructor, then looked at in each direction. It holds the modes the DMs lack,
    the layers seen blurred by the WFS fields, and the footprint of each direction
    outside the DMs' sensed discs.
aliasing
    The same projection done by the real Shack-Hartmann sensors (noise-free) minus the
    ideal one: what the high orders the SH cannot resolve put into the low ones.
temporal
    The servo lag: a copy of the controller (same gain, delay, predictor) driven by the
    ideal sensors' exposure-averaged modal turbulence, and the difference between the
    instantaneous ideal projection and the command this copy has on the mirror, seen in
    each direction.
noise
    WFS noise through the reconstructor and the loop: the command covariance
    ``noise_propagation(g, delay, exposure) R N R^T`` (:mod:`modalinfo.servo`), seen in
    each direction by a Monte-Carlo average of 64 draws. With a predictor the loop
    filters noise differently; the integrator's factor is used (a stated approximation).
"""

from __future__ import annotations

import copy
from collections import deque

import numpy as np

from closedloop.control.controller import Controller
from closedloop.model import LoopModel
from closedloop.optics import _kernels
from closedloop.optics.science import ScienceCamera
from closedloop.resources import ideal_sensor_config as _ideal_config  # counted there too
from closedloop.result import ErrorBudget  # the budget's numbers live with the run's result
from closedloop.state import LoopState
from modalinfo.servo import noise_propagation

__all__ = ["ErrorBudget", "BudgetProbe"]

_N_NOISE_DRAWS = 64


class BudgetProbe:
    """Runs the budget's estimates alongside :func:`closedloop.simulate` (internal).

    Parameters
    ----------
    model : LoopModel
        The run's model.
    predictor : modalinfo.forecast.Predictor or None
        The run's predictor (deep-copied: its fitted state, not its running state); None
        without a predictor and for the oracle.
    every : int
        Estimate every this many frames.
    oracle : bool
        The run forecasts with the true future: :meth:`frame_end` then gets the oracle's
        exposure-averaged turbulence maps.
    """

    def __init__(self, model: LoopModel, predictor, every: int, *, oracle: bool = False):
        self.model = model
        self.ideal = LoopModel(_ideal_config(model.config))
        self.every = every
        loop = model.config.loop
        self.oracle = oracle
        self.controller = Controller(
            model.n_modes, gain=loop.gain, leak=loop.leak, delay_frames=loop.delay_frames,
            integration_frames=loop.integration_frames,
            predictor=None if predictor is None else copy.deepcopy(predictor),
            projector=None if predictor is None else model.controlled_projector)
        self.cam = ScienceCamera(model.geometry, model.science.directions)
        self.turb = [np.zeros_like(v) for v in self.cam.plane_views()]
        self.acc = [np.zeros_like(v) for v in self.turb]
        self.pending: deque = deque()
        self.applied = np.zeros(model.n_modes)
        self.rows: dict[str, list] = {"frame": [], "fitting": [], "sh": [], "temporal": []}

    # ------------------------------------------------------------------ loop hooks
    def step(self, s: int, state: LoopState, in_exposure: bool) -> None:
        """At internal step ``s``: apply due commands, take the run's turbulence, accumulate."""
        while self.pending and self.pending[0][0] <= s:
            self.applied = self.pending.popleft()[1]
        state.turbulence(self.turb)
        if in_exposure:
            for a, t in zip(self.acc, self.turb, strict=True):
                a += t

    def frame_end(self, k: int, n_int: int, apply_step: int,
                  future_maps: list[np.ndarray] | None = None) -> None:
        """At the end of frame ``k`` (after the science sample of the real loop).

        ``apply_step``: the internal step at which this frame's command reaches the
        mirrors; ``future_maps``: the oracle's maps (None without the oracle).
        """
        if k % self.every == 0:
            fit = self.ideal.sense(self.turb, None)
            sh = self.model.sense(self.turb, None)
            self.rows["frame"].append(k)
            self.rows["fitting"].append(self._variance(self.turb, fit))
            self.rows["sh"].append(self._variance(self.turb, sh))
            self.rows["temporal"].append(self._variance(None, fit - self.applied))
        for a in self.acc:
            a /= n_int
        # the ideal sensors see the modal turbulence y; the residual they would measure is
        # y less what this controller's mirror did during the exposure
        y = self.ideal.sense(self.acc, None)
        for a in self.acc:
            a[:] = 0.0
        forecast = None
        if self.oracle and future_maps is not None:
            forecast = self.ideal.sense(future_maps, None)
        command, _, _ = self.controller.step(y - self.controller.seen_commands(), forecast)
        self.pending.append((apply_step, command.copy()))

    def _variance(self, turbulence, commands) -> np.ndarray:
        """Piston-removed variance per direction of ``turbulence - DMs(commands)``."""
        views = self.cam.plane_views()
        for p, v in enumerate(views):
            if turbulence is None:
                v[:] = 0.0
            else:
                v[:] = turbulence[p]
        for d, dm in enumerate(self.model.dms):
            _kernels.subtract_scatter(views[dm.plane], dm.pixels,
                                      dm.forward(commands[self.model.mode_slices[d]]), 1.0)
        return self.cam.forward().copy()

    # ------------------------------------------------------------------ result
    def _noise_variance(self, seed: int) -> np.ndarray:
        model = self.model
        loop = model.config.loop
        noise = np.concatenate([np.full(w.n_measurements, w.noise_rms ** 2)
                                for w in model.wfss])
        if not np.any(noise > 0):
            return np.zeros(len(self.cam.directions))
        if model.reconstructor is not None:
            rec = model.reconstructor
        else:
            rec = np.zeros((model.n_modes, noise.size))
            start = 0
            for w in model.wfss:
                block = (np.eye(w.n_measurements) if w.reconstructor is None
                         else w.reconstructor)
                rec[model.mode_slices[w.dm.index], start:start + w.n_measurements] = block
                start += w.n_measurements
        factor = noise_propagation(gain=loop.gain, delay_frames=loop.delay_frames,
                                   integration_frames=loop.integration_frames)
        # draws c = sqrt(factor) R n with n ~ N(0, diag(noise)): covariance factor R N R^T
        rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
        out = np.zeros(len(self.cam.directions))
        for _ in range(_N_NOISE_DRAWS):
            c = np.sqrt(factor) * (rec @ (np.sqrt(noise) * rng.standard_normal(noise.size)))
            out += self._variance(None, c)
        return out / _N_NOISE_DRAWS

    def result(self, measured: np.ndarray, start: int, scale: float, seed: int) -> ErrorBudget:
        """Return the budget over the probed frames from ``start`` on (``scale``: to science)."""
        frames = np.array(self.rows["frame"], dtype=np.int64)
        keep = frames >= start
        if not np.any(keep):
            keep = np.ones_like(frames, dtype=bool)
        fit = np.array(self.rows["fitting"])[keep].mean(axis=0)
        sh = np.array(self.rows["sh"])[keep].mean(axis=0)
        temporal = np.array(self.rows["temporal"])[keep].mean(axis=0)
        noise = self._noise_variance(seed)
        return ErrorBudget(directions=np.array(self.cam.directions), fitting=fit * scale,
                           aliasing=(sh - fit) * scale, temporal=temporal * scale,
                           noise=noise * scale,
                           measured=measured[frames[keep]].mean(axis=0),
                           frames=frames[keep])
