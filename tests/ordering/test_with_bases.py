"""Orderings and fitting errors on the package's Zernike and K-L bases and logs.

References: Noll (1976) Kolmogorov Zernike covariance (``zernike_covariance``), whose
eigenvectors (the theoretical K-L basis) minimise the expected truncation error
(Karhunen-Loeve / Eckart-Young): the expected curve is computed exactly by feeding the
rows of sqrt(M) L^T (C = L L^T) as frames, and a seeded open-loop sample is checked
too; unit conversion (rad = 2 pi OPD / lambda) through ``ModalLog.to_units``; change
of basis (K-L coefficients from Zernike ones) against ``KLBasis.coefficients_from_zernike``;
the pupil-sampling rule (``n_pixels >= 2 n``) against the radial order ``n`` of an index
from the conventions' definitions (Noll 1976: order ``n`` holds ``j`` in
``(n (n + 1) / 2, (n + 1)(n + 2) / 2]``; ANSI Z80.28: ``[n (n + 1) / 2, (n + 1)(n + 2) / 2)``).
"""

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis, zernike_covariance
from modalinfo.ordering import fitting_error, order_modes
from modalinfo.telemetry import ModalLog

# these coarse pupils serve other checks; fitting_error's note on them
# (PupilSamplingWarning) is tested in tests/ordering/test_fixes33a.py
pytestmark = pytest.mark.filterwarnings(
    "ignore::modalinfo.ordering.fitting_error.PupilSamplingWarning")

MODES = list(range(2, 29))


@pytest.fixture(scope="module")
def bases():
    pupil = Pupil(24)
    return ZernikeBasis(pupil, MODES), KLBasis.from_turbulence(pupil, 27, zernike_modes=MODES)


@pytest.fixture(scope="module")
def kolmogorov():
    cov = zernike_covariance(MODES) * 20.0 ** (5 / 3)  # D/r0 = 20, rad^2
    rng = np.random.default_rng(0)
    return cov, rng.multivariate_normal(np.zeros(27), cov, size=2000)


def test_theoretical_kl_beats_standard_zernike_in_expectation(bases, kolmogorov):
    zb, kl = bases
    cov, _ = kolmogorov
    lower = np.linalg.cholesky(cov)
    frames = np.sqrt(27) * lower.T  # mean over these rows of a a^T is exactly cov
    z_curve = fitting_error(frames, zb).mean
    kl_curve = fitting_error(kl.coefficients_from_zernike(frames), kl).mean
    assert np.all(kl_curve <= z_curve + 1e-9 * z_curve[0])
    # the K-L gain grows with n: at n = 20, over 25 % less residual than Zernike
    assert kl_curve[19] < 0.75 * z_curve[19]


def test_open_loop_sample_kl_and_mi(bases, kolmogorov):
    zb, kl = bases
    _, a = kolmogorov
    log = ModalLog(a, rate=1000.0, modes=MODES, units="rad", wavelength=500e-9)
    z_std = fitting_error(log, zb).mean
    kl_var = fitting_error(log, kl, order_modes(log, kl, "variance")).mean
    # sampling noise: 2000 frames, tolerance 2 % of the curve
    assert np.all(kl_var <= 1.02 * z_std)
    # MI-ordered Zernikes (greedy, histogram) on open-loop Kolmogorov data: they follow
    # the variance order closely, so the curve stays within 3 % of the standard order
    # (measured: ratio 0.93-1.00 at every n with 100k samples)
    mi = order_modes(log, zb, "mi_greedy", sample_budget=30_000, seed=0, n_resamples=0)
    z_mi = fitting_error(log, zb, mi).mean
    assert np.all(z_mi[:-1] <= 1.03 * z_std[:-1])
    assert set(mi.labels[:3]) == {"Z2", "Z3", "Z4"} or set(mi.labels[:2]) == {"Z2", "Z3"}


def test_log_units_and_kl_change_of_basis(bases):
    zb, kl = bases
    rng = np.random.default_rng(1)
    a_rad = rng.standard_normal((50, 27)) * 0.3
    wavelength = 600e-9
    nm = a_rad * wavelength / (2 * np.pi) * 1e9
    log_nm = ModalLog(nm, modes=MODES, units="nm", wavelength=wavelength)
    ref = fitting_error(a_rad, zb)
    via_log = fitting_error(log_nm, zb)
    np.testing.assert_allclose(via_log.per_frame, ref.per_frame, rtol=1e-10)
    no_lambda = ModalLog(nm, modes=MODES, units="nm")
    np.testing.assert_allclose(
        fitting_error(no_lambda, zb, wavelength=wavelength).per_frame, ref.per_frame, rtol=1e-10)
    # K-L: the log's Zernike coefficients go through coefficients_from_zernike
    via_kl = fitting_error(log_nm, kl)
    direct = fitting_error(kl.coefficients_from_zernike(a_rad), kl)
    np.testing.assert_allclose(via_kl.per_frame, direct.per_frame, rtol=1e-10)
    # Phi_ref is the same wavefront in both bases (27 K-L modes span the 27 Zernikes)
    np.testing.assert_allclose(via_kl.total, ref.total, rtol=1e-8)
    # columns of the log matched by Noll index, whatever their order in the file
    shuffled = ModalLog(a_rad[:, ::-1], modes=MODES[::-1], units="rad")
    np.testing.assert_allclose(fitting_error(shuffled, zb).per_frame, ref.per_frame)


def test_apply_and_reordered_basis(bases):
    zb, _ = bases
    rng = np.random.default_rng(2)
    a = rng.standard_normal((100, 27)) * np.linspace(0.1, 1.0, 27)  # Z28 largest
    log = ModalLog(a, modes=MODES, units="rad")
    res = order_modes(log, zb, "variance")
    assert res.labels[0] == "Z28"
    reordered = res.apply(zb)
    assert list(reordered.labels) == list(res.labels)
    # the reordered basis in standard order gives the same curve as the ordering
    np.testing.assert_allclose(fitting_error(log, reordered).mean,
                               fitting_error(log, zb, res).mean, rtol=1e-10)
    with pytest.raises(ValueError, match="`basis` labels must match"):
        res.apply(reordered)
    with pytest.raises(ValueError, match="`basis` must have the 27 modes"):
        res.apply(ZernikeBasis(zb.pupil, range(2, 10)))


def test_log_missing_modes(bases):
    zb, _ = bases
    log = ModalLog(np.ones((5, 3)), modes=[2, 3, 4], units="rad")
    with pytest.raises(ValueError, match="lacks the Zernike modes the basis needs"):
        fitting_error(log, zb)


def test_data_kl_pca_is_the_floor_on_a_log(bases):
    zb, _ = bases
    rng = np.random.default_rng(3)
    mix = rng.standard_normal((27, 27)) * np.linspace(1, 0.1, 27)
    a = rng.standard_normal((400, 27)) @ mix
    log = ModalLog(a, modes=MODES, units="rad")
    ortho = ZernikeBasis(zb.pupil, MODES, orthonormalize=True)
    data_kl = KLBasis.from_data(ortho, a)
    pca = fitting_error(log, data_kl, order_modes(log, data_kl, "pca")).mean
    for method in ("standard", "variance"):
        other = fitting_error(log, ortho, order_modes(log, ortho, method)).mean
        assert np.all(pca <= other * (1 + 1e-9) + 1e-12)


def test_parseval_equals_pixels_on_orthonormalised_zernikes():
    zb = ZernikeBasis(Pupil(32), MODES, orthonormalize=True)
    rng = np.random.default_rng(4)
    a = rng.standard_normal((30, 27)) * np.linspace(1, 0.1, 27)
    order = rng.permutation(27)
    parseval = fitting_error(a, zb, order)
    assert parseval.method == "parseval"
    pixels = fitting_error(a, zb, order, method="pixels")
    np.testing.assert_allclose(parseval.per_frame, pixels.per_frame, rtol=1e-9, atol=1e-12)
    # the plain sampled Zernikes are not orthonormal on a 32-pixel grid: Gram form used
    plain = ZernikeBasis(Pupil(32), MODES)
    assert fitting_error(a, plain).method == "gram"
    np.testing.assert_allclose(fitting_error(a, plain, order).per_frame,
                               fitting_error(a, plain, order, method="pixels").per_frame,
                               rtol=1e-9, atol=1e-12)


def test_pupil_sampling_rule_reads_the_labels_in_their_convention():
    from modalinfo.ordering.compare import check_pupil_sampling

    # label 1485 = 54 x 55 / 2: the last Noll mode of order 53, the first ANSI one of order 54
    check_pupil_sampling([2, 3, 1485], 106)  # Noll: 2 x 53 pixels suffice
    with pytest.raises(ValueError, match=r"`n_pixels` must be >= 106 .*radial order 53.* got 105"):
        check_pupil_sampling([2, 3, 1485], 105)
    check_pupil_sampling([1, 2, 1485], 108, convention="ansi")
    with pytest.raises(ValueError, match=r"`n_pixels` must be >= 108 .*radial order 54.* got 106"):
        check_pupil_sampling([1, 2, 1485], 106, convention="ansi")
