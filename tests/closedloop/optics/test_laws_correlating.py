"""The correlating (solar) SH against outside laws: its band, its tracker, its grid.

References (computed in the test; none is an intermediate of the sensor's code):
- the sensor's own band: the scene's rms contrast is the granulation contrast at the
  WFS wavelength (500 nm): 14.4 % at 630 nm (Danilovic et al. 2008) scaled by the Wien
  law 1 / lambda, 18.1 %; nothing a sensor measures depends on the *science*
  wavelength (a change of it must leave the noise, the contrast weights and the
  operators bit for bit the same), and its slopes' noise in the loop's units is the
  shift in pixels times ``2 pi pixel_scale / r0_wavelength`` (a phase gradient at the
  wavelength of the simulator's phase scales as 1 / lambda exactly);
- the tracker's unmodelled variance: a subaperture's unmodelled slope variance is
  ``model_error`` times the Z-tilt variance of a disc of the pitch d,
  ``16 * 0.449 (d / r0)^(5/3) / d^2`` (Noll 1976: tilt coefficient variance 0.449
  (d/r0)^(5/3) rad^2; Z2 = 2 (r / R) cos t, so the slope is 4 a2 / d), summed over the
  layers; the tracker measures the mean of ``n_valid`` Z-tilts, whose unmodelled parts
  are (nearly) independent between subapertures, so its variance is ``1 / n_valid`` of
  a slope's (the variance of a mean of n independent terms). Its noise: against a
  noise-free stored reference, the rms of SDF + 2QI shifts of 2000 images drawn here
  with Poisson photon and Gaussian read noise (no sqrt(2)). The joint reconstructor is
  recomputed here from that N by the documented MAP formula (whitened truncated SVD,
  ``closedloop/model.py``'s docstring) and must equal the model's; the same formula
  with the tracker weighted as one slope gives a measurably different reconstructor;
- the same meta-pupil and grid as the geometric SH built from the same config: pitch
  ``(D + 2 h tan(F / 2)) / n_sub`` (the layer-oriented meta-pupil), the same valid set,
  which matches the subapertures with more than half their area lit (exact area by a
  fine grid here, except within 0.1 of the half where the pixel discretisation
  decides), and the slopes of a quadratic phase ``a x^2 + b y^2``: ``(2 a x_c, 2 b y_c)``
  at the centres ``x_c = (j + 1/2) d - d_wfs / 2`` of the fully lit subapertures (the
  Z-tilt and the mean gradient of a quadratic over a square are both the gradient at
  its centre); and the slopes of a WFS conjugated to 5 km on a random phase, against
  the independent Z-tilt computation of test_correlating_sensor (its tests put the WFS
  at the pupil, where the direction of the beam's shift cannot show).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from closedloop.model import LoopModel

from ..conftest import correlating_config, correlating_sensor

ARCSEC = math.pi / 648000.0
#: Danilovic et al. (2008): rms granulation contrast 14.4 % at 630 nm; Wien: 1 / lambda
CONTRAST_630 = 0.144
WFS_WAVELENGTH = 500e-9  # the PhotonBudget's default band (table1-solar's docs: 500 nm)
NOLL_TILT = 0.449  # Noll (1976): variance of each tilt coefficient / (D/r0)^(5/3)


def _config(*, wavelength=630e-9, r0_wavelength=500e-9, kind="correlating", n_sub=4):
    noise = 0.0 if kind == "correlating" else 0.005
    sensors = [correlating_sensor(h, fov, n_sub=n_sub, field_samples=2, dm=i, kind=kind,
                                  noise=noise)
               for i, (h, fov) in enumerate(((0.0, 16.0), (5000.0, 10.0)))]
    return correlating_config("laws", [(0.0, 6.0), (5000.0, 3.0)], [(0.0, 14), (5000.0, 9)],
                              sensors, wavelength=wavelength, r0_wavelength=r0_wavelength)


@pytest.fixture(scope="module")
def model():
    return LoopModel(_config())


# ---------------------------------------------------------------- the sensor's own band
def test_scene_contrast_is_the_wfs_band_granulation(model):
    expected = CONTRAST_630 * 630e-9 / WFS_WAVELENGTH
    for w in model.wfss:
        assert w.wavelength == WFS_WAVELENGTH
    # the same sensor with the contrast set explicitly to the law's value: same noise
    cfg = _config()
    wfss = tuple(dataclasses.replace(w, contrast=expected) for w in cfg.wfss)
    explicit = LoopModel(cfg.replace(wfss=wfss))
    for a, b in zip(model.wfss, explicit.wfss, strict=True):
        np.testing.assert_allclose(a.slope_noise_pixels, b.slope_noise_pixels, rtol=1e-12)
        np.testing.assert_allclose(a.tracker_noise_pixels, b.tracker_noise_pixels, rtol=1e-12)
    # ... and the contrast of the science band (630 nm) would not give it: the test bites
    wfss = tuple(dataclasses.replace(w, contrast=CONTRAST_630) for w in cfg.wfss)
    science_band = LoopModel(cfg.replace(wfss=wfss))
    for a, b in zip(model.wfss, science_band.wfss, strict=True):
        assert b.slope_noise_pixels[0] > 1.1 * a.slope_noise_pixels[0]


@pytest.mark.parametrize("wavelength", [500e-9, 1000e-9])
def test_science_wavelength_does_not_change_the_sensor(model, wavelength):
    other = LoopModel(_config(wavelength=wavelength))
    for a, b in zip(model.wfss, other.wfss, strict=True):
        np.testing.assert_array_equal(a.noise_rms, b.noise_rms)
        np.testing.assert_array_equal(a.direction_weights, b.direction_weights)
        np.testing.assert_array_equal(a.valid_subapertures, b.valid_subapertures)
        for pa, pb in zip(a.operators, b.operators, strict=True):
            assert (pa != pb).nnz == 0
        np.testing.assert_array_equal(
            a.model_error_variance([1 / 6, 1 / 3], 0.3),
            b.model_error_variance([1 / 6, 1 / 3], 0.3))
    np.testing.assert_array_equal(model.reconstructor, other.reconstructor)


def test_noise_in_loop_units_scales_as_one_over_r0_wavelength(model):
    other = LoopModel(_config(r0_wavelength=800e-9))
    for a, b in zip(model.wfss, other.wfss, strict=True):
        np.testing.assert_array_equal(a.slope_noise_pixels, b.slope_noise_pixels)
        np.testing.assert_allclose(b.noise_rms, a.noise_rms * 500.0 / 800.0, rtol=1e-12)
        # pixels -> rad/m: a shift s px is the angle s * pixel_scale, the phase gradient
        # 2 pi s pixel_scale / r0_wavelength
        n = a.n_valid_subapertures
        to_slope = 2.0 * math.pi * a.pixel_scale * ARCSEC / 500e-9
        # a relative slope against the best-lit subaperture: variance sigma_1^2 (v(s) +
        # v(s_ref)), 2 sigma_1^2 fully lit, v = (1 - r) / s + r / s^2 (light shares s:
        # issue 27, left31-edge; test_correlating_field_rule_left29)
        s = a.field_share[:n]
        r = a.read_fraction
        v = (1.0 - r) / s + r / s ** 2
        np.testing.assert_allclose(a.noise_rms[:n], a.slope_noise_pixels[0] * to_slope
                                   * np.sqrt((v + v[np.argmax(s)]) / 2.0), rtol=1e-12)
        np.testing.assert_allclose(a.noise_rms[2 * n:], a.tracker_noise_pixels * to_slope,
                                   rtol=1e-12)


# ---------------------------------------------------------------- the tracker
def _slope_model_error(cfg, j, model_error):
    w = cfg.wfss[j]
    d = (cfg.telescope.diameter + 2.0 * w.altitude * math.tan(w.field_of_view / 2 * ARCSEC)
         ) / w.n_subapertures
    r0s = [cfg.telescope.diameter / lay.d_over_r0 for lay in cfg.layers]
    return model_error * 16.0 * NOLL_TILT * sum((d / r0) ** (5 / 3) for r0 in r0s) / d ** 2


@pytest.mark.parametrize("n_sub", [4, 6])
def test_tracker_model_error_averages_down_over_the_subapertures(n_sub):
    cfg = _config(n_sub=n_sub)
    m = LoopModel(cfg)
    r0s = [cfg.telescope.diameter / lay.d_over_r0 for lay in cfg.layers]
    for j, w in enumerate(m.wfss):
        n = w.n_valid_subapertures
        v = _slope_model_error(cfg, j, 0.3)
        got = np.asarray(w.model_error_variance(r0s, 0.3))
        assert got.shape == (2 * n + 2,)
        # a slope averaged over fewer directions: 1 / its field share (issue 27)
        share = w.field_share[:2 * n]
        np.testing.assert_allclose(got[:2 * n], v / share, rtol=1e-12)
        # the mean of n independent terms: the mean of their variances over n
        np.testing.assert_allclose(got[2 * n:], [np.mean(v / share[:n]) / n,
                                                 np.mean(v / share[n:]) / n], rtol=1e-12)


def _map_reconstructor(G, prior, noise):
    """The documented MAP reconstructor: whitened truncated SVD (closedloop/model.py)."""
    signal = np.mean(np.sum(G ** 2, axis=0) * prior) / G.shape[0]
    noise = np.maximum(noise, 1e-4 * signal)
    wh = G * np.sqrt(prior)[None, :] / np.sqrt(noise)[:, None]
    u, s, vt = np.linalg.svd(wh, full_matrices=False)
    keep = s > max(1.0, 1e-3 * s[0])
    r = (np.sqrt(prior)[:, None] * vt[keep].T) @ (u[:, keep] / s[keep]).T
    return r / np.sqrt(noise)[None, :]


def test_joint_reconstructor_weights_the_tracker_by_its_averaged_variance(model):
    cfg = model.config
    me = cfg.loop.model_error
    G = np.block([[w.interaction_with(dm) for dm in model.dms] for w in model.wfss])
    per_sub, as_one = [], []
    for j, w in enumerate(model.wfss):
        n = w.n_valid_subapertures
        v = _slope_model_error(cfg, j, me)
        base = w.noise_rms ** 2
        vs = v / w.field_share[:2 * n]           # 1 / field share (issue 27)
        per_sub.append(base + np.concatenate([vs, [vs[:n].mean() / n, vs[n:].mean() / n]]))
        as_one.append(base + v)
    expected = _map_reconstructor(G, model.prior, np.concatenate(per_sub))
    wrong = _map_reconstructor(G, model.prior, np.concatenate(as_one))
    scale = np.abs(expected).max()
    np.testing.assert_allclose(model.reconstructor, expected, atol=1e-9 * scale)
    # the test can fail: weighting the tracker as one slope changes the reconstructor
    assert np.abs(wrong - expected).max() > 0.1 * scale


# ---------------------------------------------------------------- the grid
@pytest.fixture(scope="module")
def geometric():
    return LoopModel(_config(kind="shack_hartmann"))


def test_same_meta_pupil_and_valid_set_as_the_geometric_sh(model, geometric):
    cfg = model.config
    for j, (c, s) in enumerate(zip(model.wfss, geometric.wfss, strict=True)):
        w = cfg.wfss[j]
        d_wfs = cfg.telescope.diameter + 2.0 * w.altitude * math.tan(
            w.field_of_view / 2 * ARCSEC)
        assert c.pitch == pytest.approx(d_wfs / w.n_subapertures, rel=1e-12)
        assert s.pitch == pytest.approx(d_wfs / w.n_subapertures, rel=1e-12)
        if w.altitude == 0.0:
            np.testing.assert_array_equal(c.valid_subapertures, s.valid_subapertures)
        else:
            # at altitude both use what some direction half-lights (issue 27): the
            # geometric SH on the beam's light, the correlating SH on the light its plane
            # fits use (``sqrt(2) dx`` inside the pupil's edge): a subset of it
            assert np.all(np.isin(c.valid_subapertures, s.valid_subapertures))
        # exact lit area (a fine grid), averaged over the field samples
        n_sub = w.n_subapertures
        pitch = d_wfs / n_sub
        fine = ((np.arange(80) + 0.5) / 80 - 0.5) * pitch
        fy, fx = np.meshgrid(fine, fine, indexing="ij")
        frac = np.zeros(n_sub * n_sub)
        for k in range(n_sub * n_sub):
            cx = (k % n_sub + 0.5) * pitch - d_wfs / 2
            cy = (k // n_sub + 0.5) * pitch - d_wfs / 2
            frac[k] = np.mean([np.mean(np.hypot(cx + fx - w.altitude * t[0] * ARCSEC,
                                                cy + fy - w.altitude * t[1] * ARCSEC)
                                       <= cfg.telescope.diameter / 2)
                               for t in c.samples])
        clear = np.abs(frac - 0.5) > 0.1
        assert clear.sum() >= n_sub * n_sub // 2
        valid = np.isin(np.arange(n_sub * n_sub), c.valid_subapertures)
        np.testing.assert_array_equal(valid[clear], frac[clear] > 0.5)


@pytest.mark.parametrize("a,b", [(3.0, -2.0), (-1.5, 4.0)])
def test_quadratic_phase_gives_the_gradient_at_the_same_centres(model, geometric, a, b):
    # a quadratic on the ground plane only, seen by the ground WFS (conjugated there:
    # every field direction reads the same point of it)
    g = model.geometry
    cfg = model.config
    ground = [p for p, plane in enumerate(g.planes) if plane.altitude == 0.0]
    assert len(ground) == 1
    maps = []
    for p, plane in enumerate(g.planes):
        x = g.plane_coords(p)
        yy, xx = np.meshgrid(x, x, indexing="ij")
        maps.append(a * xx ** 2 + b * yy ** 2 if p == ground[0] else np.zeros((plane.n,) * 2))
    c, s = model.wfss[0], geometric.wfss[0]
    n_sub = cfg.wfss[0].n_subapertures
    pitch = cfg.telescope.diameter / n_sub
    idx = c.valid_subapertures
    xc = (idx % n_sub + 0.5) * pitch - cfg.telescope.diameter / 2
    yc = (idx // n_sub + 0.5) * pitch - cfg.telescope.diameter / 2
    # fully lit (conjugated to the pupil: every field sample lights the same disc), with
    # two pixels to spare
    far = np.hypot(np.abs(xc) + pitch / 2, np.abs(yc) + pitch / 2)
    full = far <= cfg.telescope.diameter / 2 - 2 * g.dx
    assert full.sum() >= 4
    n = c.n_valid_subapertures
    meas = c.forward(maps)
    raw = np.concatenate([meas[:n] + meas[2 * n], meas[n:2 * n] + meas[2 * n + 1]])
    geo = s.forward(maps)
    for got in (raw, geo):
        np.testing.assert_allclose(got[:n][full], 2 * a * xc[full], rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(got[n:][full], 2 * b * yc[full], rtol=1e-6, atol=1e-9)


def test_upper_wfs_sees_its_meta_pupil_from_every_direction(model):
    # the other tests of the linear mode put the WFS at the pupil (altitude 0), where
    # every field direction lights the same footprint; a WFS conjugated to 5 km sees the
    # pupil's beam shifted by -h theta per direction: its Z-tilts against the
    # independent computation of test_correlating_sensor (scipy interpolation + lstsq
    # over each direction's lit samples) on a random phase on every plane
    from .test_correlating_sensor import _independent_ztilts

    rng = np.random.default_rng(5)
    maps = [rng.standard_normal((p.n, p.n)) for p in model.geometry.planes]
    for w in model.wfss:
        n = w.n_valid_subapertures
        s = w.forward(maps)
        raw = np.concatenate([s[:n] + s[2 * n], s[n:2 * n] + s[2 * n + 1]])
        expected = _independent_ztilts(w, maps)
        np.testing.assert_allclose(raw, expected, rtol=1e-9,
                                   atol=1e-9 * np.abs(expected).max())


def test_tracker_noise_is_the_monte_carlo_of_its_images(model):
    # the tracker correlates against a stored reference refreshed often enough to be
    # noise-free: its rms is the law's, without the slopes' sqrt(2). Reference: 2000
    # images drawn here from the noise-free reference image with the documented noise
    # (Poisson photon noise, Gaussian read noise of the photon budget), correlated
    # against that reference by SDF + 2QI; the rms of a Gaussian sample of K has a
    # relative s.e. of 1 / sqrt(2 K) = 1.6 %, allowed 4 times
    from closedloop.optics.correlating_sensor import MAX_SHIFT
    from closedloop.optics.shifts import measure_shifts

    k = 2000
    rng = np.random.default_rng(3)
    for w in model.wfss:
        tr = w.tracker
        ref = tr.reference
        ron = tr.budget.read_noise
        imgs = (rng.poisson(np.clip(ref, 0.0, None), size=(k,) + ref.shape)
                + ron * rng.standard_normal((k,) + ref.shape))
        shifts = measure_shifts(ref, imgs, method="sdf", max_shift=MAX_SHIFT).shifts
        empirical = shifts.std(axis=0)
        np.testing.assert_allclose(w.tracker_noise_pixels, empirical,
                                   rtol=4.0 / math.sqrt(2 * k))
        # the slopes (smaller images, a noisy same-frame reference) are noisier
        assert np.all(w.slope_noise_pixels > w.tracker_noise_pixels)
