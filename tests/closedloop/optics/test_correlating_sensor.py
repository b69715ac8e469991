"""The correlating Shack-Hartmann as a loop sensor (``kind="correlating"``).

References, each from outside the code under test:
- linear mode: an independent Z-tilt computation written here (scipy's
  ``RegularGridInterpolator`` for the footprints, ``numpy.linalg.lstsq`` for the plane fit
  over each subaperture's lit samples, contrast weights from the reference image's
  gradient energy in the nearest-direction cells), on random phases;
- imaging mode: the images formed and correlated every frame
  (``CorrelatingSubapertures`` + ``measure_shifts``) give the linear mode's slopes within
  the SDF/2QI interpolation bias (<= 0.03 px per image, measured last session: here two
  images per relative slope) and its predicted noise within 15 %;
- tracker: a pure tilt's analytic Zernike coefficient (``a x = (a R / 2) Z2``);
- configs: TOML/JSON round trips, and the plain forms of the old presets, unchanged;
- the loop: ``table1-solar``'s SR rises well above its own open-loop SR.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from closedloop import presets, simulate
from closedloop.config import (
    ARCSEC,
    FieldConfig,
    load_config,
    save_config,
)
from closedloop.kinds import sensor_kind
from closedloop.model import LoopModel
from closedloop.optics.correlating_sensor import CorrelatingShackHartmann

from ..conftest import correlating_config, correlating_sensor


def _config(*, field_samples=1, image_formation=False, layer_altitude=0.0, d_over_r0=4.0,
            signal=None, contrast=None, n_sub=4, fov=10.0):
    sensor = correlating_sensor(0.0, fov, n_sub=n_sub, field_samples=field_samples,
                                image_formation=image_formation, signal=signal,
                                contrast=contrast)
    return correlating_config("test", [(layer_altitude, d_over_r0)], [(0.0, 20)], [sensor])


def _turbulence(model: LoopModel, seed: int) -> list[np.ndarray]:
    from closedloop.state import LoopState

    st = LoopState(model, model.atmosphere(seed, 0.01))
    st.evolve_until(0.0)
    return st.turbulence([np.zeros((p.n, p.n)) for p in model.geometry.planes])


def test_registered_and_configured():
    assert sensor_kind("correlating").build is CorrelatingShackHartmann
    model = LoopModel(_config())
    (w,) = model.wfss
    assert isinstance(w, CorrelatingShackHartmann)
    assert w.n_measurements == 2 * w.n_valid_subapertures + 2
    assert w.noise_rms.shape == (w.n_measurements,) and np.all(w.noise_rms > 0)


# ---------------------------------------------------------------------- linear mode
def _independent_ztilts(w: CorrelatingShackHartmann, maps) -> np.ndarray:
    """Raw contrast-weighted Z-tilts ``(x..., y...)`` [rad/m], computed independently."""
    g = w._geometry
    n_sub = g.config.wfss[w.index].n_subapertures
    d_wfs = w.pitch * n_sub
    f = w.n_pupil
    off = ((np.arange(f) + 0.5) / f - 0.5) * w.pitch
    edge = math.sqrt(2.0) * g.dx
    interps = [RegularGridInterpolator((g.plane_coords(p), g.plane_coords(p)), maps[p])
               for p in range(len(g.planes))]  # (y, x) axes of the (rows, cols) maps
    # contrast weights: the reference's gradient energy over the correlation window,
    # each pixel counted for the nearest field direction
    ref = w.imager.reference
    n = ref.shape[0]
    lag = 4  # max_shift + 1
    win = np.arange(lag, n - lag)
    gx = (ref[np.ix_(win, win + 1)] - ref[np.ix_(win, win - 1)]) / 2.0
    gy = (ref[np.ix_(win + 1, win)] - ref[np.ix_(win - 1, win)]) / 2.0
    pos = (win - (n - 1) / 2.0) * w.pixel_scale
    weights = np.zeros((len(w.samples), 2))
    for iy, y in enumerate(pos):
        for ix, x in enumerate(pos):
            k = np.argmin((w.samples[:, 0] - x) ** 2 + (w.samples[:, 1] - y) ** 2)
            weights[k] += gx[iy, ix] ** 2, gy[iy, ix] ** 2
    weights /= weights.sum(axis=0)
    out = np.zeros((2, w.valid_subapertures.size))
    for i, s in enumerate(w.valid_subapertures):
        cx = (s % n_sub + 0.5) * w.pitch - d_wfs / 2.0
        cy = (s // n_sub + 0.5) * w.pitch - d_wfs / 2.0
        yy, xx = np.meshgrid(cy + off, cx + off, indexing="ij")
        acc, norm = np.zeros(2), np.zeros(2)
        for t, theta in enumerate(w.samples):
            bx = xx - w.altitude * theta[0] * ARCSEC
            by = yy - w.altitude * theta[1] * ARCSEC
            lit = np.hypot(bx, by) <= g.diameter / 2.0 - edge
            # used when the beam (the plain pupil) lights half of the subaperture; fitted
            # on the margined samples (left30-solar: the margin is the bilinear reads')
            if (np.hypot(bx, by) <= g.diameter / 2.0).mean() < 0.5:
                continue
            phase = np.zeros(lit.sum())
            for p, plane in enumerate(g.planes):
                sh = (plane.altitude - w.altitude) * theta * ARCSEC
                phase += interps[p](np.column_stack([yy[lit] + sh[1], xx[lit] + sh[0]]))
            design = np.column_stack([np.ones(lit.sum()), xx[lit], yy[lit]])
            coef = np.linalg.lstsq(design, phase, rcond=None)[0]
            acc += weights[t] * coef[1:]
            norm += weights[t]
        out[:, i] = acc / norm
    return out.ravel()


@pytest.mark.parametrize("field_samples,layer_altitude", [(1, 0.0), (2, 3000.0)])
def test_linear_mode_is_the_contrast_weighted_ztilt(field_samples, layer_altitude):
    model = LoopModel(_config(field_samples=field_samples, layer_altitude=layer_altitude,
                              fov=30.0))
    (w,) = model.wfss
    rng = np.random.default_rng(3)
    maps = [rng.standard_normal((p.n, p.n)) for p in model.geometry.planes]
    raw = _independent_ztilts(w, maps)
    np.testing.assert_allclose(w._operate(maps), raw, rtol=1e-9,
                               atol=1e-10 * np.abs(raw).max())
    # the measurements: slopes less their mean per axis, then the tracker's two means
    n = w.n_valid_subapertures
    s = w.forward(maps)
    for a in range(2):
        v = raw[a * n:(a + 1) * n]
        np.testing.assert_allclose(s[a * n:(a + 1) * n], v - v.mean(), atol=1e-9 * np.abs(v).max())
        assert s[2 * n + a] == pytest.approx(v.mean(), rel=1e-9, abs=1e-12)
    if field_samples > 1:
        # a wide field: the weights are not uniform (granulation's contrast varies)
        assert np.ptp(w.direction_weights[:, 0]) > 0.1 / len(w.samples)


def test_tracker_restores_the_global_tilt():
    model = LoopModel(_config())
    g = model.geometry
    (w,) = model.wfss
    a, b = 0.8, -0.5  # rad/m
    co = g.plane_coords(0)
    xx, yy = np.meshgrid(co, co, indexing="xy")
    maps = [a * xx + b * yy]
    s = w.forward(maps)
    n = w.n_valid_subapertures
    # relative slopes lose the tilt; the tracker has it
    assert np.abs(s[:2 * n]).max() < 1e-12
    np.testing.assert_allclose(s[2 * n:], [a, b], rtol=1e-12)
    # unit-RMS Z2 = 2 x / R, Z3 = 2 y / R: a x + b y = (a R / 2) Z2 + (b R / 2) Z3
    radius = model.dms[0].diameter / 2.0
    modal = model.sense(maps, None)
    np.testing.assert_allclose(modal[:2], [a * radius / 2.0, b * radius / 2.0], rtol=1e-3)
    assert np.abs(modal[2:]).max() < 1e-3 * abs(a * radius / 2.0)


# ---------------------------------------------------------------------- imaging mode
@pytest.fixture(scope="module")
def imaging():
    # 16" at 0.5": 32 px images, a 24 px correlation window. The default signal (15 000
    # e-) at a low contrast gives a predicted rms of ~0.01 px, where the linearised law
    # holds (at 400 e- and 8 %, 0.07 px, a same-frame reference's noise energy, which
    # varies with the lag, adds 2-10x: measured while writing this test)
    model = LoopModel(_config(image_formation=True, contrast=0.04, fov=16.0))
    w = model.wfss[0]
    # vignetted subapertures have broader, dimmer-contrast images than the reference
    # the law is evaluated on: compared where every direction lights the whole subaperture
    full = np.flatnonzero(w._amplitude.min(axis=(0, 2, 3)) > 0)
    assert full.size >= 4
    return model, w, full


def test_imaging_mode_equals_the_linear_mode_without_noise(imaging):
    model, w, full = imaging
    n = w.n_valid_subapertures
    sel = np.concatenate([full, full + n])
    worst = 0.0
    for seed in range(3):
        maps = _turbulence(model, seed)
        linear = w.relative(w._operate(maps))[:2 * n] / w._to_slope     # [pixels]
        imaged = w.image_slopes(maps) / w._to_slope
        assert np.abs(linear[sel]).max() > 0.1  # the turbulence moves the images measurably
        worst = max(worst, np.abs(imaged - linear)[sel].max())
    # within 0.08 px: test_correlating's bound for one image's Z-tilt against a stored
    # reference (2QI bias 0.03 px on pure shifts, plus up to 0.05 px from coma-like terms)
    assert worst < 0.08, worst
    # the measurement vector: image slopes, then the (linear) tracker
    maps = _turbulence(model, 0)
    s = w.forward(maps)
    np.testing.assert_array_equal(s[:2 * n], w.image_slopes(maps))
    np.testing.assert_array_equal(s[2 * n:], w.relative(w._operate(maps))[2 * n:])


def test_imaging_noise_matches_the_predicted_rms(imaging):
    model, w, full = imaging
    n = w.n_valid_subapertures
    maps = _turbulence(model, 1)
    clean = w.image_slopes(maps)
    rng = np.random.default_rng(7)
    diffs = np.array([w.image_slopes(maps, rng.standard_normal(w.n_measurements)) - clean
                      for _ in range(40)])
    # slopes less their mean: each keeps (1 - 1/n) of a slope's noise variance
    for a in range(2):
        empirical = diffs[:, a * n + full].std()
        predicted = w.noise_rms[a * n] * math.sqrt(1.0 - 1.0 / n)
        assert empirical == pytest.approx(predicted, rel=0.15), (a, empirical, predicted)
    # the prediction is not negligible against the noise-free scatter (else trivial)
    assert w.slope_noise_pixels.min() > 0.005


def test_linear_noise_falls_with_signal_and_contrast():
    def rms(**kw):
        return LoopModel(_config(**kw)).wfss[0].slope_noise_pixels[0]

    # photon-noise dominated: rms ~ 1 / (contrast sqrt(signal)) (Michau et al. 1992)
    base = rms(signal=400.0, contrast=0.08)
    assert rms(signal=1600.0, contrast=0.08) == pytest.approx(base / 2.0, rel=0.05)
    assert rms(signal=400.0, contrast=0.16) == pytest.approx(base / 2.0, rel=0.1)


# ---------------------------------------------------------------------- configs
@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_round_trip(fmt, tmp_path):
    c = _config(image_formation=True, signal=1000.0, contrast=0.1)
    c = c.replace(wfss=(dataclasses.replace(c.wfss[0], pixel_scale=0.4),))
    save_config(c, tmp_path / f"c.{fmt}")
    back = load_config(tmp_path / f"c.{fmt}")
    assert back == c
    d = c.to_dict()["wfss"][0]
    assert d["pixel_scale"] == 0.4 and d["signal"] == 1000.0 and d["image_formation"] is True


@pytest.mark.parametrize("name", ["table1", "table1-wind", "mcao3", "kaos"])
def test_old_plain_forms_have_no_new_keys(name):
    for w in presets.get(name).to_dict()["wfss"]:
        assert set(w) == {"altitude", "field_of_view", "n_subapertures", "noise", "kind",
                          "field_samples", "dm"}


def test_table1_solar_preset():
    c = presets.get("table1-solar")
    t1 = presets.get("table1")
    assert [w.kind for w in c.wfss] == ["correlating"] * 2
    assert [w.field_of_view for w in c.wfss] == [w.field_of_view for w in t1.wfss]
    assert c.loop.delay == presets.SOLAR_RTC_DELAY
    assert c.replace(wfss=t1.wfss, loop=t1.loop, name="table1") == t1


@pytest.mark.parametrize("changes,exc,match", [
    ({"pixel_scale": 0.3}, ValueError, r"`wfss\[0\]\.pixel_scale` must be left at its default"),
    ({"signal": 100.0}, ValueError, r"`wfss\[0\]\.signal` must be left at its default"),
    ({"image_formation": True}, ValueError, r"`wfss\[0\]\.image_formation` must be left"),
    ({"kind": "correlating", "noise": 0.01}, ValueError, r"`wfss\[0\]\.noise` must be 0"),
    ({"kind": "correlating", "noise": 0.0, "signal": 4e4}, ValueError,
     r"`wfss\[0\]\.signal` must be <= 30000"),
    ({"kind": "correlating", "noise": 0.0, "contrast": 0.0}, ValueError,
     r"`wfss\[0\]\.contrast` must be >= 0\.001"),
    ({"kind": "correlating", "noise": 0.0, "image_formation": 1}, TypeError,
     r"`wfss\[0\]\.image_formation` must be a bool"),
    ({"kind": "correlating", "noise": 0.0, "field_of_view": 3.0}, ValueError,
     r"`wfss\[0\]\.field_of_view` must be >= 8 detector pixels"),
])
def test_refusals_name_the_key(changes, exc, match):
    c = presets.get("table1")
    with pytest.raises(exc, match=match):
        c.replace(wfss=(dataclasses.replace(c.wfss[0], **changes), c.wfss[1]))


# ---------------------------------------------------------------------- the loop
def test_table1_solar_closes_its_loop():
    # the first frame, before any command reaches the mirrors, is the open-loop SR
    c = presets.get("table1-solar")
    r = simulate(c, 0.06, progress=False)
    assert r.strehl_peak[0] < 1e-3
    assert r.strehl_peak[-20:].mean() > 0.1


def test_aot_export_keeps_slopes_and_tracker(tmp_path):
    # reference: the run's own measurement vectors, read back by aotpy
    aotpy = pytest.importorskip("aotpy")
    from closedloop.aot import export_aot

    c = _config()
    model = LoopModel(c)
    r = simulate(c, 0.005, model=model, progress=False)
    export_aot(r, tmp_path / "c.fits", model=model)
    (w,) = model.wfss
    n = w.n_valid_subapertures
    back = np.asarray(aotpy.AOSystem.read_from_file(tmp_path / "c.fits")
                      .wavefront_sensors[0].measurements.data)
    meas = np.asarray(r.measurements[0])
    assert back.shape == (meas.shape[0], 2, n + 1)
    np.testing.assert_array_equal(back[:, 0, :n], meas[:, :n])
    np.testing.assert_array_equal(back[:, 1, :n], meas[:, n:2 * n])
    np.testing.assert_array_equal(back[:, :, n], meas[:, 2 * n:])


# ---------------------------------------------------------------------- error budget
def _solar_small():
    from ..conftest import small

    c = small()
    wfss = tuple(dataclasses.replace(w, kind="correlating", noise=0.0) for w in c.wfss)
    return c.replace(wfss=wfss, loop=dataclasses.replace(c.loop, delay=presets.SOLAR_RTC_DELAY))


def test_error_budget_adds_up_small_solar():
    # reference: the residual the loop really left (independent estimates of each term,
    # cross terms neglected), within 15 % in every direction of a 3x3 grid
    from ..test_physics import _budget_check

    result = _budget_check(_solar_small(), 0.15, 2)
    assert result.budget.directions.shape == (9, 2)


@pytest.mark.slow
def test_error_budget_adds_up_table1_solar_3x3():
    from ..test_physics import _budget_check

    cfg = presets.get("table1-solar")
    cfg = cfg.replace(field=FieldConfig(size=cfg.field.size, n_points=3))
    result = _budget_check(cfg, 0.3, 3)
    assert result.budget.directions.shape == (9, 2)
