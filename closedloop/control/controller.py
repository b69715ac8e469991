"""Per-mode integrator with pseudo-open-loop (POL) prediction, on the shared servo model.

Timing (exact on the simulator's internal grid, the model of :mod:`modalinfo.servo`):
frame ``k`` ends at ``t_k = (k + 1) T``; the WFS integrated the residual over the last
``integration_time`` of the frame; the command ``c_k`` computed from it is applied from
``t_k + delay`` until ``c_{k+1}`` replaces it. The WFS therefore saw the combination
``sum_j w_j c_{k-j}`` of past commands (``modalinfo.servo.command_weights``), and the
pseudo-open-loop coefficients are

    p_k = m_k + sum_j w_j c_{k-j}

(measured modal residual plus what the mirror did during the exposure): the modal
turbulence the WFS would have measured without correction.

The control law is the integrator with the POL replaced by its forecast:

    c_k = (1 - leak) c_{k-1} + g (p^_k - sum_j w_j c_{k-j}),

where ``p^_k`` is the forecast of the POL over the lead ``L = delay / T + 1/2 +
integration / (2 T)`` frames (from the middle of the exposure to the middle of the
application window). Without a predictor ``p^_k = p_k`` and the law is exactly the
classic integrator ``c_k = (1 - leak) c_{k-1} + g m_k``; the persistence predictor gives
the same thing, bit for bit. With the MAP reconstructor the POL is reconstructed from the
pseudo-open-loop measurements (``sensed``: pseudo-open-loop control) and the law is no
longer the classic integrator. A per-mode predictor's forecast is kept inside the modes
the reconstructor controls (``projector``: ``p^_k <- p_k + R G (p^_k - p_k)``): directions
no WFS sees would otherwise be commanded from the predictor's own past commands alone,
never measured, and drift (on table1-solar the ARMA lost the loop). A predictor is any
``modalinfo.forecast.Predictor`` (fitted beforehand): ``reset()`` once, ``update(p_k)``
each frame (O(1)), returning forecasts for horizons 1..H; a fractional lead is
interpolated linearly between the two whole horizons around it (horizon 0 being ``p_k``
itself).

How this relates to the paper: LOST applied its predictors "as filters on the correction
signals". Here they filter the POL signal, the open-loop modal turbulence reconstructed
from the measurement and the known commands, which is what a forecast must extrapolate
(the closed-loop residual is whitened by the loop itself); the integrator then follows
the forecast instead of the last measurement.
"""

from __future__ import annotations

import math

import numpy as np

from closedloop.optics.products import DenseProduct
from modalinfo.servo import check_loop, check_stable, command_weights

__all__ = ["Controller", "PredictorFault", "lead_frames", "PREDICTOR_FAULT_ACTIONS"]

#: what the loop does when a predictor's output is unusable (``on_predictor_fault``)
PREDICTOR_FAULT_ACTIONS = ("raise", "hold")


class PredictorFault(ValueError):  # noqa: N818 - a fault, not an error of the loop
    """A predictor returned an unusable forecast inside the loop.

    Attributes
    ----------
    step : int
        Loop frame at which it happened (0-based).
    mode : int or None
        Index of the first offending mode (all DMs concatenated), None for a shape fault.
    """

    def __init__(self, message: str, *, step: int, mode: int | None):
        super().__init__(message)
        self.step = step
        self.mode = mode


def lead_frames(delay_frames: float, integration_frames: float) -> float:
    """Forecast lead [frames]: middle of the exposure to the middle of the command's hold."""
    return delay_frames + 0.5 + integration_frames / 2.0


class Controller:
    """Integrators of all modes, with an optional POL predictor.

    Parameters
    ----------
    n_modes : int
        Total number of controlled modes (all DMs concatenated).
    gain, leak : float
        Integrator gain and leak.
    delay_frames, integration_frames : float
        Loop timing in frames.
    predictor : modalinfo.forecast.Predictor or None
        Fitted predictor of the POL coefficients, or None. Its output at every step must
        be finite and of shape exactly ``(predictor.horizon, n_modes)`` (a ``(n_modes,)``
        vector is refused, not reshaped).
    on_predictor_fault : {"raise", "hold"}
        A wrong shape or a non-finite value raises :class:`PredictorFault` naming the
        predictor, the step and the mode (``"raise"``), or keeps the last command for
        that frame and counts it in :attr:`n_faults` (``"hold"``).
    projector : (n_modes, n_modes) ndarray or None
        The projector onto the commands the WFSs see
        (``LoopModel.controlled_projector``). A predictor's forecast is replaced by
        ``p_k + P (p^_k - p_k)``: its change over the POL is kept only where the loop can
        measure it (an external forecast, the oracle's, is sensed and already lies
        there). None: the forecast is used as it is.
    sensed : (n_modes, n_modes) ndarray or None
        ``R G``, what the reconstruction makes of a command, when it is not the identity
        on the commands (the MAP reconstructor, ``LoopModel.sensed_commands``): the POL is
        then ``p_k = m_k + R G sum_j w_j c_{k-j}``, the reconstruction of the
        pseudo-open-loop measurements ``s_k + G sum_j w_j c_{k-j}``, and the law above
        integrates ``p^_k - sum_j w_j c_{k-j}`` (pseudo-open-loop control: Ellerbroek &
        Vogel 2003, Proc. SPIE 5169, 206; Gilles 2005, Appl. Opt. 44, 993, who shows that
        a minimum-variance reconstructor cascaded with the plain integrator is unstable
        in MCAO, and pseudo-open-loop control stable). The commands then follow the MAP
        estimate of the turbulence, each direction at the gain ``g``. None: ``R G`` is
        the identity on the commands (a least-squares or truncated reconstructor, whose
        commands lie where it is) and ``p_k = m_k + sum_j w_j c_{k-j}``, the classic
        integrator.
    float32_from : float
        Float64 size [bytes] from which the ``projector`` and ``sensed`` products run in
        float32 (:class:`closedloop.optics.products.DenseProduct`; the loop passes
        :data:`closedloop.optics.products.FLOAT32_MIN_BYTES` when a mirror asks for large
        products: ``est-mcao``'s ``R G`` is 4,881 x 4,881, 190 MB in float64 read every
        frame). Default ``inf``: always float64.
    """

    def __init__(self, n_modes: int, *, gain: float, leak: float, delay_frames: float,
                 integration_frames: float, predictor=None, on_predictor_fault: str = "raise",
                 projector: np.ndarray | None = None, sensed: np.ndarray | None = None,
                 float32_from: float = math.inf):
        if on_predictor_fault not in PREDICTOR_FAULT_ACTIONS:
            raise ValueError(f"`on_predictor_fault` must be one of "
                             f"{', '.join(map(repr, PREDICTOR_FAULT_ACTIONS))}; got "
                             f"{on_predictor_fault!r}.")
        gain, delay_frames, integration_frames = check_loop(gain, delay_frames,
                                                            integration_frames)
        check_stable(gain, delay_frames, integration_frames, leak=leak)
        self.gain = gain
        self.leak = leak
        self.weights = command_weights(delay_frames, integration_frames)
        self.lead = lead_frames(delay_frames, integration_frames)
        self.predictor = predictor
        self.n_modes = n_modes
        if projector is not None:
            projector = np.asarray(projector, dtype=np.float64)
            if projector.shape != (n_modes, n_modes) or not np.isfinite(projector).all():
                raise ValueError(f"`projector` must be a finite ({n_modes}, {n_modes}) "
                                 f"array; got shape {projector.shape}.")
        self.projector = projector
        if sensed is not None:
            sensed = np.asarray(sensed, dtype=np.float64)
            if sensed.shape != (n_modes, n_modes) or not np.isfinite(sensed).all():
                raise ValueError(f"`sensed` must be a finite ({n_modes}, {n_modes}) "
                                 f"array; got shape {sensed.shape}.")
        self.sensed = sensed
        # the products of the step (float32 for large matrices when asked, else float64)
        self._project = None if projector is None else DenseProduct(projector, float32_from)
        self._sense = None if sensed is None else DenseProduct(sensed, float32_from)
        self.on_predictor_fault = on_predictor_fault
        #: frames whose forecast was unusable and whose command was held ("hold")
        self.n_faults = 0
        self._step = 0
        # history of past commands c_{k-1}, c_{k-2}, ... (newest first)
        self._history = np.zeros((self.weights.size, n_modes))
        if predictor is not None:
            horizon = int(getattr(predictor, "horizon", 1))
            if horizon < math.ceil(self.lead):
                raise ValueError(
                    f"`predictor.horizon` must be >= {math.ceil(self.lead)} (the lead of "
                    f"{self.lead:g} frames rounded up); got {horizon}."
                )
            predictor.reset()
            self._expected = (horizon, n_modes)

    def reset(self) -> None:
        """Back to the state after construction: no past command, step 0, the predictor reset."""
        self.n_faults = 0
        self._step = 0
        self._history[:] = 0.0
        if self.predictor is not None:
            self.predictor.reset()

    @property
    def command(self) -> np.ndarray:
        """The latest command ``c_{k-1}``."""
        return self._history[0]

    def seen_commands(self) -> np.ndarray:
        """``sum_j w_j c_{k-j}``: what the mirror did during frame k's exposure (``w_0 = 0``)."""
        # weights[j] multiplies c_{k-j}; _history[j - 1] holds c_{k-j}
        return self.weights[1:] @ self._history[: self.weights.size - 1]

    def step(self, measured: np.ndarray, forecast_pol: np.ndarray | None = None) -> tuple:
        """Advance one frame from the modal residual ``m_k``.

        Parameters
        ----------
        measured : (M,) ndarray
            Reconstructed modal residual of frame ``k``.
        forecast_pol : (M,) ndarray or None
            An externally supplied POL forecast (the oracle); overrides the predictor.

        Returns
        -------
        command, pol, forecast : (M,) ndarrays
            The new command ``c_k``, the POL ``p_k`` and the forecast ``p^_k`` used.
        """
        seen = self.seen_commands()
        pol = measured + (seen if self._sense is None else self._sense(seen))
        step = self._step
        self._step += 1
        if forecast_pol is not None:
            forecast = forecast_pol
        elif self.predictor is not None:
            try:
                forecast = self._forecast(pol, step)
                if self.projector is not None:
                    # a per-mode forecast leaks into the directions no WFS sees; commanded
                    # there, they are never measured and drift (table1-solar's ARMA lost
                    # the loop): keep only the forecast's change the loop can observe.
                    # Persistence's change is exactly 0, so its bits stay the integrator's
                    forecast = pol + self._project(forecast - pol)
            except PredictorFault:
                if self.on_predictor_fault == "raise":
                    raise
                self.n_faults += 1
                command = self._history[0].copy()  # hold: the mirror keeps c_{k-1}
                self._history[1:] = self._history[:-1]
                self._history[0] = command
                return command, pol, pol
        else:
            forecast = pol
        command = (1.0 - self.leak) * self._history[0] + self.gain * (forecast - seen)
        self._history[1:] = self._history[:-1]
        self._history[0] = command
        return command, pol, forecast

    def _forecast(self, pol: np.ndarray, step: int) -> np.ndarray:
        raw = self.predictor.update(pol)
        name = type(self.predictor).__name__
        hint = " (on_predictor_fault='hold' keeps the last command instead)"
        try:
            out = np.asarray(raw, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise PredictorFault(f"predictor {name} returned {type(raw).__name__} at step "
                                 f"{step}, not an array of numbers{hint}.", step=step,
                                 mode=None) from exc
        if out.shape != self._expected:
            raise PredictorFault(
                f"predictor {name} returned shape {out.shape} at step {step}; the loop "
                f"needs exactly {self._expected} (horizons x modes){hint}.",
                step=step, mode=None)
        # one pass per step (~2 us for 10 x 200): the loop never runs on NaN or inf
        if not np.isfinite(out).all():
            h, m = np.argwhere(~np.isfinite(out))[0]
            raise PredictorFault(
                f"predictor {name} returned {out[h, m]} at step {step} for mode {m} "
                f"(horizon {h + 1}){hint}.", step=step, mode=int(m))
        lo = math.floor(self.lead)
        frac = self.lead - lo
        below = pol if lo == 0 else out[lo - 1]
        if frac == 0.0:
            return np.array(below)
        # below + frac (above - below): exact when the two horizons agree (persistence)
        return below + frac * (out[lo] - below)
