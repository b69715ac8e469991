"""closedloop.model.LoopModel: the joint reconstructor's noise, floor and cut; parts; seeds.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/model.py"). References, from
outside the module under test:

- the Gauss-Markov (weighted least-squares) estimator ``(G^T N^-1 G)^-1 G^T N^-1``: when
  no whitened mode is cut, the documented reconstructor (a pseudo-inverse in the prior-
  and noise-whitened space) is exactly this, whatever the prior, so it pins ``N``;
- ``N`` written from the documentation: the configured noise ``2 pi alpha / lambda``
  [rad/m] squared, plus ``model_error`` times the Z-tilt variance of a subaperture
  ``16 * 0.449 (d / r0)^(5/3) / d^2`` summed over the layers (``d`` the meta-pupil
  ``D + 2 h tan(F / 2)`` over ``n_subapertures``), floored at 1e-4 of the mean signal
  ``mean_j(sum_i G_ij^2 C_j) / n_measurements``;
- the prior ``C`` of each DM: ``max(s_d, 1e-6 max s) * prior_variance`` with ``s_d`` the
  sum of ``(D_d / r0)^(5/3)`` over the layers nearest to DM ``d`` (the DM kind's
  ``prior_variance``, pinned against Noll's table by ``test_laws_map_prior.py``);
- the documented cut: whitened singular values ``> max(1, 1e-3 s_0)`` are kept and
  ``R G`` is then a projector of that rank;
- ``sense`` = ``reconstruct(measure(...))`` with the noise drawn from the generator given;
- each layer of ``atmosphere`` carries its config's wind ``(v cos a, v sin a)``, outer
  scale, plane altitude and the run's duration; the seed layout that every published
  number rests on (``SeedSequence(seed).spawn(n_layers + 1)``: child ``i`` for layer
  ``i``, the last for the WFS noise; tests/test_golden.py pins its bits end to end).

``G`` is the WFSs' ``interaction_with`` (closedloop.optics.wfs, pinned by the sensor laws).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from closedloop.config import (
    DMConfig,
    LayerConfig,
    LoopConfig,
)
from closedloop.model import LoopModel
from closedloop.optics.atmosphere import AtmosphericLayer

from .conftest import GAP_DIAMETER, GAP_R0_WAVELENGTH, gap_config, gap_sensor

ARCSEC = math.pi / 648000.0
D = GAP_DIAMETER
DM_ALTITUDES = (0.0, 8000.0)
LAMBDA_R0 = GAP_R0_WAVELENGTH


def _config(noises=(0.002, 0.006), fields=(60.0, 20.0), diameters=(None, None),
            layers=((0.0, 8.0), (8000.0, 4.0)), model_error=0.3, n_dms=2):
    dms = tuple(DMConfig(altitude=h, n_modes=m, diameter=d)
                for h, m, d in zip(DM_ALTITUDES, (9, 5), diameters, strict=True))[:n_dms]
    wfss = tuple(gap_sensor(h, f, n, i)
                 for i, (h, f, n) in enumerate(zip(DM_ALTITUDES, fields, noises,
                                                   strict=True)))[:n_dms]
    return gap_config("gaps", tuple((h, s, 5.0) for h, s in layers), dms, wfss, n_points=3,
                      loop=LoopConfig(model_error=model_error))


def _interaction(model):
    return np.block([[w.interaction_with(dm) for dm in model.dms] for w in model.wfss])


def _meta_pupil(h, field):
    return D + 2.0 * h * math.tan(field / 2.0 * ARCSEC)


def _prior(cfg, model):
    """``max(s_d, 1e-6 max s) * prior_variance`` per DM, written from the config."""
    diam = [cfg.dms[d].diameter or _meta_pupil(DM_ALTITUDES[d], cfg.wfss[d].field_of_view)
            for d in range(2)]
    s = [0.0, 0.0]
    for lay in cfg.layers:
        d = int(np.argmin([abs(lay.altitude - a) for a in DM_ALTITUDES]))  # zenith
        s[d] += (diam[d] / (D / lay.d_over_r0)) ** (5.0 / 3.0)
    return np.concatenate([max(s[d], 1e-6 * max(s)) * model.dms[d].prior_variance()
                           for d in range(2)])


def _noise(cfg, model, g, prior):
    """Per-measurement noise variance N [(rad/m)^2] from the config and the docstrings."""
    r0s = [D / lay.d_over_r0 for lay in cfg.layers]
    out = []
    for j, w in enumerate(cfg.wfss):
        slope = 2.0 * math.pi * w.noise * ARCSEC / LAMBDA_R0
        d = _meta_pupil(w.altitude, w.field_of_view) / w.n_subapertures
        error = cfg.loop.model_error * 16.0 * 0.449 * sum((d / r0) ** (5.0 / 3.0)
                                                          for r0 in r0s) / d ** 2
        # a layer-oriented WFS weighs each measurement by its share of the field's light:
        # photon noise and unmodelled signal both as 1 / share (issue 27, left28-field)
        share = model.wfss[j].field_share
        out.append(np.full(model.wfss[j].n_measurements, slope ** 2 + error) / share)
    noise = np.concatenate(out)
    signal = np.mean(np.sum(g ** 2, axis=0) * prior) / g.shape[0]
    return np.maximum(noise, 1e-4 * signal)


def _gauss_markov(g, noise):
    gn = g.T / noise[None, :]
    return np.linalg.solve(gn @ g, gn)


def test_reconstructor_weighs_each_sensor_by_its_configured_noise():
    # unequal noise on the two WFSs (0.002" and 0.006") and a model error of 0.01 (the
    # two terms of N of the same order): high enough SNR that nothing is cut, so R is
    # the Gauss-Markov estimator for N
    cfg = _config(model_error=0.01)
    model = LoopModel(cfg)
    g = _interaction(model)
    noise = _noise(cfg, model, g, _prior(cfg, model))
    assert model.n_controlled == model.n_modes == 14
    np.testing.assert_allclose(model.reconstructor, _gauss_markov(g, noise),
                               rtol=1e-7, atol=1e-9 * np.abs(model.reconstructor).max())
    # the weights matter here: equal weights give another estimator
    equal = _gauss_markov(g, np.ones_like(noise))
    assert np.abs(equal - model.reconstructor).max() > 1e-3 * np.abs(equal).max()


def test_a_noise_free_sensor_gets_the_floor_of_the_mean_signal():
    # WFS 1 noise-free, no model error: its variance is the floor, 1e-4 of the mean
    # signal; WFS 0's noise (2.1e-4") is of the same order, so the floor sets the weights
    cfg = _config(noises=(2.1e-4, 0.0), model_error=0.0)
    model = LoopModel(cfg)
    g = _interaction(model)
    prior = _prior(cfg, model)
    noise = _noise(cfg, model, g, prior)
    floor = noise[-1]
    assert 0.5 < noise[0] / floor < 2.0
    assert model.n_controlled == model.n_modes
    np.testing.assert_allclose(model.prior, prior, rtol=1e-12)
    np.testing.assert_allclose(model.reconstructor, _gauss_markov(g, noise),
                               rtol=1e-7, atol=1e-9 * np.abs(model.reconstructor).max())


# weak layers on purpose (s_0 < 1: a total r0 of 7.5 m, warned as implausible)
@pytest.mark.filterwarnings("ignore:`total r0 .* is beyond 1 m at 500 nm:UserWarning")
def test_a_dm_without_layers_gets_the_prior_floor():
    # every layer nearest the ground DM, weak (s_0 < 1, so the floor is 1e-6 s_0, not
    # 1e-6): the 8-km DM's prior is 1e-6 of the ground DM's strength
    cfg = _config(layers=((0.0, 0.4), (2000.0, 0.3)))
    model = LoopModel(cfg)
    prior = _prior(cfg, model)
    s0 = sum((_meta_pupil(0.0, 60.0) / (D / x)) ** (5.0 / 3.0) for x in (0.4, 0.3))
    assert s0 < 1.0
    np.testing.assert_allclose(model.prior[model.mode_slices[1]],
                               1e-6 * s0 * model.dms[1].prior_variance(), rtol=1e-12)
    np.testing.assert_allclose(model.prior, prior, rtol=1e-12)


def test_the_cut_is_snr_one_or_1e_3_of_the_largest_whichever_is_higher():
    # both DMs 6 m across, both fields 20": the DMs' modes nearly degenerate; WFS 0 at the
    # noise floor (s_0 > 1000), WFS 1 noisy (0.004"; 0.0013" before its ring was weighted
    # by field share, issue 27; 0.005" before the share counted the lit area, left31-edge:
    # 0.003-0.0045" hold the setup): some whitened singular values sit between 1 and
    # 1e-3 s_0, and the documented cut drops them
    cfg = _config(noises=(0.0, 0.004), fields=(20.0, 20.0), diameters=(6.0, 6.0),
                  model_error=0.0)
    model = LoopModel(cfg)
    g = _interaction(model)
    prior = _prior(cfg, model)
    noise = _noise(cfg, model, g, prior)
    white = g * np.sqrt(prior)[None, :] / np.sqrt(noise)[:, None]
    u, sv, vt = np.linalg.svd(white, full_matrices=False)
    cut = max(1.0, 1e-3 * sv[0])
    assert cut > 2.0
    assert np.sum((sv > 1.0) & (sv <= cut)) >= 2  # the relative cut matters here
    assert np.all(np.abs(sv / cut - 1.0) > 0.05)  # and no value sits on it
    keep = sv > cut
    assert model.n_controlled == keep.sum() < model.n_modes
    expected = (np.sqrt(prior)[:, None] * vt[keep].T) @ (u[:, keep] / sv[keep]).T
    expected /= np.sqrt(noise)[None, :]
    np.testing.assert_allclose(model.reconstructor, expected, rtol=1e-6,
                               atol=1e-9 * np.abs(expected).max())
    rg = model.controlled_projector
    np.testing.assert_allclose(rg @ rg, rg, atol=1e-8)
    assert np.trace(rg) == pytest.approx(keep.sum(), abs=1e-8)


def test_one_dm_has_no_prior_and_a_bad_config_is_named():
    model = LoopModel(_config(n_dms=1, layers=((0.0, 8.0),)))
    assert model.prior is None and model.reconstructor is None
    with pytest.raises(TypeError) as err:
        LoopModel({"name": "x"})
    assert str(err.value) == "`config` must be a SimulationConfig; got dict."


def test_reconstruct_refuses_measurements_of_fewer_sensors():
    model = LoopModel(_config(n_dms=1, layers=((0.0, 8.0),)))  # one reconstructor per WFS
    with pytest.raises(ValueError):
        model.reconstruct([])


def test_sense_draws_the_noise_from_the_generator_given():
    model = LoopModel(_config(n_dms=1, noises=(0.05, 0.0), layers=((0.0, 8.0),)))
    maps = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
    noisy = model.sense(maps, np.random.default_rng(3))
    expected = model.reconstruct(model.measure(maps, np.random.default_rng(3)))
    np.testing.assert_array_equal(noisy, expected)
    assert np.abs(noisy).max() > 0.0
    np.testing.assert_array_equal(model.sense(maps, None), np.zeros(model.n_modes))


def test_atmosphere_layers_carry_the_configs_wind_outer_scale_and_duration():
    layers = (LayerConfig(altitude=0.0, d_over_r0=8.0, wind_speed=6.0, wind_direction=60.0,
                          outer_scale=25.0),
              LayerConfig(altitude=8000.0, d_over_r0=4.0, wind_speed=10.0,
                          wind_direction=-120.0))
    model = LoopModel(_config().replace(layers=layers))
    atm = model.atmosphere(seed=5, duration=0.25)
    g = model.geometry
    for i, (lay, cfg) in enumerate(zip(atm.layers, layers, strict=True)):
        a = math.radians(cfg.wind_direction)
        assert lay.velocity == pytest.approx((cfg.wind_speed * math.cos(a),
                                              cfg.wind_speed * math.sin(a)), rel=1e-12)
        assert lay.outer_scale == cfg.outer_scale
        assert lay.r0 == pytest.approx(D / cfg.d_over_r0, rel=1e-12)
        assert lay.altitude == g.planes[g.layer_plane[i]].altitude == cfg.altitude
        assert lay.n_pixels == g.planes[g.layer_plane[i]].n
        assert lay.duration_hint == 0.25


def test_seed_layout_one_child_per_layer_and_the_last_for_the_noise():
    model = LoopModel(_config())
    n = len(model.config.layers)
    children = np.random.SeedSequence(11).spawn(n + 1)
    atm = model.atmosphere(seed=11, duration=0.1)
    for i, lay in enumerate(atm.layers):
        again = AtmosphericLayer(
            n_pixels=lay.n_pixels, pixel_scale=lay.pixel_scale, r0=lay.r0,
            velocity=lay.velocity, outer_scale=lay.outer_scale, altitude=lay.altitude,
            duration_hint=0.1, seed=np.random.default_rng(children[i]))
        np.testing.assert_array_equal(lay.screen, again.screen)
    draws = model.noise_rng(11).standard_normal(8)
    np.testing.assert_array_equal(draws,
                                  np.random.default_rng(children[n]).standard_normal(8))
    # the noise is none of the layers' streams
    for i in range(n):
        assert not np.array_equal(draws, np.random.default_rng(children[i]).standard_normal(8))
