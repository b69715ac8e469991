"""Karhunen-Loeve bases.

References: the eigen-equation C V = V diag(lambda) of the Zernike covariance (numpy
``eigvalsh`` as the reference spectrum), Ky Fan's maximum principle (the first k K-L
modes capture at least as much variance as any k Zernikes), sklearn's PCA for the
centred empirical K-L, and the sampling distribution of sample eigenvalues (relative
standard deviation sqrt(2/T) for Gaussian data, Anderson 1963).
"""

import pickle

import numpy as np
import pytest
from sklearn.decomposition import PCA

from modalinfo.bases import (
    KLBasis,
    Pupil,
    ZernikeBasis,
    _kernels,
    default_zernike_modes,
    noll_to_zernike,
    zernike_covariance,
    zernike_variance,
)


@pytest.fixture(scope="module")
def pupil():
    return Pupil(64, diameter=4.0)


def test_default_zernike_modes():
    modes = default_zernike_modes(100)
    assert modes[0] == 2 and modes.size >= 300
    n, _ = noll_to_zernike(modes)
    assert n.max() == 24 and modes[-1] == 325  # complete radial orders 1..24
    assert default_zernike_modes(1).tolist() == [2, 3, 4, 5, 6]
    assert default_zernike_modes(3).tolist() == list(range(2, 11))


def test_default_set_converges(pupil):
    # K-L variances from the default set vs from 860 Zernikes (radial orders <= 40)
    small = Pupil(16)
    for n_modes, tol in ((10, 5e-3), (27, 1e-4)):
        kl = KLBasis.from_turbulence(small, n_modes)
        ref = KLBasis.from_turbulence(small, n_modes, zernike_modes=range(2, 862))
        np.testing.assert_allclose(kl.variances, ref.variances, rtol=tol)


def test_theoretical_kl_diagonalises_covariance(pupil):
    modes = range(2, 67)  # radial orders 1..10
    kl = KLBasis.from_turbulence(pupil, 65, zernike_modes=modes)
    cov = zernike_covariance(modes)
    v, lam = kl.zernike_from_kl, kl.variances
    assert np.all(np.diff(lam) <= 1e-15)
    np.testing.assert_allclose(cov @ v, v * lam, atol=1e-12 * lam.max())
    np.testing.assert_allclose(lam, np.sort(np.linalg.eigvalsh(cov))[::-1], atol=1e-14)
    np.testing.assert_allclose(v.T @ v, np.eye(65), atol=1e-12)
    np.testing.assert_allclose(v @ v.T, np.eye(65), atol=1e-12)
    np.testing.assert_allclose(kl.kl_from_zernike @ kl.zernike_from_kl, np.eye(65), atol=1e-12)
    assert lam.sum() == pytest.approx(np.trace(cov), rel=1e-12)
    assert kl.labels[:3] == ["KL1", "KL2", "KL3"]


def test_kl_beats_zernikes(pupil):
    kl = KLBasis.from_turbulence(pupil, 50)
    zvar = np.sort(zernike_variance(kl.zernike_modes))[::-1]
    assert kl.variances[0] > zvar[0]  # 0.4493 > 0.4489 (tip)
    # Ky Fan: cumulative K-L variance >= cumulative of the best Zernikes, every k
    assert np.all(np.cumsum(kl.variances) >= np.cumsum(zvar[:50]) - 1e-15)
    assert np.cumsum(kl.variances)[9] > np.cumsum(zvar)[9] + 1e-4


def test_int_zernike_modes_excludes_piston(pupil):
    kl = KLBasis.from_turbulence(pupil, 5, zernike_modes=21)
    assert kl.zernike_modes.tolist() == list(range(2, 22))
    with pytest.raises(ValueError, match=r"`zernike_modes` must be an int >= 2; got 1"):
        KLBasis.from_turbulence(pupil, 1, zernike_modes=1)


def test_modes_are_pure_cos_or_sin(pupil):
    kl = KLBasis.from_turbulence(pupil, 40)
    n, m = noll_to_zernike(kl.zernike_modes)
    kind = np.where(m == 0, 0, np.where(kl.zernike_modes % 2 == 0, 1, 2))
    for k in range(40):
        used = np.abs(kl.zernike_from_kl[:, k]) > 1e-12
        assert len(set(zip(np.abs(m[used]), kind[used], strict=True))) == 1
    # KL1/KL2 are tip/tilt-like with positive dominant coefficient
    assert np.argmax(np.abs(kl.zernike_from_kl[:, 0])) == 0
    assert kl.zernike_from_kl[0, 0] > 0.99


def test_pixel_matrix_and_projection(pupil):
    modes = range(2, 37)
    kl = KLBasis.from_turbulence(pupil, 35, zernike_modes=modes)
    zb = ZernikeBasis(pupil, modes)
    np.testing.assert_allclose(kl.matrix, zb.matrix @ kl.zernike_from_kl, atol=1e-13)
    a_z = np.random.default_rng(2).normal(size=(3, 35))
    a_kl = kl.coefficients_from_zernike(a_z)
    np.testing.assert_allclose(kl.zernike_from_coefficients(a_kl), a_z, atol=1e-12)
    # same span (M = n_z): pixel least squares = change of basis
    np.testing.assert_allclose(kl.project(zb.synthesize(a_z)), a_kl, atol=1e-10)
    np.testing.assert_allclose(kl.synthesize(a_kl), zb.synthesize(a_z), atol=1e-12)
    assert kl.coefficients_from_zernike(a_z[0]).shape == (35,)


def test_von_karman_kl(pupil):
    kol = KLBasis.from_turbulence(pupil, 20)
    vk = KLBasis.from_turbulence(pupil, 20, outer_scale=25.0)
    assert np.all(np.diff(vk.variances) <= 1e-15)
    assert vk.variances[0] < 0.8 * kol.variances[0]  # tip/tilt damped by L0 = 6 D
    vk_big = KLBasis.from_turbulence(pupil, 20, outer_scale=1e4)
    assert np.all(np.isfinite(vk_big.variances)) and vk_big.variances[0] < kol.variances[0]


def test_reorder_keeps_kl_attributes(pupil):
    kl = KLBasis.from_turbulence(pupil, 10)
    r = kl.reorder([2, 0, 1])
    assert isinstance(r, KLBasis) and r.labels == ["KL3", "KL1", "KL2"]
    np.testing.assert_array_equal(r.variances, kl.variances[[2, 0, 1]])
    np.testing.assert_array_equal(r.zernike_from_kl, kl.zernike_from_kl[:, [2, 0, 1]])
    np.testing.assert_array_equal(r.matrix, kl.matrix[:, [2, 0, 1]])
    np.testing.assert_array_equal(r.kl_from_zernike, kl.kl_from_zernike[[2, 0, 1]])


def test_empirical_kl_recovers_eigenvalues():
    """Data drawn from N(0, C) with C the Kolmogorov covariance of Z2..Z22.

    For Gaussian data the relative standard deviation of a sample eigenvalue is
    sqrt(2/T) (1% at T = 20000); the tolerance is 5 of them on the worst of the 21
    eigenvalues (observed max over 30 seeds: 3.8).
    """
    modes = range(2, 23)
    cov = zernike_covariance(modes)
    lam = np.sort(np.linalg.eigvalsh(cov))[::-1]
    t = 20000
    rng = np.random.default_rng(11)
    coeffs = rng.standard_normal((t, 21)) @ np.linalg.cholesky(cov).T
    kl = KLBasis.from_data(ZernikeBasis(Pupil(32), modes), coeffs)
    np.testing.assert_allclose(kl.variances, lam, rtol=5 * np.sqrt(2 / t))
    assert np.all(np.diff(kl.variances) <= 0)
    # the leading (well separated from the rest) degenerate pair spans the theory's
    kl_theory = KLBasis.from_turbulence(Pupil(32), 21, zernike_modes=modes)
    overlap = kl.zernike_from_kl[:, :2].T @ kl_theory.zernike_from_kl[:, :2]
    assert np.linalg.svd(overlap, compute_uv=False).min() > 0.99


def test_empirical_kl_non_centred_vs_centred_and_sklearn():
    rng = np.random.default_rng(5)
    zb = ZernikeBasis(Pupil(32), range(2, 12))
    coeffs = rng.normal(size=(500, 10)) * np.linspace(2, 0.2, 10) + 0.3  # static offset
    centred = KLBasis.from_data(zb, coeffs, center=True)
    pca = PCA().fit(coeffs)
    np.testing.assert_allclose(centred.variances, pca.explained_variance_, rtol=1e-10)
    np.testing.assert_allclose(np.abs(centred.zernike_from_kl.T), np.abs(pca.components_),
                               atol=1e-8)
    ms = KLBasis.from_data(zb, coeffs, n_modes=4)
    moment = coeffs.T @ coeffs / 500
    np.testing.assert_allclose(ms.variances, np.sort(np.linalg.eigvalsh(moment))[::-1][:4],
                               rtol=1e-12)
    # mean-square optimum: residual mean square = sum of the dropped eigenvalues
    a_kl = ms.coefficients_from_zernike(coeffs)
    resid = coeffs - ms.zernike_from_coefficients(a_kl)
    dropped = np.sort(np.linalg.eigvalsh(moment))[::-1][4:].sum()
    assert np.mean(np.sum(resid**2, axis=1)) == pytest.approx(dropped, rel=1e-10)


def test_combination_kernel_against_dense_product(pupil):
    # numba kernel (sparse, compressed columns) vs numpy Z @ V with a sparse random V
    rng = np.random.default_rng(4)
    modes = np.arange(1, 56)
    v = rng.normal(size=(55, 7)) * (rng.uniform(size=(55, 7)) < 0.3)
    v[:, 3] = 0.0  # an empty column
    z = ZernikeBasis(pupil, modes).matrix
    n, m = noll_to_zernike(modes)
    counts = (v != 0).sum(axis=0)
    indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    rows, cols = np.nonzero((v != 0).T)
    out = np.empty((pupil.n_valid, 7))
    cos_t, sin_t = pupil.direction_cosines()
    _kernels.zernike_combination_matrix(pupil.rho_valid, cos_t, sin_t, n, m, indptr,
                                        cols.astype(np.int64), v.T[rows, cols].copy(), out)
    np.testing.assert_allclose(out, z @ v, atol=1e-12)
    # the theoretical K-L pixel matrix (kernel path) equals the Zernike matrix product
    kl = KLBasis.from_turbulence(pupil, 30)
    np.testing.assert_allclose(kl.matrix, kl.zernike_basis.matrix @ kl.zernike_from_kl,
                               atol=1e-12)


def test_pickle_round_trip(pupil):
    kl = KLBasis.from_turbulence(pupil, 10)
    back = pickle.loads(pickle.dumps(kl))
    np.testing.assert_array_equal(back.matrix, kl.matrix)
    np.testing.assert_array_equal(back.variances, kl.variances)
    assert back.labels == kl.labels and back.pupil == pupil
    phase = kl.synthesize(np.arange(10.0))
    np.testing.assert_allclose(back.project(phase), np.arange(10.0), atol=1e-9)


def test_bad_inputs(pupil):
    zb = ZernikeBasis(pupil, range(2, 8))
    with pytest.raises(ValueError, match=r"`n_modes` must be <= the number of Zernike modes \(6\)"):
        KLBasis.from_turbulence(pupil, 7, zernike_modes=range(2, 8))
    with pytest.raises(ValueError, match=r"`n_modes` must be an int >= 1; got 0"):
        KLBasis.from_turbulence(pupil, 0)
    with pytest.raises(ValueError, match=r"must not contain piston"):
        KLBasis.from_turbulence(pupil, 3, zernike_modes=range(1, 8))
    with pytest.raises(TypeError, match="`pupil` must be a modalinfo.bases.Pupil"):
        KLBasis.from_turbulence(64, 3)
    with pytest.raises(ValueError, match=r"`coeffs` must have n_z=6 columns"):
        KLBasis.from_data(zb, np.zeros((10, 5)))
    with pytest.raises(ValueError, match=r"`coeffs` must be finite"):
        KLBasis.from_data(zb, np.full((10, 6), np.nan))
    with pytest.raises(ValueError, match=r"`coeffs` needs at least 2 samples"):
        KLBasis.from_data(zb, np.zeros((1, 6)))
    with pytest.raises(ValueError, match=r"`n_modes` must be an int <= 6; got 7"):
        KLBasis.from_data(zb, np.ones((10, 6)), n_modes=7)
    with pytest.raises(TypeError, match="`zbasis` must be a ZernikeBasis"):
        KLBasis.from_data(None, np.ones((10, 6)))
    kl = KLBasis.from_data(zb, np.random.default_rng(0).normal(size=(20, 6)))
    with pytest.raises(ValueError, match=r"`a_z` must have last axis of length n_z=6"):
        kl.coefficients_from_zernike(np.zeros(5))
    with pytest.raises(ValueError, match=r"`a_kl` must have last axis of length n_modes=6"):
        kl.zernike_from_coefficients(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="`zernike_from_kl` must have orthonormal columns"):
        KLBasis(zb, np.ones((6, 2)), [1.0, 1.0])


def test_more_kl_modes_than_the_grid_resolves_are_refused():
    # audit 9, centre: from_turbulence(Pupil(32), 1000) built 1000 "modes" on 812 pixels.
    # Reference: K-L mode k resolves like Noll Zernike k + 1, whose radial order n must
    # be <= pixels / 2 (Nyquist); on 32 pixels order 16 closes at Noll 17 * 18 / 2 = 153
    assert KLBasis.from_turbulence(Pupil(32), 152).n_modes == 152
    for n_modes in (153, 1000):
        with pytest.raises(ValueError, match=rf"`n_modes` = {n_modes} K-L modes need a finer"):
            KLBasis.from_turbulence(Pupil(32), n_modes)
def test_default_zernike_modes_refuses_counts_beyond_any_basis():
    """Audit 9: n_modes = 2**70 spun 2^35 steps of the radial-order loop (a hang)."""
    from modalinfo.bases import default_zernike_modes

    assert default_zernike_modes(5)[-1] == 21  # 3 x 5 = 15 <= 20 modes after piston (n <= 5)
    with pytest.raises(ValueError, match="`n_modes` must be an int <= 1000000"):
        default_zernike_modes(2**70)
