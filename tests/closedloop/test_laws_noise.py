"""WFS noise from first principles: slope noise, and command noise through the loop.

References (computed in the test, not with closedloop's ``noise_rms`` or
``modalinfo.servo``):
- a configured noise of alpha arcsec RMS per axis per subaperture is a wavefront tilt of
  alpha; as a phase gradient at the wavelength of the simulator's phase (``r0_wavelength``)
  it is ``2 pi alpha [rad] / lambda`` rad/m (alpha in rad = alpha'' pi / 648000). The
  slope unit is checked independently: a plane wave tilted by alpha gives every x slope
  exactly that value;
- the command noise of the per-mode integrator: the impulse response of the loop's
  difference equation, written here from the timing (a command computed at the end of
  frame k is applied from (k + 1) T + delay to (k + 2) T + delay; the WFS of frame k
  integrates over the last ``integration`` of the frame, so it sees past commands with
  weights equal to their overlap with the exposure), fed with the measurement noise
  reconstructed by the WFS's reconstructor R: command covariance
  ``sum_k h_k^2 sigma^2 R R^T``. The statistical tolerance comes from the same impulse
  response (the estimate's correlation time) and the effective number of modes.
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
from closedloop.simulation import LoopModel, simulate

# negligible turbulence on purpose (D/r0 = 1e-6, a total r0 of 4000 km): the loop sees
# its noise only
pytestmark = pytest.mark.filterwarnings("ignore:`total r0 .* is beyond 1 m at 500 nm:UserWarning")

ARCSEC = math.pi / 648000.0


def _config(*, noise, r0_wavelength=500e-9, gain=0.4, delay=0.5e-3, integration=1e-3,
            n_modes=20):
    # turbulence negligible (D/r0 = 1e-6 gives ~1e-10 rad^2): the WFS sees its noise
    return SimulationConfig(
        name="noise",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32),
        layers=(LayerConfig(altitude=0.0, d_over_r0=1e-6, wind_speed=0.0),),
        dms=(DMConfig(altitude=0.0, n_modes=n_modes),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=8, noise=noise,
                        field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=integration, delay=delay,
                        gain=gain),
        field=FieldConfig(size=0.0, n_points=1), wavelength=630e-9,
        r0_wavelength=r0_wavelength)


@pytest.mark.parametrize("alpha,wavelength", [(0.01, 500e-9), (0.03, 1.0e-6)])
def test_slope_noise_is_the_configured_angle_as_a_phase_gradient(alpha, wavelength):
    cfg = _config(noise=alpha, r0_wavelength=wavelength)
    model = LoopModel(cfg)
    wfs = model.wfss[0]
    g = model.geometry
    expected = 2.0 * math.pi * alpha * ARCSEC / wavelength  # rad of phase per m
    # the slope unit: a plane wave tilted by alpha along x (phase 2 pi alpha x / lambda)
    maps = []
    for p, plane in enumerate(g.planes):
        x = g.plane_coords(p)
        maps.append(np.tile(expected * x, (plane.n, 1)))
    tilt = wfs.forward(maps)
    n_sub = wfs.n_measurements // 2
    np.testing.assert_allclose(tilt[:n_sub], expected, rtol=1e-9)
    np.testing.assert_allclose(tilt[n_sub:], 0.0, atol=1e-9 * expected)
    # the noise of a WFS that sees no phase: 500 draws of every slope
    zero = [np.zeros((p.n, p.n)) for p in g.planes]
    rng = model.noise_rng(7)
    draws = np.array([model.measure(zero, rng)[0] for _ in range(500)])
    # the configured angle is a fully lit subaperture's; a pupil-edge one collects less
    # light and is noisier (test_lit_share_left31): the fully lit slopes only
    full = np.asarray(wfs.field_share) == 1.0
    assert full.sum() >= 0.6 * full.size                 # 32 of 52 on 8 x 8
    n_sub = int(full[:n_sub].sum())
    draws = draws[:, full]
    # 500 x 64 Gaussian draws: the RMS has a relative s.e. of ~0.4 %
    rel_se = 1.0 / math.sqrt(2.0 * draws.size)
    assert np.sqrt(np.mean(draws ** 2)) == pytest.approx(expected, rel=5 * rel_se)
    # each axis alike, no bias
    assert np.sqrt(np.mean(draws[:, :n_sub] ** 2)) == pytest.approx(expected, rel=8 * rel_se)
    assert abs(draws.mean()) < 5 * expected / math.sqrt(draws.size)


def _seen_weights(delay_frames, integration_frames, n=16):
    """w[j]: share of frame k's exposure during which command c_{k-j} was on the mirror."""
    exp_lo, exp_hi = 1.0 - integration_frames, 1.0  # frame k = 0's exposure, in frames
    w = np.zeros(n)
    for j in range(n):
        on_lo = -j + 1.0 + delay_frames  # c_{-j} computed at (1 - j) T, applied after delay
        on_hi = on_lo + 1.0
        w[j] = max(0.0, min(exp_hi, on_hi) - max(exp_lo, on_lo)) / integration_frames
    return w


def _impulse_response(gain, delay_frames, integration_frames, n=600):
    """Commands of one mode after a unit measurement-noise impulse at frame 0."""
    w = _seen_weights(delay_frames, integration_frames)
    c = np.zeros(n)
    for k in range(n):
        seen = sum(w[j] * c[k - j] for j in range(1, w.size) if k - j >= 0)
        c[k] = (c[k - 1] if k else 0.0) + gain * ((1.0 if k == 0 else 0.0) - seen)
    return c


def test_seen_weights_of_the_usual_timings():
    # a hand check of the test's own timing: 0.5-frame delay, full exposure -> half of
    # the last and half of the one before; one-frame delay -> all of the one before
    np.testing.assert_allclose(_seen_weights(0.5, 1.0)[:3], [0.0, 0.5, 0.5])
    np.testing.assert_allclose(_seen_weights(1.0, 1.0)[:3], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(_seen_weights(0.0, 1.0)[:3], [0.0, 1.0, 0.0])
    np.testing.assert_allclose(_seen_weights(0.0, 0.5)[:3], [0.0, 1.0, 0.0])


@pytest.mark.parametrize("gain,delay,integration", [
    (0.4, 0.5e-3, 1e-3),
    (0.3, 1e-3, 0.5e-3),
])
def test_command_noise_is_the_noise_through_reconstructor_and_servo(gain, delay, integration):
    alpha = 0.02
    cfg = _config(noise=alpha, gain=gain, delay=delay, integration=integration)
    model = LoopModel(cfg)
    wfs = model.wfss[0]
    r = wfs.reconstructor
    # the loop is one scalar filter per mode when the reconstructor inverts the
    # interaction exactly (every mode kept)
    np.testing.assert_allclose(r @ wfs.interaction, np.eye(r.shape[0]), atol=1e-9)
    sigma = 2.0 * math.pi * alpha * ARCSEC / cfg.r0_wavelength
    h = _impulse_response(gain, delay / 1e-3, integration / 1e-3)
    ntf = float(np.sum(h ** 2))
    cov = ntf * sigma ** 2 * (r @ r.T)
    n_frames, skip = 1500, 100
    result = simulate(cfg, n_frames * 1e-3, seed=4, progress=False)
    commands = result.logs["dm0.commands"].coeffs[skip:]
    measured_total = float(np.sum(np.var(commands, axis=0)))
    expected_total = float(np.trace(cov))
    # s.e. of a variance estimated from N correlated samples: sqrt(2 sum_k rho_k^2 / N);
    # over modes, divided by the effective number of independent modes tr(C)^2 / tr(C^2)
    rho = np.correlate(h, h, "full")[h.size - 1:] / ntf
    m_eff = np.trace(cov) ** 2 / np.trace(cov @ cov)
    rel_se = math.sqrt(2.0 * (2.0 * np.sum(rho ** 2) - 1.0) / (n_frames - skip) / m_eff)
    assert measured_total == pytest.approx(expected_total, rel=4.5 * rel_se)
    print(f"command noise {measured_total:.4g} vs {expected_total:.4g} rad^2 "
          f"(s.e. {rel_se:.1%})")
