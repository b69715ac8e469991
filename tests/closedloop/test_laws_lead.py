"""The predictor's lead: the horizon the controller forecasts over, and what the command uses.

References (written in the test):
- the lead from the timing: the exposure of frame k is the last ``integration`` of the
  frame, ending at (k + 1) T; the command computed then is held from (k + 1) T + delay
  to (k + 2) T + delay. From the middle of the one to the middle of the other:
  L = delay / T + 1/2 + integration / (2 T) frames;
- deterministic pseudo-open-loop signals (a ramp, a sinusoid) and predictors written
  here that know them exactly (two-point linear extrapolation; the two-term recursion
  of a sinusoid), so the forecast at a lead L is known in closed form (between whole
  horizons the controller interpolates linearly, as its contract says);
- the integrator written out: c_k = (1 - leak) c_{k-1} + g (p^_k - seen_k), with the
  commands seen during the exposure weighted by their overlap with it;
- the oracle: the true future, i.e. the noise-free measurement of the turbulence alone
  over the command's hold window, computed here from a copy of the run's atmosphere.
"""

import math

import numpy as np
import pytest

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.control.controller import Controller
from closedloop.simulation import ORACLE, LoopModel, simulate


def _lead(delay_frames, integration_frames):
    exposure_middle = 1.0 - integration_frames / 2.0  # frame 0 ends at 1
    hold_middle = 1.0 + delay_frames + 0.5
    return hold_middle - exposure_middle


def _seen_weights(delay_frames, integration_frames, n=16):
    w = np.zeros(n)
    for j in range(n):
        on_lo = 1.0 - j + delay_frames
        w[j] = max(0.0, min(1.0, on_lo + 1.0) - max(1.0 - integration_frames, on_lo))
    return w / integration_frames


class RampExtrapolator:
    """x[n + h] = x[n] + h (x[n] - x[n-1]): exact on a ramp."""

    name = "ramp"

    def __init__(self, horizon):
        self.horizon = horizon

    def reset(self):
        self._last = None

    def update(self, x):
        x = np.asarray(x, dtype=float)
        prev = x if self._last is None else self._last
        self._last = x.copy()
        return np.array([x + h * (x - prev) for h in range(1, self.horizon + 1)])


class SinusoidRecursion:
    """x[n + 1] = 2 cos(w) x[n] - x[n - 1]: exact on any sinusoid of angular step w."""

    def __init__(self, horizon, omega):
        self.horizon = horizon
        self.omega = omega

    def reset(self):
        self._last = None

    def update(self, x):
        x = np.asarray(x, dtype=float)
        prev = x if self._last is None else self._last
        self._last = x.copy()
        out, a, b = [], prev, x
        for _ in range(self.horizon):
            a, b = b, 2.0 * math.cos(self.omega) * b - a
            out.append(b)
        return np.array(out)


TIMINGS = [(0.0, 1.0), (0.5, 1.0), (1.0, 1.0), (0.5, 0.5), (1.5, 0.25), (2.0, 0.75)]


@pytest.mark.parametrize("delay,integration", TIMINGS)
def test_lead_formula_from_the_timing(delay, integration):
    assert _lead(delay, integration) == pytest.approx(delay + 0.5 + integration / 2.0)


@pytest.mark.parametrize("delay,integration", TIMINGS)
@pytest.mark.parametrize("signal", ["ramp", "sinusoid"])
def test_controller_forecasts_the_pol_over_the_exact_lead(delay, integration, signal):
    lead = _lead(delay, integration)
    omega = 0.3
    horizon = math.ceil(lead) + 1
    if signal == "ramp":
        predictor = RampExtrapolator(horizon)
        truth = lambda t: np.array([0.3 + 0.07 * t, -1.0 - 0.02 * t])  # noqa: E731
    else:
        predictor = SinusoidRecursion(horizon, omega)
        truth = lambda t: np.array([np.sin(omega * t + 0.2), 0.5 * np.cos(omega * t)])  # noqa: E731
    gain, leak = 0.3, 0.01
    ctl = Controller(2, gain=gain, leak=leak, delay_frames=delay,
                     integration_frames=integration, predictor=predictor)
    w = _seen_weights(delay, integration)
    history = [np.zeros(2)] * w.size  # c_{k-1}, c_{k-2}, ...
    lo = math.floor(lead)
    frac = lead - lo
    for k in range(40):
        pol = truth(k)
        seen = sum(w[j] * history[j - 1] for j in range(1, w.size))
        command, pol_out, forecast = ctl.step(pol - seen)
        np.testing.assert_allclose(pol_out, pol, atol=1e-12)  # POL = m + seen commands
        if k >= 1:  # both predictors need two samples
            if signal == "ramp":
                expected = truth(k + lead)
            else:  # linear between the whole horizons around the lead
                expected = (1 - frac) * truth(k + lo) + frac * truth(k + lo + 1)
            np.testing.assert_allclose(forecast, expected, atol=1e-10)
        # the command follows that forecast
        np.testing.assert_allclose(
            command, (1 - leak) * history[0] + gain * (forecast - seen), atol=1e-12)
        history = [command] + history[:-1]


def _loop_config(delay, integration, *, wind=7.0, direction=30.0, gain=0.6):
    # a zonal (ideal) DM and an ideal WFS: the measurement is the phase on the DM's disc,
    # so the POL is the turbulence itself
    return SimulationConfig(
        name="lead",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=16),
        layers=(LayerConfig(altitude=0.0, d_over_r0=8.0, wind_speed=wind,
                            wind_direction=direction),),
        dms=(DMConfig(altitude=0.0, kind="ideal"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=integration * 1e-3,
                        delay=delay * 1e-3, gain=gain),
        field=FieldConfig(size=0.0, n_points=1), wavelength=500e-9, r0_wavelength=500e-9)


def _forecasts_from_logs(result, cfg):
    """p^_k recovered from the logs: c_k = (1 - leak) c_{k-1} + g (p^_k - (p_k - m_k))."""
    c = result.logs["dm0.commands"].coeffs
    p = result.logs["dm0.pol"].coeffs
    m = result.logs["dm0.residual"].coeffs
    prev = np.vstack([np.zeros((1, c.shape[1])), c[:-1]])
    lp = cfg.loop
    return (c - (1 - lp.leak) * prev) / lp.gain + (p - m)


@pytest.mark.parametrize("delay,integration", [(0.5, 1.0), (1.0, 0.5), (0.0, 1.0), (1.0, 1.0)])
def test_the_oracle_forecast_is_the_true_future_at_the_lead(delay, integration):
    cfg = _loop_config(delay, integration)
    n_frames = 12
    model = LoopModel(cfg)
    result = simulate(cfg, n_frames * 1e-3, seed=2, predictor=ORACLE, model=model,
                      progress=False)
    forecast = _forecasts_from_logs(result, cfg)
    # the truth: the same atmosphere (same seed), averaged over the hold window
    # [(k + 1) T + delay, (k + 2) T + delay) on the loop's internal grid
    n_os = cfg.loop.oversampling
    atm = model.atmosphere(2, (n_frames + delay + 1) * 1e-3)
    layer = atm.layers[0]
    dm = model.dms[0]
    for k in range(n_frames):
        acc = 0.0
        for i in range(n_os):
            t = ((k + 1) + delay + i / n_os) * 1e-3
            layer.evolve_until(t)
            acc = acc + layer.phase().ravel()[dm.pixels]
        np.testing.assert_allclose(forecast[k], acc / n_os, atol=1e-9)
    # the POL is the turbulence over the exposure: the last `integration` of the frame,
    # [(k + 1) T - integration, (k + 1) T) on the same grid
    n_int = round(integration * n_os)
    pol = result.logs["dm0.pol"].coeffs
    for k in range(n_frames):
        acc = 0.0
        for i in range(n_os - n_int, n_os):
            layer.evolve_until((k + i / n_os) * 1e-3)
            acc = acc + layer.phase().ravel()[dm.pixels]
        np.testing.assert_allclose(pol[k], acc / n_int, atol=1e-9)
    # the oracle's forecast at a lead of a whole number of frames is a later frame's POL
    lead = _lead(delay, integration)
    if integration == 1.0 and lead == round(lead):
        # hold window of c_k = exposure of frame k + lead
        shift = int(lead) - 1
        np.testing.assert_allclose(forecast[:n_frames - shift - 1],
                                   pol[shift + 1:], atol=1e-9)


def test_the_loop_commands_follow_the_predictors_forecast():
    # the ramp extrapolator inside simulate: the forecast the command used (recovered
    # from the logs) is the extrapolation of the logged POL over the lead
    delay, integration = 0.5, 1.0
    cfg = _loop_config(delay, integration, wind=3.0)
    lead = _lead(delay, integration)
    result = simulate(cfg, 0.015, seed=1, predictor=RampExtrapolator(3), progress=False)
    forecast = _forecasts_from_logs(result, cfg)
    p = result.logs["dm0.pol"].coeffs
    expected = p[1:] + lead * (p[1:] - p[:-1])
    np.testing.assert_allclose(forecast[1:], expected, atol=1e-9)
    assert result.predictor == "RampExtrapolator"
