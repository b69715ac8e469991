"""The error budget's noise and temporal terms against outside references.

Temporal: in a loop whose only error is the servo lag (ideal sensor, zonal "ideal" DM
that takes any shape on its disc, no noise, one layer on the pupil), the fitting,
aliasing and noise terms are 0 and the temporal term must be the residual the real loop
left in the same frames (its science camera: an independent path from the budget's copy
of the controller), for several gains, delays and exposures; the residual itself obeys
the pure-delay structure-function law (test_physics.py), so the temporal term does too.

Fitting: in a loop whose only error is fitting (static turbulence, ideal sensor, a
20-mode Zernike DM, gain 1, no delay) the aliasing, temporal and noise terms are 0 and
the fitting term is the real loop's residual (which test_physics.py checks against
Noll's Delta_J).

Noise: the analytic propagation of the configured noise in a noise-only loop.

References (computed in the test, not with ``modalinfo.servo`` or the budget's code):
- the slope noise: a configured alpha arcsec RMS per axis per subaperture is the phase
  gradient ``2 pi alpha [rad] / r0_wavelength`` rad/m (a tilt of alpha);
- the servo's noise transfer in closed form: with a one-frame exposure and a one-frame
  delay the integrator is ``c_k = c_{k-1} + g (n_k - c_{k-2})``, an AR(2) process
  ``c_k = c_{k-1} - g c_{k-2} + g n_k`` whose variance per unit noise variance is
  ``g^2 (1 - phi2) / ((1 + phi2) ((1 - phi2)^2 - phi1^2))`` with phi1 = 1, phi2 = -g
  (Box & Jenkins 1976, eq. 3.2.27), i.e. ``g (1 + g) / ((1 - g) (2 + g))``; with a half-frame
  delay the command seen is the mean of the last two, and the variance is the sum of the
  squared impulse response of the difference equation written here; with a half-frame
  delay and a half-frame exposure (the frame's end) each exposure sees one command only,
  an AR(1) process of variance ``g / (2 - g)`` (this case pins the exposure's part in
  the propagation: with a whole-frame exposure it would be the half-frame sum);
- the command covariance ``ntf sigma^2 R R^T`` (R: the WFS's reconstructor, the
  matrix the loop applies), seen in every science direction as the piston-removed
  variance of the mirror's modes over the pupil: ``tr(Gram C)`` with ``Gram`` the
  modes' piston-removed inner products over the pupil pixels (a ground DM: every
  direction sees the same footprint), converted to the science wavelength by
  ``(r0_wavelength / wavelength)^2``.
The budget draws the noise by Monte Carlo; the test raises its number of draws so that
the scatter, computed here as ``sqrt(2 tr((Gram C)^2) / n_draws) / tr(Gram C)`` (the
variance of a Gaussian quadratic form), is below 1.5 %, and allows 4.5 times it. Two
cases: one ground DM (every direction sees the same footprint), and two DMs with the
joint MAP reconstructor, where the field's directions read the 5-km DM 8 whole pixels
off axis (the expected term, from each direction's Gram matrix of both DMs' modes,
falls from 0.032 on axis to 0.023 in the corners; measured 0.989-0.994 of it).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from closedloop import budget as budget_module
from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.model import LoopModel
from closedloop.simulation import simulate

from .conftest import lag_only

# negligible turbulence on purpose (D/r0 = 1e-6, a total r0 of 4000 km): the loop sees
# its noise only
pytestmark = pytest.mark.filterwarnings("ignore:`total r0 .* is beyond 1 m at 500 nm:UserWarning")

ARCSEC = math.pi / 648000.0
N_DRAWS = 4096


@pytest.mark.parametrize("gain,delay,integration", [
    (1.0, 0.0, 1e-3), (0.5, 0.5e-3, 1e-3), (0.4, 1e-3, 0.5e-3)])
def test_temporal_term_is_the_residual_of_a_lag_only_loop(gain, delay, integration):
    cfg = lag_only(gain=gain, delay=delay, integration=integration)
    b = simulate(cfg, 0.03, seed=1, progress=False, budget_every=1).budget
    assert b.frames.size >= 10
    for term in (b.fitting, b.aliasing, b.noise):
        np.testing.assert_array_equal(term, 0.0)
    assert np.all(b.temporal > 0)
    np.testing.assert_allclose(b.temporal, b.measured, rtol=1e-9)


def test_fitting_term_is_the_residual_of_a_fitting_only_loop():
    cfg = lag_only(gain=1.0, delay=0.0, integration=1e-3)
    dm = dataclasses.replace(cfg.dms[0], kind="zernike")
    layer = dataclasses.replace(cfg.layers[0], wind_speed=0.0, d_over_r0=10.0)
    cfg = cfg.replace(dms=(dm,), layers=(layer,))
    b = simulate(cfg, 0.02, seed=1, progress=False, budget_every=1).budget
    assert b.frames.size >= 5
    for term in (b.aliasing, b.temporal, b.noise):
        np.testing.assert_array_equal(term, 0.0)
    assert np.all(b.fitting > 0)
    np.testing.assert_allclose(b.fitting, b.measured, rtol=1e-9)


def _config(*, alpha, gain, delay, integration=1e-3):
    # turbulence negligible (D/r0 = 1e-6): the loop sees its noise only
    return SimulationConfig(
        name="noise-budget",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32),
        layers=(LayerConfig(altitude=0.0, d_over_r0=1e-6, wind_speed=0.0),),
        dms=(DMConfig(altitude=0.0, n_modes=20),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=8, noise=alpha,
                        field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=integration, delay=delay,
                        gain=gain),
        field=FieldConfig(size=20.0, n_points=3), wavelength=630e-9, r0_wavelength=500e-9)


def _ntf_closed_form(gain):
    phi1, phi2 = 1.0, -gain
    return gain ** 2 * (1 - phi2) / ((1 + phi2) * ((1 - phi2) ** 2 - phi1 ** 2))


def _ntf_half_frame(gain, n=4000):
    """Sum of squares of c_k = c_{k-1} + g (n_k - (c_{k-1} + c_{k-2}) / 2) for a unit impulse."""
    c = np.zeros(n)
    for k in range(n):
        c1 = c[k - 1] if k >= 1 else 0.0
        c2 = c[k - 2] if k >= 2 else 0.0
        c[k] = c1 + gain * ((1.0 if k == 0 else 0.0) - 0.5 * (c1 + c2))
    return float(np.sum(c ** 2))


def _ntf_short_exposure(gain):
    """Half-frame delay, half-frame exposure at the frame's end: AR(1) variance.

    The exposure of frame k, the last half of the frame, sees only ``c_{k-1}`` (applied
    half a frame after frame k-1's end, held one frame), so ``c_k = (1 - g) c_{k-1} +
    g n_k`` and the variance per unit noise is ``g^2 / (1 - (1 - g)^2) = g / (2 - g)``.
    """
    return gain / (2.0 - gain)


def test_closed_form_is_the_impulse_response():
    # the AR(2) variance against a direct sum of the squared impulse response
    g = 0.4
    c = np.zeros(4000)
    for k in range(c.size):
        c[k] = (c[k - 1] if k else 0.0) + g * ((k == 0) - (c[k - 2] if k >= 2 else 0.0))
    assert _ntf_closed_form(g) == pytest.approx(float(np.sum(c ** 2)), rel=1e-12)
    assert _ntf_closed_form(g) == pytest.approx(g * (1 + g) / ((1 - g) * (2 + g)), rel=1e-14)


def _pupil_gram(model):
    """Piston-removed inner products of the DM's modes over the pupil pixels."""
    g = model.geometry
    dm = model.dms[0]
    plane = g.planes[dm.plane]
    maps = np.zeros((dm.shapes.shape[1], plane.n * plane.n))
    maps[:, dm.pixels] = dm.shapes.T
    maps = maps.reshape(-1, plane.n, plane.n)
    off = plane.centre - (g.n_pixels - 1) / 2.0   # the pupil's pixels on the plane
    o = int(round(off))
    assert off == o
    pup = maps[:, o:o + g.n_pixels, o:o + g.n_pixels][:, g.pupil_mask]
    pup = pup - pup.mean(axis=1, keepdims=True)
    return pup @ pup.T / pup.shape[1]


@pytest.mark.parametrize("alpha,gain,delay,integration", [
    (0.02, 0.4, 1e-3, 1e-3), (0.01, 0.5, 0.5e-3, 1e-3), (0.02, 0.5, 0.5e-3, 0.5e-3)])
def test_noise_term_is_the_propagated_configured_noise(monkeypatch, alpha, gain, delay,
                                                       integration):
    monkeypatch.setattr(budget_module, "_N_NOISE_DRAWS", N_DRAWS)
    cfg = _config(alpha=alpha, gain=gain, delay=delay, integration=integration)
    model = LoopModel(cfg)
    r = model.wfss[0].reconstructor
    sigma = 2.0 * math.pi * alpha * ARCSEC / cfg.r0_wavelength
    if integration < 1e-3:
        ntf = _ntf_short_exposure(gain)
    elif delay == 1e-3:
        ntf = _ntf_closed_form(gain)
    else:
        ntf = _ntf_half_frame(gain)
    # each slope's variance sigma^2 / its light share: the pupil-edge subapertures'
    # noise follows their lit area (left31-edge, test_lit_share_left31 checks the law)
    var = sigma ** 2 / model.wfss[0].field_share
    np.testing.assert_allclose(np.asarray(model.wfss[0].noise_rms) ** 2
                               * np.ones_like(var), var, rtol=1e-12)
    cov = ntf * ((r * var[None, :]) @ r.T)
    gc = _pupil_gram(model) @ cov
    to_science = (cfg.r0_wavelength / cfg.wavelength) ** 2
    expected = float(np.trace(gc)) * to_science
    rel_se = math.sqrt(2.0 * np.trace(gc @ gc) / N_DRAWS) / float(np.trace(gc))
    assert rel_se < 0.01
    result = simulate(cfg, 0.01, seed=2, progress=False, model=model, budget_every=2)
    noise = result.budget.noise
    assert noise.shape == (9,)
    # a ground DM: every direction sees the same footprint, so the same draws
    np.testing.assert_allclose(noise, noise[0], rtol=1e-9)
    assert noise[0] == pytest.approx(expected, rel=4.5 * rel_se)
    print(f"noise term {noise[0]:.5g} vs {expected:.5g} rad^2 (s.e. {rel_se:.2%})")


def _mcao_noise_config(alpha, shift_px):
    # two DMs, two WFSs; the field's corner directions read the 5-km plane `shift_px`
    # whole pixels off axis (theta = k dx / h), so the science camera copies pixels. The
    # joint MAP reconstructor needs turbulence in its prior (with none it controls
    # nothing); the noise term depends on R and the noise only, not on the atmosphere
    n, diameter, h = 32, 4.0, 5000.0
    theta = shift_px * diameter / n / h / ARCSEC
    return SimulationConfig(
        name="noise-budget-mcao",
        telescope=TelescopeConfig(diameter=diameter, n_pixels=n),
        layers=(LayerConfig(altitude=0.0, d_over_r0=4.0, wind_speed=0.0),
                LayerConfig(altitude=h, d_over_r0=2.0, wind_speed=0.0)),
        dms=(DMConfig(altitude=0.0, n_modes=14), DMConfig(altitude=h, n_modes=9)),
        wfss=(WFSConfig(altitude=0.0, field_of_view=30.0, n_subapertures=6, noise=alpha,
                        dm=0),
              WFSConfig(altitude=h, field_of_view=20.0, n_subapertures=6, noise=alpha,
                        dm=1)),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=1e-3, gain=0.4),
        field=FieldConfig(size=2.0 * theta, n_points=3), wavelength=630e-9,
        r0_wavelength=500e-9)


def _direction_gram(model, direction):
    """Piston-removed inner products over the pupil of every DM's modes seen along ``direction``."""
    g = model.geometry
    cols = []
    for dm in model.dms:
        plane = g.planes[dm.plane]
        shift = plane.altitude * np.asarray(direction) * ARCSEC / g.dx   # (x, y) pixels
        off = plane.centre - (g.n_pixels - 1) / 2.0 + shift
        o = np.rint(off).astype(int)
        np.testing.assert_allclose(off, o, atol=1e-9)   # whole-pixel reads only
        maps = np.zeros((dm.shapes.shape[1], plane.n * plane.n))
        maps[:, dm.pixels] = dm.shapes.T
        maps = maps.reshape(-1, plane.n, plane.n)
        cols.append(maps[:, o[1]:o[1] + g.n_pixels, o[0]:o[0] + g.n_pixels][:, g.pupil_mask])
    pup = np.concatenate(cols, axis=0)
    pup = pup - pup.mean(axis=1, keepdims=True)
    return pup @ pup.T / pup.shape[1]


def test_noise_term_of_the_joint_reconstructor_in_every_direction(monkeypatch):
    monkeypatch.setattr(budget_module, "_N_NOISE_DRAWS", N_DRAWS)
    alpha = 0.02
    cfg = _mcao_noise_config(alpha, shift_px=8)
    model = LoopModel(cfg)
    r = model.reconstructor
    assert r is not None and r.shape[1] == sum(w.n_measurements for w in model.wfss)
    sigma = 2.0 * math.pi * alpha * ARCSEC / cfg.r0_wavelength
    # each slope's noise variance sigma^2 / its field share (a WFS at altitude co-adds
    # fewer directions' light on its metapupil's ring; issue 27, left28-field)
    share = np.concatenate([w.field_share for w in model.wfss])
    cov = _ntf_closed_form(cfg.loop.gain) * ((r * (sigma ** 2 / share)[None, :]) @ r.T)
    to_science = (cfg.r0_wavelength / cfg.wavelength) ** 2
    result = simulate(cfg, 0.01, seed=2, progress=False, model=model, budget_every=2)
    b = result.budget
    expected, rel_se = [], []
    for d in b.directions:
        gc = _direction_gram(model, d) @ cov
        expected.append(float(np.trace(gc)) * to_science)
        rel_se.append(math.sqrt(2.0 * np.trace(gc @ gc) / N_DRAWS) / float(np.trace(gc)))
    expected = np.array(expected)
    assert max(rel_se) < 0.015
    # off axis the two DMs' modes no longer overlap as on axis: the terms differ
    assert np.ptp(expected) > 0.05 * expected.mean()
    np.testing.assert_allclose(b.noise, expected, rtol=4.5 * max(rel_se))
    print("noise term / expected per direction:", np.round(b.noise / expected, 4))
