"""The correlating SH's slope noise at the sub-pixel shifts a closed loop leaves (issue 27).

References (outside the code under test):
- the real measurement: a Monte Carlo of ``measure_shifts`` (SDF + 2QI) on granulation
  displaced by the Fourier shift theorem (exact for a periodic scene) or imaged through a
  Z-tilt, with white Gaussian noise of variance ``mean + RON^2`` drawn by numpy; the
  variance of ``n`` draws has a relative standard error ``sqrt(2 / (n - 1))`` (400 draws:
  7.1 %; the prediction's 4000 Gaussian surfaces add 2.2 %), so a bound of +-35 % on a
  measured / predicted ratio is > 4.5 standard errors;
- at a whole-pixel shift, the linearised law ``sdf_noise_rms`` (Michau et al. 1992),
  itself checked against the measurement in test_shifts_round29;
- a Z-tilt's image formed by ``CorrelatingSubapertures.images`` (the PSF of a tilted
  pupil) for the displaced reference images.

Before this branch, ``CorrelatingShackHartmann`` (linear mode: table1-solar,
est-mcao-solar, Figure 7) drew every slope's noise from the whole-pixel law whatever the
slope's sub-pixel shift: 1.5-6x too little variance at 0.3-0.45 pixel
(test_the_linear_sensor_draws_the_measured_noise_at_sub_pixel_shifts fails there).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from closedloop.model import LoopModel
from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.granulation import granulation_scene
from closedloop.optics.shifts import measure_shifts, sdf_noise_at_shifts, sdf_noise_rms

from ..conftest import correlating_config, correlating_sensor

SCENE = granulation_scene(96, 0.25, seed=3)
DRAWS = 400


def _shifted(sx: float, sy: float) -> np.ndarray:
    f = np.fft.fft2(SCENE)
    ky = np.fft.fftfreq(SCENE.shape[0])[:, None]
    kx = np.fft.fftfreq(SCENE.shape[1])[None, :]
    return np.real(np.fft.ifft2(f * np.exp(-2j * np.pi * (kx * sx + ky * sy))))[24:72, 24:72]


def _measured_var(ref, mean, var, rng) -> np.ndarray:
    live = mean[None] + np.sqrt(var)[None] * rng.standard_normal((DRAWS,) + mean.shape)
    return measure_shifts(ref, live, max_shift=3).shifts.var(axis=0, ddof=1)


SHIFTS = [(0.0, 0.0), (0.2, 0.0), (0.4, 0.2), (-0.3, 0.45), (1.3, -0.4)]


def test_noise_at_shifts_is_the_measured_noise():
    rng = np.random.default_rng(5)
    ref = _shifted(0.0, 0.0) * 1000.0
    live = np.stack([_shifted(*s) * 1000.0 for s in SHIFTS])
    predicted = sdf_noise_at_shifts(ref, live, live, max_shift=3) ** 2
    ratios = np.array([_measured_var(ref, m, m, rng) for m in live]) / predicted
    assert np.all(np.abs(ratios - 1.0) < 0.35), ratios
    # at a whole pixel it is the linearised law (within its 2QI cross-term neglect)
    law = sdf_noise_rms(ref, ref, max_shift=3) ** 2
    np.testing.assert_allclose(predicted[0] / law, 1.0, atol=0.1)
    # and not at sub-pixel shifts (else the function would add nothing)
    assert predicted[2, 0] / law[0] > 1.6 and predicted[3, 1] / law[1] > 2.0


def test_noise_at_shifts_refuses_bad_input():
    ref = _shifted(0.0, 0.0)
    with pytest.raises(ValueError, match="`live` image 0 is displaced by"):
        sdf_noise_at_shifts(ref, _shifted(2.6, 0.0), 1.0, max_shift=3)
    with pytest.raises(ValueError, match="`draws`"):
        sdf_noise_at_shifts(ref, ref, 1.0, draws=1)
    with pytest.raises(ValueError, match="`noise_variance`"):
        sdf_noise_at_shifts(ref, ref, -1.0)


def test_displaced_references_are_the_images_of_a_z_tilt():
    ps, d, p = 0.4, 0.1, 8
    cs = CorrelatingSubapertures(granulation_scene(128, ps, seed=1), ps, d, p, 24, max_shift=3)
    x = (np.arange(p) + 0.5) / p * d - d / 2
    xx, yy = np.meshgrid(x, x, indexing="xy")
    per_pixel = 2 * np.pi * ps * np.pi / 180 / 3600 / cs.wavelength   # rad/m per pixel
    sh = np.array([[0.0, 0.0], [0.3, -0.2], [0.5, 0.5], [-1.2, 0.7]])
    tilted = cs.images(np.stack([per_pixel * (sx * xx + sy * yy) for sx, sy in sh])[None])
    shifted = cs.displaced_references(sh)
    np.testing.assert_array_equal(shifted[0], cs.reference)
    np.testing.assert_allclose(shifted, tilted, atol=1e-3 * cs.reference.max())


@pytest.fixture(scope="module")
def sensor():
    wfs = correlating_sensor(0.0, 10.0, n_sub=4, signal=400.0, contrast=0.08)
    cfg = correlating_config("test", [(0.0, 4.0)], [(0.0, 20)], [wfs])
    return LoopModel(cfg).wfss[0]


def test_the_linear_sensor_draws_the_measured_noise_at_sub_pixel_shifts(sensor, monkeypatch):
    w = sensor
    n = w.n_valid_subapertures
    # each subaperture at its own sub-pixel shift [pixels]: the noise-free measurement
    # (the Z-tilt operators and the relative transform) replaced by these shifts
    rng = np.random.default_rng(3)
    shifts = np.column_stack([rng.uniform(-0.5, 0.5, n), rng.uniform(-0.5, 0.5, n)])
    shifts -= shifts.mean(axis=0)
    clean = np.concatenate([shifts[:, 0], shifts[:, 1], [0.0, 0.0]]) * w._to_slope
    monkeypatch.setattr(w, "_operate", lambda maps: None)
    monkeypatch.setattr(w, "relative", lambda raw: clean.copy())
    noisy = np.array([w.forward([], rng.standard_normal(w.n_measurements))
                      for _ in range(DRAWS)])
    drawn = ((noisy - clean) / w._to_slope).var(axis=0, ddof=1)[:2 * n] / 2.0
    # the real measurement: the subaperture's reference image displaced by each shift,
    # photon + read noise in the live image (the same-frame reference doubles it: / 2)
    ron2 = w.imager.budget.read_noise ** 2
    live = w.imager.displaced_references(shifts)
    measured = np.array([_measured_var(w.imager.reference, m, np.clip(m, 0, None) + ron2, rng)
                         for m in live])
    ratio = drawn / np.concatenate([measured[:, 0], measured[:, 1]])
    # each ratio of two 400-draw variances: 10 % standard error; their mean over 2 n
    # slopes ~2.5 %: the mean within 15 %, each within 50 %
    assert abs(ratio.mean() - 1.0) < 0.15, ratio
    assert np.all(np.abs(ratio - 1.0) < 0.5), ratio
    # the whole-pixel law alone would be well below the measurement here
    law = (w.slope_noise_pixels / math.sqrt(2.0)) ** 2
    assert np.mean(measured / law) > 1.5
