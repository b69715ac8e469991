"""Tests of :func:`closedloop.optics.shifts.measure_shifts`.

References:
- known sub-pixel shifts applied by the Fourier shift theorem to synthetic granulation
  blurred by a 10 cm square subaperture at 500 nm (triangle OTF) and 0.4" pixels (a
  solar-SH-like subimage: 24x24 pixels, 16x16 live window). Loefdahl 2010 (A&A 524,
  A90; abstract and conclusions) finds SDF and ADF^2 with 2D quadratic interpolation the
  most accurate and measures the error of every method on artificial granulation with
  known shifts; the FFT covariance without apodisation suffers from its edges. We check
  the ranking (SDF/ADF^2 + 2QI best, 1QI worse, CFI worst) and an order of magnitude of
  a few hundredths of a pixel (measured here, 12 subfields x 9 shifts: SDF/ADF^2 + 2QI
  max |bias| 0.03 px, scatter 0.010-0.013 px; 1QI bias 0.06, scatter 0.02-0.025 px; CFI
  bias 0.096 px). The full text was not available offline: the figure-by-figure values
  of his paper are not compared here. The ranking alone passes a 1QI worse than it should
  be, so SDF + 1QI is also held to known shifts (max |bias| 0.061 px over shifts in
  [-1, 1] on 6 subfields, tolerance 0.1 px; a sign-flipped vertex, B5 of review7: 0.71);
- noise: the linearised least-squares (Michau et al. 1992) law for the SDF with quadratic
  interpolation: with live-image noise of variance ``s2(x)``, the 1-D estimate
  ``x = (C(-1) - C(1)) / 2 (C(-1) - 2 C(0) + C(1))`` has, to first order,
  ``var = 4 sum s2 (D r)^2 / (sum (r - r(x+1))^2 + (r - r(x-1))^2)^2`` with ``D r`` the
  central difference (for a well-sampled image ``sigma^2 / sum (dr/dx)^2``, Michau's
  law; at the WFS's Nyquist-like sampling the finite differences matter by ~10 %), and
  its scaling ``1 / sqrt(photons)`` and ``1 / contrast`` for every method; tolerance
  15 % (sampling error of the rms from 1000 draws ~2 %);
- the numba kernel against a direct numpy loop written here, and called from njit.
"""

import numba as nb
import numpy as np
import pytest

from closedloop.optics import _shift_kernels
from closedloop.optics.granulation import granulation_scene
from closedloop.optics.shifts import INTERPOLATIONS, METHODS, measure_shifts, sdf_noise_rms

# CFI's bias warning (audit 9) is checked once, in test_cfi_warns_of_its_bias
pytestmark = pytest.mark.filterwarnings("ignore:method 'cfi' of measure_shifts:UserWarning")

PS = 0.4        # pixel scale [arcsec]
N_SCENE = 128
N_IMG, WIN = 24, 16


def _blurred_spectrum(seed: int, contrast: float = 0.15) -> np.ndarray:
    scene = granulation_scene(N_SCENE, PS, seed=seed, contrast=contrast)
    f = np.fft.fftfreq(N_SCENE, d=PS)                  # cycles / arcsec
    fc = 0.1 / 500e-9 * np.pi / (180 * 3600)            # d / lambda in cycles / arcsec
    tri = np.clip(1 - np.abs(f / fc), 0, None)
    otf = np.outer(tri, tri) * np.outer(np.sinc(f * PS), np.sinc(f * PS))
    return np.fft.fft2(scene) * otf


def _shifted(spec: np.ndarray, dx: float, dy: float) -> np.ndarray:
    f = np.fft.fftfreq(N_SCENE)
    ramp = np.exp(-2j * np.pi * (f[None, :] * dx + f[:, None] * dy))
    return np.fft.ifft2(spec * ramp).real


def _cut(img, offsets):
    return np.array([img[a:a + N_IMG, b:b + N_IMG] for a, b in offsets])


def _bias_tables(n_off=12):
    """Max |bias| (x or y) and rms scatter (x) [px] of every method x interpolation."""
    spec = _blurred_spectrum(seed=1)
    offs = np.random.default_rng(0).integers(0, N_SCENE - N_IMG, size=(n_off, 2))
    ref = _cut(_shifted(spec, 0, 0), offs)
    truths = np.linspace(-1.0, 1.0, 9)
    lives = [_cut(_shifted(spec, s, 0.37 * s), offs) for s in truths]
    table = {}
    for method in METHODS:
        for interpolation in INTERPOLATIONS:
            rows = []
            for s, live in zip(truths, lives, strict=True):
                r = measure_shifts(ref, live, method=method, interpolation=interpolation,
                                   max_shift=3, window=WIN if method != "cfi" else N_IMG)
                err = r.shifts - np.array([s, 0.37 * s])
                rows.append((err[:, 0].mean(), err[:, 0].std(), err[:, 1].mean()))
            rows = np.array(rows)
            table[(method, interpolation)] = (np.abs(rows[:, [0, 2]]).max(),
                                              np.sqrt((rows[:, 1] ** 2).mean()))
    return table


def test_bias_and_scatter_vs_loefdahl_ranking():
    table = _bias_tables()
    for m in ("sdf", "adf2"):
        bias, scatter = table[(m, "2d-quadratic")]
        # a few hundredths of a pixel (Loefdahl 2010's best methods; measured 0.03, 0.01)
        assert bias < 0.05 and scatter < 0.03
        # 2QI beats 1QI (measured: half the bias and half the scatter)
        assert bias < 0.75 * table[(m, "1d-quadratic")][0]
        assert scatter < 0.75 * table[(m, "1d-quadratic")][1]
    # CFI (cyclic covariance, no apodisation) is the least accurate (measured 3x the bias)
    best = max(table[("sdf", "2d-quadratic")][0], table[("adf2", "2d-quadratic")][0])
    assert table[("cfi", "2d-quadratic")][0] > 2.0 * best


@pytest.mark.parametrize("method", METHODS)
def test_exact_integer_shifts_are_found(method):
    spec = _blurred_spectrum(seed=4)
    offs = [(30, 40), (70, 20)]
    ref = _cut(_shifted(spec, 0, 0), offs)
    live = _cut(np.roll(_shifted(spec, 0, 0), (-1, 2), axis=(0, 1)), offs)
    r = measure_shifts(ref, live, method=method, max_shift=3,
                       window=WIN if method != "cfi" else N_IMG)
    np.testing.assert_array_equal(r.integer, [[2, -1], [2, -1]])
    assert not r.at_edge.any()


def test_normalize_removes_the_bias_mismatch():
    # a live image 20 % brighter than its reference (another subaperture's vignetting):
    # raw SDF mistakes intensity for structure; normalised, the shift is as without it
    spec = _blurred_spectrum(seed=2)
    offs = np.random.default_rng(1).integers(0, N_SCENE - N_IMG, size=(8, 2))
    ref = _cut(_shifted(spec, 0, 0), offs)
    live = _cut(_shifted(spec, 0.3, -0.2), offs)
    truth = np.array([0.3, -0.2])
    raw = measure_shifts(ref, 1.2 * live, max_shift=2).shifts
    norm = measure_shifts(ref, 1.2 * live, max_shift=2, normalize=True).shifts
    # scale-free: the same bits up to rounding as the unscaled live image, normalised
    np.testing.assert_allclose(
        norm, measure_shifts(ref, live, max_shift=2, normalize=True).shifts, atol=1e-9)
    # within the 2QI bias (measured 0.05 px max on these 8 subfields; 0.03 px on the
    # 12 of the bias test), while raw SDF is lost (measured 3.3 px: an edge of the range)
    assert np.abs(norm - truth).max() < 0.08
    assert np.abs(raw - truth).max() > 0.5


def _discrete_law(ref, nph):
    """1-D linearised SDF + quadratic-interpolation noise (module docstring)."""
    r0 = (N_IMG - WIN) // 2
    c = ref[r0:r0 + WIN, r0:r0 + WIN]
    rp = ref[r0:r0 + WIN, r0 + 1:r0 + WIN + 1]
    rm = ref[r0:r0 + WIN, r0 - 1:r0 + WIN - 1]
    d = (rp - rm) / 2.0
    a = ((c - rp) ** 2 + (c - rm) ** 2).sum()
    return np.sqrt(4.0 * ((c / nph) * d ** 2).sum() / a ** 2)


def _noisy_sd(ref, nph, method, rng, m=1000):
    live = rng.poisson(nph * np.broadcast_to(ref, (m,) + ref.shape)).astype(float) / nph
    r = measure_shifts(ref, live, method=method, max_shift=2,
                       window=WIN if method != "cfi" else N_IMG)
    return r.shifts[:, 0].std()


def test_noise_matches_linearised_law():
    rng = np.random.default_rng(7)
    for seed, (a, b) in ((1, (40, 50)), (2, (10, 90))):
        ref = _shifted(_blurred_spectrum(seed), 0, 0)[a:a + N_IMG, b:b + N_IMG]
        for nph in (1e3, 1e4):
            sd = _noisy_sd(ref, nph, "sdf", rng)
            assert sd == pytest.approx(_discrete_law(ref, nph), rel=0.15)
            # the library's law (both axes) equals the one written here
            lib = sdf_noise_rms(ref * nph, ref * nph, max_shift=2, window=WIN)
            assert lib[0] == pytest.approx(_discrete_law(ref, nph), rel=1e-12)
            assert lib[1] == pytest.approx(_discrete_law(ref.T.copy(), nph), rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_noise_scales_with_photons_and_contrast(method):
    rng = np.random.default_rng(11)
    a, b = 40, 50
    ref = _shifted(_blurred_spectrum(1, 0.15), 0, 0)[a:a + N_IMG, b:b + N_IMG]
    low = _shifted(_blurred_spectrum(1, 0.075), 0, 0)[a:a + N_IMG, b:b + N_IMG]
    # 600 draws each: a ratio of two rms has a sampling error of 4 %
    s1 = _noisy_sd(ref, 1e3, method, rng, m=600)
    s4 = _noisy_sd(ref, 4e3, method, rng, m=600)
    sc = _noisy_sd(low, 4e3, method, rng, m=600)
    assert s1 / s4 == pytest.approx(2.0, rel=0.15)   # 1 / sqrt(photons)
    assert sc / s4 == pytest.approx(2.0, rel=0.15)   # 1 / contrast


def _surfaces_loop(refs, images, r0, c0, win, lag, squared):
    n = images.shape[0]
    out = np.empty((n, 2 * lag + 1, 2 * lag + 1))
    for k in range(n):
        r = refs[k if refs.shape[0] > 1 else 0]
        for iy, dy in enumerate(range(-lag, lag + 1)):
            for ix, dx in enumerate(range(-lag, lag + 1)):
                d = [images[k, r0 + y, c0 + x] - r[r0 + y - dy, c0 + x - dx]
                     for y in range(win) for x in range(win)]
                out[k, iy, ix] = (sum(v * v for v in d) if squared
                                  else sum(abs(v) for v in d) ** 2)
    return out


@nb.njit
def _call_in_njit(refs, images, r0, c0, win, lag, squared, out):
    _shift_kernels.difference_surfaces(refs, images, r0, c0, win, lag, squared, out)


@pytest.mark.parametrize("squared", [True, False])
@pytest.mark.parametrize("n_ref", [1, 3])
def test_kernel_against_python_loop(squared, n_ref):
    rng = np.random.default_rng(3)
    images = rng.normal(size=(3, 10, 11))
    refs = rng.normal(size=(n_ref, 10, 11))
    want = _surfaces_loop(refs, images, 3, 3, 4, 2, squared)
    out = np.empty_like(want)
    _shift_kernels.difference_surfaces(refs, images, 3, 3, 4, 2, squared, out)
    np.testing.assert_allclose(out, want, rtol=1e-12)
    out2 = np.empty_like(want)
    _call_in_njit(refs, images, 3, 3, 4, 2, squared, out2)
    np.testing.assert_array_equal(out2, out)


def test_validation():
    ref = np.ones((12, 12))
    with pytest.raises(ValueError, match="`method` must be one of"):
        measure_shifts(ref, ref, method="xcorr")
    with pytest.raises(ValueError, match="`interpolation` must be one of"):
        measure_shifts(ref, ref, interpolation="spline")
    with pytest.raises(ValueError, match="`max_shift` must be an int >= 1; got 0"):
        measure_shifts(ref, ref, max_shift=0)
    with pytest.raises(ValueError, match=r"`window` must be an int in \[3, 4\]"):
        measure_shifts(ref, ref, max_shift=3, window=8)
    with pytest.raises(ValueError, match=r"`window` must be an int in \[9, 12\]"):
        measure_shifts(ref, ref, method="cfi", max_shift=3, window=8)
    with pytest.raises(ValueError, match="must have the same"):
        measure_shifts(ref, np.ones((10, 12)))
    with pytest.raises(ValueError, match="must hold 1 image or one per image"):
        measure_shifts(np.ones((2, 12, 12)), np.ones((3, 12, 12)))
    bad = ref.copy()
    bad[2, 2] = np.nan
    with pytest.raises(ValueError, match="`images` must be finite"):
        measure_shifts(ref, bad)
    with pytest.raises(ValueError, match=r"`reference` must be \(H, W\) or"):
        measure_shifts(np.ones(5), ref)
    with pytest.raises(ValueError, match="`images` must have a positive mean"):
        measure_shifts(ref, -ref, normalize=True)
    with pytest.raises(TypeError, match="`normalize` must be a bool"):
        measure_shifts(ref, ref, normalize="yes")
    with pytest.raises(TypeError, match="`images` must be a real numeric array"):
        measure_shifts(ref, np.full((12, 12), "a"))


def test_noise_law_validation():
    ref = np.ones((12, 12))
    with pytest.raises(ValueError, match=r"`reference` must be one \(H, W\) image"):
        sdf_noise_rms(np.ones((2, 12, 12)), 1.0)
    with pytest.raises(ValueError, match="`noise_variance` must be finite and >= 0"):
        sdf_noise_rms(ref, -1.0)
    with pytest.raises(ValueError, match=r"`window` must be an int in \[3, 4\]"):
        sdf_noise_rms(ref, 1.0, max_shift=3, window=6)


@pytest.mark.slow
def test_noise_law_many_fields_and_levels():
    """Slow tier: the SDF noise law on 3 scenes x 3 fields x 3 photon levels, 3000 draws
    each (rms sampling error 1.3 %); ADF^2's ratio to the same law is printed."""
    rng = np.random.default_rng(21)
    for seed in (1, 2, 3):
        blurred = _shifted(_blurred_spectrum(seed), 0, 0)
        for a, b in ((10, 10), (40, 90), (95, 50)):
            ref = blurred[a:a + N_IMG, b:b + N_IMG]
            for nph in (3e2, 3e3, 3e4):
                sd = _noisy_sd(ref, nph, "sdf", rng, m=3000)
                law = sdf_noise_rms(ref * nph, ref * nph, max_shift=2, window=WIN)[0]
                assert sd == pytest.approx(law, rel=0.15)
                print(seed, a, b, nph, round(sd / law, 3),
                      round(_noisy_sd(ref, nph, "adf2", rng, m=3000) / law, 3))


@pytest.mark.parametrize(("method", "largest"), [("sdf", 1), ("adf2", 1), ("cfi", 2)])
def test_search_range_too_large_names_max_shift(method, largest):
    # 8x8 images: a difference method needs a window of >= 3 px inside the +-(s+1) search,
    # 8 - 2 (s + 1) >= 3, so s <= 1; the FFT method a window of 2 (s + 1) + 1 <= 8, s <= 2
    im = np.random.default_rng(0).random((8, 8))
    measure_shifts(im, im[None], max_shift=largest, method=method)
    with pytest.raises(ValueError, match=rf"`max_shift` = {largest + 1} is too large .* "
                                         rf"must be <= {largest}\."):
        measure_shifts(im, im[None], max_shift=largest + 1, method=method)
    with pytest.raises(ValueError, match=r"`max_shift` = 2 is too large .* must be <= 1\."):
        sdf_noise_rms(im, 1.0, max_shift=2)


def test_sdf_1qi_recovers_known_subpixel_shifts():
    spec = _blurred_spectrum(seed=1)
    offs = np.random.default_rng(0).integers(0, N_SCENE - N_IMG, size=(6, 2))
    ref = _cut(_shifted(spec, 0, 0), offs)
    worst = 0.0
    for s in np.linspace(-1.0, 1.0, 9):
        live = _cut(_shifted(spec, s, 0.37 * s), offs)
        r = measure_shifts(ref, live, method="sdf", interpolation="1d-quadratic",
                           max_shift=3, window=WIN)
        err = r.shifts - np.array([s, 0.37 * s])
        worst = max(worst, float(np.abs(err.mean(axis=0)).max()))
    assert worst < 0.1, worst


@pytest.mark.filterwarnings("error")
def test_cfi_warns_of_its_bias_and_sdf_does_not():
    # a 1.3-pixel shift (Fourier shift theorem) of blurred granulation: the cyclic
    # covariance of the non-periodic windows reads it short (Loefdahl 2010: the FFT
    # covariance without apodisation suffers from its edges); SDF is silent and close
    spec = _blurred_spectrum(seed=2)
    offs = np.array([[40, 40]])
    ref, live = _cut(_shifted(spec, 0, 0), offs), _cut(_shifted(spec, 1.3, 0), offs)
    with pytest.warns(UserWarning, match=r"method 'cfi' of measure_shifts .* underestimates"):
        cfi = measure_shifts(ref, live, method="cfi", window=N_IMG).shifts[0, 0]
    sdf = measure_shifts(ref, live, method="sdf", window=WIN).shifts[0, 0]
    assert abs(sdf - 1.3) < 0.1 and cfi < sdf


def test_a_constant_reference_has_no_shift():
    # a flat difference surface has no minimum: lag (-3, -3) was returned (audit 9)
    live = _cut(_shifted(_blurred_spectrum(seed=2), 0, 0), np.array([[40, 40]]))
    with pytest.raises(ValueError, match=r"`reference` image 0 is constant"):
        measure_shifts(np.ones_like(live), live)
