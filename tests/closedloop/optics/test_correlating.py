"""Tests of the correlating Shack-Hartmann's image formation and measurement.

References:
- Z-tilt vs G-tilt: for a phase ``t x / R + b (x / R)^3`` over a square subaperture of
  half-side ``R``, the least-squares (Z) tilt is ``(t + 3 b / 5) / R`` (computed here by
  ``np.linalg.lstsq`` on the pupil samples) and the mean gradient (G-tilt, what the
  geometric SH of ``closedloop.optics.wfs`` reports) ``(t + b) / R``: they differ by
  ``2 b / (5 R)``. Loefdahl (2010, A&A 524, A90) shows that SDF/ADF^2 correlation
  measures the Z-tilt. Noise-free, one patch: the slopes equal the Z-tilt within the
  2QI interpolation bias (0.08 px; test_shifts measures 0.03 px max on pure shifts, the
  coma adds up to 0.05 px here) and sit at least 80 % of the way from G to Z;
- wide field: linearising the SDF of ``I = sum_d w_d r(x - s_d)`` gives
  ``s = sum_d s_d c_d / sum_d c_d`` with ``c_d = sum_window w_d (dr/dx)^2``: the
  contrast-weighted mean of the patches' tilts (weights and blending recomputed here
  from the reference image with cos^2 ramps written in the test); checked on a scene
  whose contrast differs 4x between the field's halves, so that the weighted and the
  plain means differ;
- the photon budget against astropy's BlackBody (an independent Planck law);
- detector statistics: Poisson + read noise variance ``mean + RON^2`` on a flat scene;
- end to end, the slope noise from the photon budget against the linearised SDF law
  (``shifts.sdf_noise_rms``, itself checked against Monte Carlo in test_shifts) within
  15 %, and twice its variance with a noisy same-frame reference subaperture.
"""

import math

import numpy as np
import pytest

from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.granulation import granulation_scene
from closedloop.optics.photon_budget import PhotonBudget
from closedloop.optics.shifts import sdf_noise_rms

PS = 0.25          # arcsec / pixel
D_SUB = 0.25       # m, table1's 4 m / 16
P = 16             # pupil samples across
R = D_SUB / 2
LAM = 500e-9
PX_RAD = PS * math.pi / (180 * 3600)
U = (np.arange(P) - (P - 1) / 2) * (D_SUB / P)
X, Y = np.meshgrid(U, U)
PLANE = np.column_stack([np.ones(P * P), X.ravel(), Y.ravel()])


@pytest.fixture(scope="module")
def scene():
    return granulation_scene(256, PS, seed=3, wavelength=LAM)


def _px(gradient):
    """Phase gradient [rad/m] at LAM -> image shift [px]."""
    return np.asarray(gradient) * LAM / (2 * math.pi) / PX_RAD


def test_noise_free_slopes_are_z_tilts_not_g_tilts(scene):
    b = 2.0  # rad: G - Z = 2b / 5R = 0.42 px
    for centre in [(40, 60), (200, 180), (20, 220)]:
        cs = CorrelatingSubapertures(scene, PS, D_SUB, P, 24, field_centre=centre)
        phases, z_tilts, g_tilts = [], [], []
        for t in (-1.0, 0.0, 1.5):
            phi = t * X / R + b * (X / R) ** 3 + 0.3 * t * Y / R
            phases.append(phi)
            z_tilts.append(np.linalg.lstsq(PLANE, phi.ravel(), rcond=None)[0][1:])
            g_tilts.append(np.array([(t + b) / R, 0.3 * t / R]))
        m = cs.measure(np.array(phases)[None])
        z = _px(np.array(z_tilts))
        g = _px(np.array(g_tilts))
        s = _px(m.slopes)
        # theory: G - Z = 2 b / (5 R) along x (lstsq on 16 samples: 1.4 % more)
        np.testing.assert_allclose(g[:, 0] - z[:, 0], _px(0.4 * b / R), rtol=0.02)
        np.testing.assert_allclose(s, z, atol=0.08)
        frac = (s[:, 0] - z[:, 0]) / (g[:, 0] - z[:, 0])
        assert np.all(np.abs(frac) < 0.2)
        assert not m.at_edge.any()


def _cos2(n, k):
    """Blending weights written independently: 1 outside the outer centres, cos^2 between."""
    sp = n / k
    centres = (np.arange(k) + 0.5) * sp - 0.5
    w = np.zeros((k, n))
    for i in range(n):
        if i <= centres[0]:
            w[0, i] = 1.0
        elif i >= centres[-1]:
            w[-1, i] = 1.0
        else:
            j = int(np.searchsorted(centres, i)) - 1
            t = (i - centres[j]) / sp
            w[j, i] = math.cos(math.pi * t / 2) ** 2
            w[j + 1, i] = math.sin(math.pi * t / 2) ** 2
    return w


def test_wide_field_is_contrast_weighted_mean_of_patch_tilts(scene):
    n, n_img, max_shift = scene.shape[0], 32, 2
    x = np.arange(n)
    # contrast 4x lower in the left half of every 32-px field
    low_left = 1 + (scene - 1) * np.where((x % 32) < 16, 0.25, 1.0)[None, :]
    rng = np.random.default_rng(5)
    w1 = _cos2(n_img, 2)
    w2 = np.einsum("ay,bx->abyx", w1, w1).reshape(4, n_img, n_img)
    r0 = max_shift + 1
    win = n_img - 2 * r0
    err_w, err_plain = [], []
    for trial in range(4):
        centre = (32 * (2 + trial) + 16, 40 + 45 * trial)
        cs = CorrelatingSubapertures(low_left, PS, D_SUB, P, n_img, n_patches=2,
                                     field_centre=centre, max_shift=max_shift)
        tilts = rng.uniform(-0.4, 0.4, size=(4, 2))            # px, per patch
        grads = 2 * math.pi * tilts * PX_RAD / LAM
        phase = (grads[:, 0, None, None] * X + grads[:, 1, None, None] * Y)[:, None]
        m = cs.measure(phase)
        ref = cs.reference
        dx = (ref[r0:r0 + win, r0 + 1:r0 + win + 1] - ref[r0:r0 + win, r0 - 1:r0 + win - 1]) / 2
        dy = (ref[r0 + 1:r0 + win + 1, r0:r0 + win] - ref[r0 - 1:r0 + win - 1, r0:r0 + win]) / 2
        cx = np.array([(w[r0:r0 + win, r0:r0 + win] * dx ** 2).sum() for w in w2])
        cy = np.array([(w[r0:r0 + win, r0:r0 + win] * dy ** 2).sum() for w in w2])
        weighted = np.array([(tilts[:, 0] * cx).sum() / cx.sum(),
                             (tilts[:, 1] * cy).sum() / cy.sum()])
        np.testing.assert_allclose(m.shifts[0], weighted, atol=0.04)
        # the library's linearised weights are these
        np.testing.assert_allclose(cs.direction_weights(),
                                   np.column_stack([cx / cx.sum(), cy / cy.sum()]), rtol=1e-12)
        err_w.append(m.shifts[0, 0] - weighted[0])
        err_plain.append(m.shifts[0, 0] - tilts[:, 0].mean())
    # the weights matter: the plain mean is far worse than the contrast-weighted one
    assert np.sqrt(np.mean(np.square(err_w))) < 0.4 * np.sqrt(np.mean(np.square(err_plain)))


def test_same_frame_reference_gives_relative_slopes(scene):
    cs = CorrelatingSubapertures(scene, PS, D_SUB, P, 24, field_centre=(90, 120))
    grads = 2 * math.pi * np.array([[0.3, -0.2], [-0.5, 0.4], [0.1, 0.6]]) * PX_RAD / LAM
    phase = (grads[:, 0, None, None] * X + grads[:, 1, None, None] * Y)[None]
    absolute = cs.measure(phase).shifts
    relative = cs.measure(phase, reference=1).shifts
    np.testing.assert_allclose(relative, absolute - absolute[1], atol=0.06)


@pytest.mark.parametrize("exposure", [1e-3, 3e-8])  # well-limited 15 000 e-; ~500 e-
def test_slope_noise_from_photon_budget_follows_the_law(scene, exposure):
    budget = PhotonBudget(exposure=exposure, read_noise=3.0)
    cs = CorrelatingSubapertures(scene, PS, D_SUB, P, 24, budget=budget, field_centre=(70, 80))
    m = cs.measure(np.zeros((1, 600, P, P)), rng=np.random.default_rng(2))
    law = sdf_noise_rms(cs.reference, cs.reference + 3.0 ** 2, max_shift=cs.max_shift)
    # 600 draws: the rms's sampling error is 3 %; the law's own error on granulation < 5 %
    np.testing.assert_allclose(m.shifts.std(axis=0), law, rtol=0.15)
    # the slopes' noise in the loop's units: 2 pi rms(shift) pixel / lambda
    np.testing.assert_allclose(m.slopes.std(axis=0), 2 * math.pi * law * PX_RAD / LAM,
                               rtol=0.15)


def test_same_frame_reference_doubles_the_noise_variance(scene):
    # the reference subaperture's noise enters every other slope: variance law x 2
    cs = CorrelatingSubapertures(scene, PS, D_SUB, P, 24, budget=PhotonBudget(read_noise=3.0),
                                 field_centre=(70, 80))
    law = sdf_noise_rms(cs.reference, cs.reference + 3.0 ** 2, max_shift=cs.max_shift)
    rng = np.random.default_rng(3)
    # 40 frames: the reference's share is sampled 40 times, so the rms is known to ~3 %
    shifts = np.concatenate([cs.measure(np.zeros((1, 16, P, P)), rng=rng, reference=0)
                             .shifts[1:] for _ in range(40)])
    np.testing.assert_allclose(shifts.std(axis=0), math.sqrt(2.0) * law, rtol=0.15)


def test_photon_budget_against_astropy_planck():
    from astropy import units as u
    from astropy.modeling.physical_models import BlackBody

    b = PhotonBudget()
    bnu = BlackBody(temperature=6300 * u.K)(500 * u.nm)          # per Hz, per sr
    blam = (bnu * (2.99792458e8 * u.m / u.s) / (500 * u.nm) ** 2).to(
        u.W / u.m ** 2 / u.m / u.sr).value
    photons = blam * 500e-9 / (6.62607015e-34 * 2.99792458e8)
    omega = (0.5 * math.pi / (180 * 3600)) ** 2
    want = photons * 10e-9 * 1e-3 * 0.0625 * omega * 0.3 * 0.6
    assert b.unattenuated_electrons(0.0625, 0.5) == pytest.approx(want, rel=1e-6)
    assert want > 1e7                                  # far beyond a well: attenuated
    assert b.electrons(0.0625, 0.5) == 15_000.0
    dim = PhotonBudget(exposure=1e-9)
    assert dim.electrons(0.0625, 0.5) == pytest.approx(want * 1e-6, rel=1e-6)


@pytest.mark.parametrize("exposure", [1e-3, 3e-9])  # 15 000 e- (Gaussian), ~200 e- (Poisson)
def test_detector_noise(exposure):
    flat = np.ones((64, 64))
    budget = PhotonBudget(read_noise=5.0, exposure=exposure)
    cs = CorrelatingSubapertures(flat, 0.5, D_SUB, 8, 16, budget=budget)
    zero = np.zeros((1, 200, 8, 8))
    img = cs.images(zero, rng=np.random.default_rng(0))
    mean = cs.electrons_per_pixel
    assert 100 < mean <= 15_000
    # 51 200 samples: sampling error of the mean < 0.1 %, of the variance 0.6 %
    assert img.mean() == pytest.approx(mean, rel=3e-3)
    assert img.var() == pytest.approx(mean + 25.0, rel=0.03)


@pytest.mark.parametrize("exposure", [1e-3, 3e-9])  # 15 000 e- (Gaussian), ~200 e- (Poisson)
def test_read_noise_dominated_detector_variance(exposure):
    # test_detector_noise's 5 e- is 0.2 % of the Gaussian branch's variance, below its
    # tolerance: here the read noise dominates (RON^2 = 2.25 x the mean), so the law
    # ``mean + RON^2`` (Poisson plus independent Gaussian read noise) pins the read
    # noise's square (a read noise entered as RON instead of RON^2 halves the variance).
    flat = np.ones((64, 64))
    mean = CorrelatingSubapertures(flat, 0.5, D_SUB, 8, 16,
                                   budget=PhotonBudget(exposure=exposure)).electrons_per_pixel
    ron = 1.5 * math.sqrt(mean)
    budget = PhotonBudget(read_noise=ron, exposure=exposure)
    cs = CorrelatingSubapertures(flat, 0.5, D_SUB, 8, 16, budget=budget)
    img = cs.images(np.zeros((1, 200, 8, 8)), rng=np.random.default_rng(1))
    # 51 200 samples: sampling error of the variance 0.6 %; the clip at 0 e- is > 7 sigma
    # below the mean (sqrt(mean / 3.25) sigma, mean >= 200 e-): no pixel reaches it
    assert img.var() == pytest.approx(mean + ron ** 2, rel=0.03)


def test_detector_gain_and_offset():
    flat = np.ones((64, 64))
    budget = PhotonBudget(read_noise=5.0)
    zero = np.zeros((1, 1, 8, 8))
    mean = CorrelatingSubapertures(flat, 0.5, D_SUB, 8, 16, budget=budget).electrons_per_pixel
    cs2 = CorrelatingSubapertures(flat, 0.5, D_SUB, 8, 16, budget=budget, gain_rms=0.01,
                                  offset_rms=3.0, detector_seed=4)
    clean = cs2.images(zero)[0]
    det = np.random.default_rng(4)
    gain = 1 + 0.01 * det.standard_normal((16, 16))
    offset = 3.0 * det.standard_normal((16, 16))
    np.testing.assert_allclose(clean, mean * gain + offset, rtol=1e-9)
    # the stored reference is ideal; each subaperture has its own fixed maps
    np.testing.assert_allclose(cs2.reference, mean, rtol=1e-12)
    two = cs2.images(np.zeros((1, 2, 8, 8)))
    assert not np.allclose(two[0], two[1])
    np.testing.assert_array_equal(two, cs2.images(np.zeros((1, 2, 8, 8))))


def test_validation(scene):
    with pytest.raises(ValueError, match="`n_pupil` must be an int >= 2"):
        CorrelatingSubapertures(scene, PS, D_SUB, 1, 24)
    with pytest.raises(ValueError, match="`n_patches` must be <= field_pixels // 4"):
        CorrelatingSubapertures(scene, PS, D_SUB, P, 24, n_patches=7)
    with pytest.raises(ValueError, match="`pupil_oversampling` must be an int >="):
        CorrelatingSubapertures(scene, PS, D_SUB, 4, 24, pupil_oversampling=1)
    with pytest.raises(ValueError, match="`scene` must be at least"):
        CorrelatingSubapertures(scene[:30, :30], PS, D_SUB, P, 24)
    with pytest.raises(ValueError, match="`max_shift` must be an int >= 1"):
        CorrelatingSubapertures(scene, PS, D_SUB, P, 24, max_shift=0)
    with pytest.raises(ValueError, match="`method` must be one of"):
        CorrelatingSubapertures(scene, PS, D_SUB, P, 24, method="xcorr")
    with pytest.raises(ValueError, match="`fill` must be <= 1"):
        PhotonBudget(fill=2.0)
    cs = CorrelatingSubapertures(scene, PS, D_SUB, P, 24)
    with pytest.raises(ValueError, match=r"`phase` must be \(n_dir=1, n_sub, 16, 16\)"):
        cs.measure(np.zeros((2, 3, 16, 16)))
    with pytest.raises(ValueError, match="`reference` must be a subaperture index"):
        cs.measure(np.zeros((1, 3, 16, 16)), reference=3)


def test_field_is_cut_at_its_centre_and_blurred_by_the_pixel(scene):
    # a 4 m "subaperture": lambda/d = 0.026" << 0.25" pixels, so the image is the scene
    # times the pixel MTF (sinc) and the square aperture's OTF, the triangle
    # 1 - |f| lambda / (d p) per axis (f in cycles per pixel: 0.95 at the detector's
    # Nyquist), cut around the field centre
    budget = PhotonBudget()
    cs = CorrelatingSubapertures(scene, PS, 4.0, 8, 24, budget=budget, field_centre=(101, 57))
    img = cs.images(np.zeros((1, 1, 8, 8)))[0] / cs.electrons_per_pixel
    f = np.fft.fftfreq(scene.shape[0])
    otf = np.clip(1.0 - np.abs(f) * LAM / (4.0 * PX_RAD), 0.0, None) * np.sinc(f)
    blurred = np.fft.ifft2(np.fft.fft2(scene) * np.outer(otf, otf)).real
    want = blurred[57 - 12:57 + 12, 101 - 12:101 + 12]
    # the PSF is computed over a finite support: its sinc^2 wings beyond it hold ~1e-3
    np.testing.assert_allclose(img, want, atol=2e-3)
    assert np.abs(img - want).max() < 0.1 * np.abs(want - 1).max()
