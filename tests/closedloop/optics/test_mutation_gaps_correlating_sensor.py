"""closedloop.optics.correlating_sensor: the imaging mode, the AOT record, the estimate.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/optics/correlating_sensor.py").
References, from outside the module under test:

- the field geometry: a plane at altitude ``h`` seen from direction ``theta`` by a WFS
  conjugated to ``h_w`` is sampled at ``x + (h - h_w) theta`` (the layer-oriented
  footprint); a bilinear interpolation reproduces a linear map exactly, so the imaging
  mode's phase operators applied to the coordinate map ``X(x, y) = x`` of a plane must
  give each lit sample's ``x + (h - h_w) theta_x`` (and likewise for y);
- the phase's units: the planes hold phase in rad at ``r0_wavelength`` and the sensor
  images at its own band (500 nm), so a phase ``a x^2 + b y^2`` (split over two planes,
  which add along the line of sight) gives, in the loop's units [rad/m at
  ``r0_wavelength``], the slopes ``(2 a x_c, 2 b y_c)`` less their mean at the
  subaperture centres ``x_c`` (a quadratic's Z-tilt over a square is its gradient at the
  centre), whatever ``r0_wavelength`` (checked at 1 um, where the phase at 500 nm is
  twice the plane's); within the SDF + 2QI interpolation bias of two images (0.08 px,
  test_correlating_sensor's bound);
- the reference subaperture as the module docstring defines it: "the fully lit
  subaperture nearest the centre", fully lit computed here from the pupil geometry
  (every sample of every sub-direction's beam at least ``sqrt(2) dx`` inside the
  pupil's edges);
- "a run is reproducible from its seed": the same normal draws give the same images'
  noise, bit for bit, and other draws other noise;
- the AOT record as ``closedloop/aot.py``'s docstring defines it: a Shack-Hartmann
  record whose last entry per axis is the correlation tracker (one entry per axis more
  than the valid subapertures), ``MI_GEOM`` naming the kind, its pixel scale and mode;
- the resource estimate's sampling (``_sampling``: "as CorrelatingShackHartmann sets
  them, without building anything") against the built sensor's pupil samples, image
  formation support, PSF samples and patches, over modes, field samples, pixel scales
  and a 2-pixel pitch; its counts from their definitions: a disc of ``n`` subapertures
  across holds ``pi n^2 / 4`` (two slopes each and the tracker's two), 6 entries per
  pupil sample and plane (2 fit weights, 4 bilinear reads), 4 per sample, plane and
  sub-direction for the imaging mode (equal to the built imaging operators' stored
  entries scaled from ``n_valid`` to ``pi n^2 / 4``), and the imaging time
  ``_SECONDS_PER_IMAGE_OP x images x support^2 x PSF samples`` (its documented model);
- the detector's noise law: each pixel's variance is its mean plus the read noise's square
  (Poisson photon noise plus independent Gaussian read noise, as
  test_correlating.py::test_read_noise_dominated_detector_variance checks on the images);
  a shift estimate's variance is the pixel variance over the squared image gradient
  (Michau et al. 1992), so on one scene scaled to ``m`` e- per pixel it goes as
  ``(m + RON^2) / m^2`` (``RON`` = :class:`PhotonBudget`'s documented 2 e-);
- the least-squares plane fit of a linear phase ``a x + b y`` is ``(a, b)`` exactly, on
  any lit part of a subaperture, so a contrast-weighted mean of the sub-directions' fits
  (weights renormalised over the directions kept, module docstring) is ``(a, b)`` too;
- a sub-direction lighting less than half of a subaperture is left out of its mean
  (module docstring): test_correlating_sensor.py's independent lstsq Z-tilts, on a 3-km
  WFS where four valid subapertures see such a sliver (6-15 % lit) from one direction;
- the project's rule for bad input: the message names the argument, the rule, the value
  (here also: fewer than 2 valid subapertures, from the annulus's area per subaperture).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import sparse

from closedloop.config import (
    ARCSEC,
    DMConfig,
    SimulationConfig,
    TelescopeConfig,
)
from closedloop.kinds import sensor_kind
from closedloop.model import LoopModel
from closedloop.optics import correlating_sensor
from closedloop.optics.photon_budget import PhotonBudget

from ..conftest import correlating_config
from ..conftest import correlating_sensor as sensor_config
from .test_correlating_sensor import _independent_ztilts


def _config(*, wfs_altitude=0.0, field_samples=1, image_formation=True, r0_wavelength=1e-6,
            n_pixels=32, obscuration=0.0, n_sub=4, fov=16.0, diameter=1.0):
    # two planes (the ground and 3 km: the layers', the DM on the WFS's) so that the
    # phase is a sum
    sensor = sensor_config(wfs_altitude, fov, n_sub=n_sub, field_samples=field_samples,
                           image_formation=image_formation, contrast=0.04)
    return correlating_config("test", [(0.0, 3.0), (3000.0, 3.0)], [(wfs_altitude, 20)],
                              [sensor], diameter=diameter, n_pixels=n_pixels,
                              obscuration=obscuration, r0_wavelength=r0_wavelength)


@pytest.fixture(scope="module")
def on_axis():
    model = LoopModel(_config())
    return model, model.wfss[0]


def _centres(w, n_sub: int, d_wfs: float) -> np.ndarray:
    """``(n_valid, 2)`` subaperture centres ``((j + 1/2) d - d_wfs / 2, (i + 1/2) d - ...)``."""
    d = d_wfs / n_sub
    sub = w.valid_subapertures
    return np.column_stack([(sub % n_sub + 0.5) * d - d_wfs / 2.0,
                            (sub // n_sub + 0.5) * d - d_wfs / 2.0])


def test_image_slopes_are_refused_in_the_linear_mode():
    w = LoopModel(_config(image_formation=False)).wfss[0]
    maps = [np.zeros((p.n, p.n)) for p in w._geometry.planes]
    with pytest.raises(ValueError) as exc:
        w.image_slopes(maps)
    assert str(exc.value) == ("`wfss[0].image_formation` must be true to form images; "
                              "got false.")


@pytest.mark.parametrize("wfs_altitude", [0.0, 3000.0])
def test_image_phase_is_each_plane_at_x_plus_h_theta(wfs_altitude):
    # a wide field (5 x 5 sub-directions of 2.4" across 16") and a WFS on the ground or at
    # 3 km: every plane is sampled along every sub-direction's line of sight
    model = LoopModel(_config(wfs_altitude=wfs_altitude, field_samples=3))
    w = model.wfss[0]
    g = model.geometry
    dirs = w.imager.directions_arcsec
    assert len(dirs) > 1 and np.abs(dirs).max() > 1.0
    n_valid, f = w.n_valid_subapertures, w.n_pupil
    d_wfs = 1.0 + 2.0 * wfs_altitude * math.tan(8.0 * ARCSEC)
    centres = _centres(w, 4, d_wfs)
    off = ((np.arange(f) + 0.5) / f - 0.5) * d_wfs / 4
    yy, xx = np.meshgrid(off, off, indexing="ij")
    x = centres[:, 0, None] + xx.ravel()[None]         # (n_valid, F): rows along y
    y = centres[:, 1, None] + yy.ravel()[None]
    lit = w._amplitude.reshape(len(dirs), n_valid, f * f) > 0
    assert lit.any(axis=(1, 2)).all()
    for p, plane in enumerate(g.planes):
        co = g.plane_coords(p)
        cx, cy = np.meshgrid(co, co, indexing="xy")
        for coord, axis, xy in ((cx, 0, x), (cy, 1, y)):
            got = (w._image_ops[p] @ coord.ravel()).reshape(len(dirs), n_valid, f * f)
            for t, theta in enumerate(dirs):
                want = xy + (plane.altitude - wfs_altitude) * theta[axis] * ARCSEC
                np.testing.assert_allclose(got[t][lit[t]], want[lit[t]], rtol=0,
                                           atol=1e-9, err_msg=f"plane {p}, dir {theta}")


def test_imaged_quadratic_phase_gives_its_gradient_in_loop_units(on_axis):
    model, w = on_axis
    g = model.geometry
    n = w.n_valid_subapertures
    full = np.flatnonzero(w._amplitude.min(axis=(0, 2, 3)) > 0)
    assert full.size >= 4
    # a [rad/m^2] on the ground plane, b on the 3-km one (seen on axis: no shift); the
    # sum is a x^2 + b y^2 along the line of sight: slopes (2 a x_c, 2 b y_c)
    a, b = 40.0, -30.0
    maps = []
    for p, (ca, cb) in enumerate(((a, 0.0), (0.0, b))):
        co = g.plane_coords(p)
        cx, cy = np.meshgrid(co, co, indexing="xy")
        maps.append(ca * cx ** 2 + cb * cy ** 2)
    centres = _centres(w, 4, 1.0)
    want = np.concatenate([2 * a * centres[:, 0], 2 * b * centres[:, 1]])
    for k in range(2):          # less the mean over the valid subapertures, per axis
        want[k * n:(k + 1) * n] -= want[k * n:(k + 1) * n].mean()
    to_px = 1.0 / (2.0 * math.pi * w.pixel_scale * ARCSEC / 1e-6)    # rad/m -> pixels
    got = w.image_slopes(maps)
    sel = np.concatenate([full, full + n])
    assert np.abs(want[sel]).max() * to_px > 0.5        # shifts of half a pixel or more
    err = np.abs(got - want)[sel].max() * to_px
    assert err < 0.08, err


def test_imaging_noise_is_reproducible_from_the_draws(on_axis):
    model, w = on_axis
    maps = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
    draws = np.random.default_rng(5).standard_normal(w.n_measurements)
    one = w.image_slopes(maps, draws)
    np.testing.assert_array_equal(w.image_slopes(maps, draws.copy()), one)
    other = w.image_slopes(maps, np.random.default_rng(6).standard_normal(w.n_measurements))
    assert np.abs(other - one).max() > 0.1 * w.noise_rms[0]


def test_reference_is_the_fully_lit_subaperture_nearest_the_centre():
    # an obscured pupil (20 %), 8 x 8 on 48 pixels: the subapertures nearest the centre
    # are vignetted by the obscuration, so the reference lies on the next ring, where
    # the fully lit one with the smallest |y| is farther out (0.319 m against 0.265 m)
    n_sub, obsc = 8, 0.2
    model = LoopModel(_config(n_sub=n_sub, obscuration=obsc, field_samples=2, n_pixels=48))
    w = model.wfss[0]
    dx = model.geometry.dx
    f = w.n_pupil
    centres = _centres(w, n_sub, 1.0)
    off = ((np.arange(f) + 0.5) / f - 0.5) / n_sub
    yy, xx = np.meshgrid(off, off, indexing="ij")
    edge = math.sqrt(2.0) * dx
    # a ground WFS: every sub-direction's beam lights the same samples (no footprint shift)
    r = np.hypot(centres[:, 0, None] + xx.ravel(), centres[:, 1, None] + yy.ravel())
    full = ((r <= 0.5 - edge) & (r >= obsc * 0.5 + edge)).all(axis=1)
    dist = np.hypot(centres[:, 0], centres[:, 1])
    assert full.any() and not full[np.argmin(dist)]      # the nearest is vignetted
    ref = w.reference_subaperture
    assert full[ref]
    # (which of the ring's equidistant subapertures is taken is float rounding's choice)
    assert dist[ref] == pytest.approx(dist[full].min(), rel=1e-12)


def test_aot_record_is_a_shack_hartmann_with_the_tracker_last(on_axis):
    model, w = on_axis
    wcfg = model.config.wfss[0]
    n = w.n_valid_subapertures
    meas = np.arange(3.0 * w.n_measurements).reshape(3, w.n_measurements)
    kind = sensor_kind("correlating")
    layout = kind.aot_layout(w, meas)
    # (x..., y..., tracker x, tracker y) -> (T, 2, n + 1), the tracker last on each axis
    assert layout.shape == (3, 2, n + 1)
    np.testing.assert_array_equal(layout[:, 0, :n], meas[:, :n])
    np.testing.assert_array_equal(layout[:, 1, :n], meas[:, n:2 * n])
    np.testing.assert_array_equal(layout[:, :, n], meas[:, 2 * n:])
    spec = kind.aot_record(model, 0, wcfg, layout)
    assert spec.kind == "shack-hartmann" and spec.n_valid_subapertures == n + 1
    assert spec.extra["kind"] == "correlating"
    assert spec.extra["pixel_scale"] == 0.5 and spec.extra["image_formation"] is True
    assert spec.extra["note"] == (
        "correlating SH on granulation: Z-tilts less their mean; the last entry of each "
        "axis is the correlation tracker's global tilt (no subaperture in the mask)")
    # the geometric SH's entries are kept beside the kind's own
    assert spec.extra["n_subapertures"] == 4 and spec.extra["drives"] == "dm0"


@pytest.mark.parametrize("changes,pixel_scale", [
    (dict(image_formation=False, field_samples=3), 0.5),     # linear: one patch
    (dict(field_samples=3), 0.5),                    # 5 x 5 patches
    (dict(field_samples=5), 0.5),                    # 9 capped at 32 px // 4 = 8
    (dict(n_sub=16, image_formation=False), 0.5),    # a 2-pixel pitch
    (dict(field_samples=2), 0.3),
])
def test_estimate_sampling_is_the_built_sensors(changes, pixel_scale):
    cfg = _config(**changes)
    cfg = cfg.replace(wfss=(dataclasses.replace(cfg.wfss[0], pixel_scale=pixel_scale),))
    model = LoopModel(cfg)
    w = model.wfss[0]
    im = w.imager
    got = correlating_sensor._sampling(cfg, 0, model.geometry.dx)
    assert got == (w.n_pupil, im.support, im.psf_pixels * im.psf_subsampling, im.n_patches)
    assert len(im.directions_arcsec) == im.n_patches ** 2


@pytest.mark.parametrize("changes", [dict(field_samples=2),
                                     dict(image_formation=False, n_sub=8, n_pixels=48)])
def test_estimate_counts_are_their_definitions(changes):
    cfg = _config(**changes)
    model = LoopModel(cfg)
    w, g = model.wfss[0], model.geometry
    n_planes, f = len(g.planes), w.n_pupil
    cost = correlating_sensor._cost(cfg, 0, n_planes, g.dx)
    n = cfg.wfss[0].n_subapertures
    disc = math.pi / 4.0 * n ** 2
    assert disc == pytest.approx(w.n_valid_subapertures, rel=0.15)
    assert cost.n_measurements == pytest.approx(2.0 * disc + 2.0, rel=1e-12)
    base = n_planes * disc * f * f * 6
    if not cfg.wfss[0].image_formation:
        assert cost.build_entries == pytest.approx(base, rel=1e-12)
        assert cost.frame_seconds == 0.0
        return
    stored = sum(op.nnz for op in w._image_ops)
    assert stored == w.imager.n_patches ** 2 * n_planes * w.n_valid_subapertures * f * f * 4
    assert cost.build_entries == pytest.approx(base + stored * disc / w.n_valid_subapertures,
                                               rel=1e-12)
    im = w.imager
    images = disc * im.n_patches ** 2
    assert cost.frame_seconds == pytest.approx(
        correlating_sensor._SECONDS_PER_IMAGE_OP * images * im.support ** 2
        * im.psf_pixels * im.psf_subsampling, rel=1e-12)
    assert cost.frame_key == "wfss[0].image_formation"


@pytest.mark.parametrize("image_formation", [False, True])
def test_forward_adds_the_draws_scaled_by_the_noise_rms(image_formation, on_axis):
    # the documented contract: the linear mode adds noise_rms x draws to every
    # measurement at a whole-pixel shift (zero maps), scaled at a sub-pixel shift by the
    # measured excess (>= ~1; left29-sdf: test_shift_noise_left29 checks it against the
    # measurement), linear in the draws; the imaging mode seeds its images' noise with
    # the draws and adds noise_rms x draws to the two tracker rows only
    if image_formation:
        model, w = on_axis
    else:
        model = LoopModel(_config(image_formation=False))
        w = model.wfss[0]
    rng = np.random.default_rng(9)
    maps = [rng.standard_normal((p.n, p.n)) for p in model.geometry.planes]
    draws = rng.standard_normal(w.n_measurements)
    n = w.n_valid_subapertures
    clean = w.forward(maps)
    noisy = w.forward(maps, draws)
    assert np.all(w.noise_rms > 0)
    if not image_formation:
        zero = [np.zeros_like(m) for m in maps]
        np.testing.assert_allclose(w.forward(zero, draws), w.noise_rms * draws, rtol=0.05)
        np.testing.assert_allclose(w.forward(maps, 2.0 * draws) - clean, 2.0 * (noisy - clean),
                                   rtol=1e-9)
        gain = (noisy - clean) / (w.noise_rms * draws)
        assert gain.min() > 0.95 and gain.max() < 4.0, gain
        return
    np.testing.assert_array_equal(noisy[:2 * n], w.image_slopes(maps, draws))
    assert np.abs(noisy[:2 * n] - clean[:2 * n]).max() > 0
    np.testing.assert_allclose(noisy[2 * n:], clean[2 * n:] + w.noise_rms[2 * n:] * draws[2 * n:],
                               rtol=0, atol=1e-12 * np.abs(noisy).max())


def test_tracker_sees_the_configured_signal():
    # "the tracker: its own image ... at the same pixel scale and signal" (module
    # docstring): its pixels hold the configured signal, and its photon-noise-limited
    # shift error falls as 1 / sqrt(signal) (Michau et al. 1992): 2x from 1000 to 4000 e-
    noise = {}
    for signal in (1000.0, 4000.0):
        cfg = _config(image_formation=False)
        cfg = cfg.replace(wfss=(dataclasses.replace(cfg.wfss[0], signal=signal),))
        w = LoopModel(cfg).wfss[0]
        assert w.tracker.electrons_per_pixel == pytest.approx(signal, rel=1e-9)
        assert w.imager.electrons_per_pixel == pytest.approx(signal, rel=1e-9)
        noise[signal] = w.tracker_noise_pixels
    np.testing.assert_allclose(noise[1000.0] / noise[4000.0], 2.0, rtol=0.05)


def test_read_noise_dominated_slope_and_tracker_noise():
    # at 1000 e- per pixel the read noise's 4 e-^2 is 0.4 % of the photon variance, below
    # every other test's tolerance; at 2 e- it is twice the photon variance, so the noise
    # laws of the slopes and of the tracker must grow from 1000 e- to 2 e- by the
    # detector's (m + RON^2) / m^2 (Poisson plus read noise): 1.5e3 x. RON^3 (8 e-^2)
    # would make it 2.5e3 x; a subtracted RON^2 a negative pixel variance (refused); a
    # 10 % wrong RON^2 moves it by 6.7 %. The scene's contrast (4 %) makes the
    # gradient-weighted mean of the pixels differ from m by < 0.5 %.
    ron2 = PhotonBudget().read_noise ** 2
    var = {}
    for signal in (1000.0, 2.0):
        cfg = _config(image_formation=False)
        cfg = cfg.replace(wfss=(dataclasses.replace(cfg.wfss[0], signal=signal),))
        w = LoopModel(cfg).wfss[0]
        var[signal] = (w.slope_noise_pixels ** 2, w.tracker_noise_pixels ** 2)
    law = ((2.0 + ron2) / 2.0 ** 2) / ((1000.0 + ron2) / 1000.0 ** 2)
    np.testing.assert_allclose(var[2.0][0] / var[1000.0][0], law, rtol=0.02)
    np.testing.assert_allclose(var[2.0][1] / var[1000.0][1], law, rtol=0.02)


@pytest.mark.parametrize("n_sub, obsc, share", [(4, 0.2, 0.95), (4, 0.3, 0.95), (6, 0.3, 0.99)])
def test_reference_is_the_best_lit_subaperture_where_none_is_lit_whole(n_sub, obsc, share):
    # a 1 m pupil on 32 pixels: no subaperture is lit whole (pixel edges) at these
    # obscurations; the reference was subaperture 0, a corner (67 % lit at 6 x 6). The
    # reference: each subaperture's lit share of its square, by a 200 x 200 sampling of
    # the annulus 0.5 obsc <= r <= 0.5 m (geometry, not the sensor's 8-pixel masks, hence
    # 5 % at 4 x 4, where the pixel masks rank the inner ring 0.874 first; at 6 x 6 the
    # best are lit whole and subaperture 0 is 0.944: the previous choice fails). At 4 x 4
    # with 30 % no subaperture is lit whole either, and the valid one nearest the centre
    # is 0.785 of the best: a reference by distance alone, without the lit share, fails
    # (_build_imaging__mutmut_56, _57)
    w = LoopModel(_config(n_sub=n_sub, obscuration=obsc)).wfss[0]
    centres = _centres(w, n_sub, 1.0)
    off = ((np.arange(200) + 0.5) / 200 - 0.5) / n_sub
    yy, xx = np.meshgrid(off, off, indexing="ij")
    r = np.hypot(centres[:, 0, None] + xx.ravel(), centres[:, 1, None] + yy.ravel())
    lit = ((r <= 0.5) & (r >= 0.5 * obsc)).mean(axis=1)
    assert lit[w.reference_subaperture] >= share * lit.max()


@pytest.mark.parametrize("wfs_altitude", [0.0, 3000.0])
def test_lit_samples_are_the_annulus_seen_from_each_direction(wfs_altitude):
    # a 2 m pupil (a slip between obscuration x D / 2 and obscuration / D / 2 shows only
    # where D != 1), 30 % obscured: a sample u of the WFS's plane is lit from theta when
    # its beam crosses the pupil at u - h_w theta at least sqrt(2) dx inside both edges
    # (module docstring); samples within 1e-9 m of an edge are left out (rounding's)
    d, obsc, n_sub = 2.0, 0.3, 6
    model = LoopModel(_config(diameter=d, obscuration=obsc, n_sub=n_sub,
                              wfs_altitude=wfs_altitude, field_samples=2))
    w = model.wfss[0]
    dx = model.geometry.dx
    assert dx == d / 32
    d_wfs = d + 2.0 * wfs_altitude * math.tan(8.0 * ARCSEC)
    f = w.n_pupil
    centres = _centres(w, n_sub, d_wfs)
    off = ((np.arange(f) + 0.5) / f - 0.5) * (d_wfs / n_sub)
    yy, xx = np.meshgrid(off, off, indexing="ij")
    edge = math.sqrt(2.0) * dx
    outer, inner = d / 2.0 - edge, obsc * d / 2.0 + edge
    # the contrast weights of the field samples: a column per axis, summing to 1
    # (the class docstring; the operators renormalise them, so only this shows a slip)
    assert w.direction_weights.shape == (len(w.samples), 2)
    assert np.all(w.direction_weights > 0)
    np.testing.assert_allclose(w.direction_weights.sum(axis=0), 1.0, rtol=1e-12)
    dirs = w.imager.directions_arcsec
    assert len(dirs) == 9
    amp = w._amplitude.reshape(len(dirs), w.n_valid_subapertures, f * f)
    for t, theta in enumerate(dirs):
        r = np.hypot(centres[:, 0, None] + xx.ravel() - wfs_altitude * theta[0] * ARCSEC,
                     centres[:, 1, None] + yy.ravel() - wfs_altitude * theta[1] * ARCSEC)
        lit = (r <= outer) & (r >= inner)
        clear = (np.abs(r - outer) > 1e-9) & (np.abs(r - inner) > 1e-9)
        assert lit.any() and (~lit).any()
        np.testing.assert_array_equal((amp[t] > 0)[clear], lit[clear], err_msg=str(theta))


def test_linear_phase_gives_its_gradient_where_a_direction_is_left_out():
    # a 3-km WFS over 16" with 2 x 2 field samples and a 30 %-obscured pupil: at the
    # obscuration's edge some valid subapertures are lit by less than half from one
    # direction, which is left out of their mean and the others' weights renormalised.
    # A linear phase's Z-tilt is its gradient from every direction, so every valid
    # subaperture's raw Z-tilt must be (a, b): without the renormalisation those
    # subapertures read (a, b) times the kept directions' weight sum (< 1).
    a, b = 0.7, -0.2
    model = LoopModel(_config(wfs_altitude=3000.0, field_samples=2, n_sub=6,
                              obscuration=0.3, image_formation=False))
    w = model.wfss[0]
    # the case under test exists (a direction dropped for some subapertures, not all)
    usable = np.array([w._plane_fit_rows(w._lit(w._points, th), w._lit(w._points, th, 0.0))[2]
                       for th in w.samples])
    assert (usable.any(axis=0) & ~usable.all(axis=0)).sum() >= 1
    n = w.n_valid_subapertures
    for p, plane in enumerate(model.geometry.planes):
        x = (np.arange(plane.n) - (plane.n - 1) / 2.0) * model.geometry.dx
        xx, yy = np.meshgrid(x, x, indexing="xy")
        # the linear phase on one plane at a time (the other plane flat)
        ztilt = w.operators[p] @ (a * xx + b * yy).ravel()
        np.testing.assert_allclose(ztilt[:n], a, rtol=1e-9, err_msg=f"plane {p}")
        np.testing.assert_allclose(ztilt[n:], b, rtol=1e-9, err_msg=f"plane {p}")


def test_a_thin_lit_sliver_is_left_out_of_the_mean():
    # a 3-km WFS over 16" with 2 x 2 field samples: four valid subapertures are lit by
    # 6-15 % from one direction (>= 3 samples, a well-posed fit), which the module
    # docstring leaves out of their mean; the independent lstsq reference drops every
    # direction lighting less than half of a subaperture
    model = LoopModel(_config(wfs_altitude=3000.0, field_samples=2, n_sub=6,
                              image_formation=False))
    w = model.wfss[0]
    frac = np.array([w._lit(w._points, th).mean(axis=1) for th in w.samples])
    assert ((frac > 0.05) & (frac < 0.5)).any(axis=0).sum() >= 1     # the case exists
    rng = np.random.default_rng(5)
    maps = [rng.standard_normal((p.n, p.n)) for p in model.geometry.planes]
    raw = _independent_ztilts(w, maps)
    np.testing.assert_allclose(w._operate(maps), raw, rtol=1e-9,
                               atol=1e-10 * np.abs(raw).max())


def test_too_few_valid_subapertures_are_refused_with_the_whole_message():
    # "a correlating SH needs at least 2" valid subapertures (the slopes are relative to
    # their mean): 2 x 2 subapertures of a 65 %-obscured pupil are lit by the beam by
    # (pi / 16) (1 - 0.65^2) / (1 / 4) = 45 % each, so none is valid (2 modes: the
    # config's own mode count rule lets it through). At 60 % (50 % lit) the rule on the
    # margined samples refused them until left30-solar; the beam's light keeps them
    cfg = _config(image_formation=False)
    cfg = SimulationConfig(
        name="test", telescope=TelescopeConfig(diameter=1.0, n_pixels=32, obscuration=0.65),
        layers=cfg.layers, dms=(DMConfig(altitude=0.0, n_modes=2),),
        wfss=(dataclasses.replace(cfg.wfss[0], n_subapertures=2),), loop=cfg.loop,
        field=cfg.field, wavelength=cfg.wavelength, r0_wavelength=cfg.r0_wavelength)
    with pytest.raises(ValueError) as exc:
        LoopModel(cfg)
    assert str(exc.value) == ("`wfss[0].n_subapertures` = 2 leaves 0 valid subaperture(s); "
                              "a correlating SH needs at least 2.")


def test_a_zonal_mirrors_interaction_is_its_poke_matrix():
    # a zonal ("ideal") DM seen by the linear mode: the interaction is sparse and equals
    # the measurements of each disc pixel poked alone through ``forward`` (the loop's
    # measurement path; tests/closedloop/test_zonal_dm.py's reference for the SH)
    cfg = _config(image_formation=False, n_pixels=16)
    model = LoopModel(cfg.replace(dms=(DMConfig(altitude=0.0, kind="ideal"),)))
    w, dm = model.wfss[0], model.dms[0]
    got = w.interaction_with(dm)
    assert sparse.issparse(got)
    cols = []
    for pix in dm.pixels:
        maps = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
        maps[dm.plane].reshape(-1)[pix] = 1.0
        cols.append(w.forward(maps))
    want = np.array(cols).T
    assert want.shape == (w.n_measurements, dm.pixels.size) and np.abs(want).max() > 0
    np.testing.assert_allclose(got.toarray(), want, rtol=0, atol=1e-12 * np.abs(want).max())
