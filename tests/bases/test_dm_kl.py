"""DM-space K-L modes.

References (outside the code): the von Karman structure function as the Hankel
integral of its PSD, ``D(r) = 4 pi int_0^inf f W(f) (1 - J0(2 pi f r)) df`` (scipy
quadrature); the piston-removed pixel covariance formed densely from that structure
function (``scipy.spatial.distance.cdist``) on a tiny grid, against which the
projection (its separable and FFT paths, within the worst-case rounding of the dense
sums; the columns copied by a symmetry of the pupil, whose premise, the dense matrix's
invariance under each permutation found, is checked on the dense matrix itself) and the
diagonalisation are checked; the DM's own least-squares fits of
``x`` and ``y`` (tip/tilt apart); the library's theoretical K-L
(``KLBasis.from_turbulence``: Noll/Wang-Markey covariance integrals) and Noll's tip
variance (``zernike_variance``) for the low orders the DM represents.
"""

import numpy as np
import pytest
from scipy import integrate, special
from scipy.spatial.distance import cdist

from modalinfo.bases import (
    DMKLBasis,
    InfluenceFunctions,
    KLBasis,
    MaskedPupil,
    Pupil,
    dm_kl_modes,
    von_karman_structure_function,
    zernike_variance,
)
from modalinfo.bases import dm_kl as dm_kl_module

R0, L0 = 0.2, 20.0


def _psd_structure_function(r, r0, l0):
    """Hankel integral of the von Karman PSD (cycles/m).

    ``int f W (1 - J0)``: the smooth part ``int f W`` over ``[F, inf)`` and the Bessel
    part over panels up to ``F = 2000 / r`` (beyond, its envelope is below 1e-9 of D).
    """
    c = (special.gamma(11 / 6) ** 2 / (2 * np.pi ** (11 / 3))
         * (24 / 5 * special.gamma(6 / 5)) ** (5 / 6))

    def w(f):
        return f * c * r0 ** (-5 / 3) * (f * f + l0 ** -2) ** (-11 / 6)

    big = 2000.0 / r
    edges = np.concatenate([[0.0], np.geomspace(1e-4 / r, 10.0 / r, 40),
                            np.arange(20.0, 2001.0, 10.0) / r])
    total = sum(integrate.quad(lambda f: w(f) * (1 - special.j0(2 * np.pi * f * r)), a, b,
                               limit=200)[0] for a, b in zip(edges[:-1], edges[1:], strict=True))
    total += integrate.quad(w, big, np.inf, limit=200)[0]
    return 4 * np.pi * total


@pytest.mark.parametrize("r", [0.01, 0.3, 3.0, 30.0])
def test_von_karman_structure_function_is_its_psd_integral(r):
    assert von_karman_structure_function(r, R0, L0) == pytest.approx(
        _psd_structure_function(r, R0, L0), rel=1e-5)


def test_kolmogorov_limit():
    r = np.array([0.01, 0.1, 1.0])
    assert np.allclose(von_karman_structure_function(r, R0),
                       6.883877 * (r / R0) ** (5 / 3), rtol=1e-6)


@pytest.fixture(scope="module")
def mirror():
    # 9 x 9 actuators on 32 pixels: the centre actuator is whole (separable path), the
    # rest are cut by the rim (one FFT column each)
    return InfluenceFunctions(Pupil(32, 4.0), 9)


@pytest.fixture(scope="module")
def dense_prior(mirror):
    """``S = M^T C_phi M / n^2`` from the dense piston-removed pixel covariance."""
    p = mirror.pupil
    xy = np.column_stack([p.x[p.mask], p.y[p.mask]])
    d = von_karman_structure_function(cdist(xy, xy), R0, L0)
    n = xy.shape[0]
    proj = np.eye(n) - 1.0 / n
    cov = -0.5 * proj @ d @ proj
    m = mirror.matrix.toarray()
    return m.T @ cov @ m / n ** 2


def _dense_structure(f):
    p = f.pupil
    xy = np.column_stack([p.x[p.mask], p.y[p.mask]])
    m = f.matrix.toarray()
    return m.T @ von_karman_structure_function(cdist(xy, xy), R0, L0) @ m


def test_fft_projection_equals_dense(mirror, dense_prior):
    s = dm_kl_module._command_prior(mirror, R0, L0)
    assert np.max(np.abs(s - dense_prior)) <= 1e-10 * np.max(np.abs(dense_prior))


def _sum_bound(f):
    """Worst-case relative rounding of the dense reference, per entry.

    Every term of ``M^T D M`` is >= 0 (Gaussian influence, ``D >= 0``), so an entry's
    rounding is at most ``gamma_k = k eps`` of the entry itself for sums of ``k`` terms:
    two products over the ``n`` pupil pixels give ``2 n eps``; the separable path sums
    fewer, shorter terms (``W^2 + W`` per pair, ``W ~ 10-40``).
    """
    return 2 * f.pupil.n_valid * np.finfo(float).eps


@pytest.mark.parametrize("n_pix, n_act, pitch_px, obscuration", [
    (48, 13, 4.0, 0.0),  # pitch 4 px: the interior actuators are whole-pixel translates
    (48, 14, 3.5, 0.0),  # pitch 3.5 px: two sub-pixel classes
    # the 60" altitude DM's 4.015 px (no two actuators alike), and a central
    # obscuration that cuts actuators inside the disc too
    (56, 15, 4.0146, 0.15),
])
def test_separable_path_equals_dense(n_pix, n_act, pitch_px, obscuration):
    f = InfluenceFunctions(Pupil(n_pix, 4.0, obscuration), n_act, pitch_px * 4.0 / n_pix)
    whole = dm_kl_module._whole_actuators(f)
    # both paths are taken: pairs of whole actuators (separable) and cut columns (FFT)
    assert 0 < whole.sum() < f.n_valid
    ref = _dense_structure(f)
    g_d = dm_kl_module._structure_operator(f, R0, L0)[0]
    assert np.array_equal(g_d, g_d.T)
    assert np.all(np.abs(g_d - ref) <= _sum_bound(f) * ref)
    # the FFT-only path (the reference before the separable one): rounding of the
    # transforms is relative to the largest entry, not to each entry
    g_fft = dm_kl_module._structure_operator(f, R0, L0, separable=False)[0]
    assert np.max(np.abs(g_fft - ref)) <= _sum_bound(f) * np.max(ref)


def test_the_symmetries_keep_the_dense_projection():
    # the premise of the copied columns, against the dense reference: each permutation
    # found maps M^T D M onto itself (entry by entry, within the reference's rounding);
    # a centred disc keeps all 7 (flips and the exchange of x and y)
    f = InfluenceFunctions(Pupil(40, 4.0), 11, 3.7 * 4.0 / 40)
    perms = dm_kl_module._symmetries(f)
    assert len(perms) == 7
    ref = _dense_structure(f)
    for perm in perms:
        assert not np.array_equal(perm, np.arange(f.n_valid))
        assert np.all(np.abs(ref[np.ix_(perm, perm)] - ref) <= 2 * _sum_bound(f) * ref)


def test_an_asymmetric_pupil_keeps_only_its_symmetries():
    # a disc with a notch at the top: only the flip of x is left, and the projection (one
    # FFT column per cut actuator pair {a, flipped a}) is still the dense one
    mask = np.asarray(Pupil(40, 4.0).mask).copy()
    mask[:8, 14:26] = False
    f = InfluenceFunctions(MaskedPupil(mask, 4.0), 11, 3.7 * 4.0 / 40)
    perms = dm_kl_module._symmetries(f)
    assert len(perms) == 1
    grid = f.valid_index
    ay, ax = grid // 11, grid % 11
    assert np.array_equal(ay[perms[0]], ay) and np.array_equal(ax[perms[0]], 10 - ax)
    ref = _dense_structure(f)
    g_d = dm_kl_module._structure_operator(f, R0, L0)[0]
    assert np.all(np.abs(g_d - ref) <= _sum_bound(f) * ref)


def test_whole_actuators_are_the_unmasked_ones():
    # the criterion against its definition: an actuator is whole iff its column of the
    # influence matrix holds its whole separable footprint (its nnz equals the product of
    # the 1-D factor's non-zeros along x and y)
    f = InfluenceFunctions(Pupil(40, 4.0, 0.25), 11, 3.7 * 4.0 / 40)
    whole = dm_kl_module._whole_actuators(f)
    nnz_1d = np.count_nonzero(f.factor, axis=0)
    grid = f.valid_index
    footprint = nnz_1d[grid // f.n_actuators] * nnz_1d[grid % f.n_actuators]
    assert np.array_equal(whole, np.diff(f.matrix.tocsc().indptr) == footprint)


@pytest.mark.parametrize("apart", [True, False])
def test_modes_orthonormal_and_diagonal(mirror, dense_prior, apart):
    m2c, var = dm_kl_modes(mirror, R0, L0, tip_tilt_apart=apart)
    assert m2c.shape == (mirror.n_valid, mirror.n_valid - 1)
    g = mirror.gram()
    assert np.max(np.abs(m2c.T @ g @ m2c - np.eye(m2c.shape[1]))) <= 1e-10
    cov = m2c.T @ dense_prior @ m2c
    first = 2 if apart else 0
    block = cov[first:, first:]
    off = block - np.diag(np.diag(block))
    assert np.max(np.abs(off)) <= 1e-6 * var.max()
    assert np.allclose(np.diag(cov), var, rtol=1e-8, atol=1e-12 * var.max())
    assert np.all(np.diff(var[first:]) <= 1e-12 * var.max())
    if apart:
        assert var[0] >= var[2] and var[1] >= var[2]
        assert abs(cov[0, 1]) <= 1e-6 * var.max()  # x and y: uncorrelated by symmetry


def test_piston_free_and_tip_tilt_are_the_dms_best_fit(mirror):
    m2c, _ = dm_kl_modes(mirror, R0, L0)
    surf = mirror.surface(m2c.T)  # (M, n)
    assert np.max(np.abs(surf.mean(axis=1))) <= 1e-12
    p = mirror.pupil
    for k, target in enumerate((p.x[p.mask], p.y[p.mask])):
        best = mirror.surface(mirror.fit(target))
        best -= best.mean()
        best /= np.sqrt(np.mean(best ** 2))
        assert np.max(np.abs(surf[k] - best)) <= 1e-10
        # modes >= 3 carry no tip/tilt
        assert np.max(np.abs(surf[2:] @ target)) <= 1e-10 * np.sqrt(np.sum(target ** 2))


def test_piston_free_without_tip_tilt_apart(mirror):
    # every mode is DM-orthogonal to the DM's least-squares piston, so its surface has
    # zero pupil mean: m^T G G^-1 M^T 1 / n = mean(M m)
    m2c, _ = dm_kl_modes(mirror, R0, L0, tip_tilt_apart=False)
    surf = mirror.surface(m2c.T)
    assert np.max(np.abs(surf.mean(axis=1))) <= 1e-12


def test_low_orders_match_the_theoretical_kl():
    pupil = Pupil(64, 4.0)
    f = InfluenceFunctions(pupil, 16)
    r0 = pupil.diameter  # variances in units of (D/r0)^(5/3)
    _, var = dm_kl_modes(f, r0, 25.0, n_modes=15, tip_tilt_apart=False)
    theory = KLBasis.from_turbulence(pupil, 15, outer_scale=25.0).variances
    # measured within 0.7 % for the first 20 modes at 17 actuators across
    assert np.allclose(var[:10], theory[:10], rtol=0.02)
    _, var_tt = dm_kl_modes(f, r0, 25.0, n_modes=3)
    noll_tip = zernike_variance([2], outer_scale=25.0, diameter=4.0)[0]
    assert var_tt[0] == pytest.approx(noll_tip, rel=0.01)
    assert var_tt[1] == pytest.approx(noll_tip, rel=0.01)


def test_basis_is_a_modal_basis(mirror):
    b = DMKLBasis.from_influence(mirror, R0, L0, n_modes=20)
    assert b.n_modes == 20 and b.labels[0] == "DMKL1"
    assert np.allclose(b.gram(), np.eye(20), atol=1e-10)
    coeffs = np.random.default_rng(0).standard_normal(20)
    assert np.allclose(b.project(b.synthesize(coeffs)), coeffs, atol=1e-10)
    order = np.arange(20)[::-1]
    r = b.reorder(order)
    assert np.array_equal(r.m2c, b.m2c[:, order])
    assert np.array_equal(r.variances, b.variances[order])
    assert np.allclose(r.matrix, mirror.matrix @ r.m2c, atol=1e-14)


def test_fewer_modes_same_variances(mirror):
    # the first n_modes from a partial eigen-decomposition (MRRR subset) against all
    m2c_all, var_all = dm_kl_modes(mirror, R0, L0)
    for apart in (True, False):
        m2c, var = dm_kl_modes(mirror, R0, L0, n_modes=12, tip_tilt_apart=apart)
        full = var_all if apart else dm_kl_modes(mirror, R0, L0, tip_tilt_apart=False)[1]
        assert np.allclose(var, full[:12], rtol=1e-9, atol=1e-12 * full.max())
        assert np.max(np.abs(m2c.T @ mirror.gram() @ m2c - np.eye(12))) <= 1e-10
    # tip and tilt do not depend on the prior's decomposition: the same strokes
    assert np.allclose(m2c_all[:, :2], dm_kl_modes(mirror, R0, L0, n_modes=12)[0][:, :2],
                       atol=1e-12)


def test_same_inputs_same_bits(mirror):
    a = dm_kl_modes(mirror, R0, L0)
    b = dm_kl_modes(mirror, R0, L0)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_bad_inputs_named(mirror):
    with pytest.raises(ValueError, match="r0"):
        dm_kl_modes(mirror, -1.0)
    with pytest.raises(ValueError, match="n_modes"):
        dm_kl_modes(mirror, R0, n_modes=mirror.n_valid)
    with pytest.raises(TypeError, match="influence"):
        dm_kl_modes(np.eye(3), R0)
    with pytest.raises(ValueError, match="m2c"):
        DMKLBasis(mirror, np.zeros((3, 2)), np.ones(2))


def test_r0_beyond_float_range_is_refused_and_within_it_follows_the_law(mirror):
    # audit 9, centre: r0 = 1e-300 m raised scipy's "array must not contain infs or NaNs"
    # and r0 = 1e300 m returned variances 0 (arbitrary modes) without a word. Reference:
    # the prior scales as (D / r0)^(5/3) (Kolmogorov), the modes do not depend on r0
    for r0 in (1e-300, 1e300):
        with pytest.raises(ValueError, match=r"`r0` must give D / r0 in \[1e-60, 1e\+60\]"):
            dm_kl_modes(mirror, r0, n_modes=6)
    m_ref, v_ref = dm_kl_modes(mirror, 0.1, n_modes=6)
    m_far, v_far = dm_kl_modes(mirror, 1e50, n_modes=6)
    np.testing.assert_allclose(v_far, v_ref * (0.1 / 1e50) ** (5 / 3), rtol=1e-9)
    # modes 1-2 (and 3-5) are degenerate pairs: compare the spanned subspaces
    for cols in ([0, 1], [2, 3, 4]):
        proj = np.linalg.lstsq(m_ref[:, cols], m_far[:, cols], rcond=None)[0]
        np.testing.assert_allclose(m_ref[:, cols] @ proj, m_far[:, cols], atol=1e-8)
def test_von_karman_tends_to_kolmogorov_as_the_outer_scale_grows():
    """Audit 9: the closed form B0 - b(u) cancels for u = 2 pi r / L0 -> 0: L0 = 1e10 m
    gave 2,000 x Kolmogorov's D at r = 1 cm, and L0 = 1e300 an OverflowError. The
    reference is the limit L0 -> inf, Kolmogorov's 6.8839 (r / r0)^(5/3) (Fried 1966),
    which von Karman approaches from below, monotonically."""
    r = np.array([0.01, 0.1, 1.0])
    kolmogorov = von_karman_structure_function(r, 0.1)
    previous = np.zeros(3)
    for outer_scale in (1e2, 1e4, 1e6, 1e8, 1e10, 1e14, 1e100, 1e300):
        ratio = von_karman_structure_function(r, 0.1, outer_scale) / kolmogorov
        assert np.all(ratio <= 1.0 + 1e-9) and np.all(ratio >= previous)
        previous = ratio
    np.testing.assert_allclose(previous, 1.0, rtol=1e-9)
    assert von_karman_structure_function(0.5, 0.1, 20.0).shape == ()  # a scalar stays 0-d
    with pytest.raises(TypeError, match="`r` must be real"):
        von_karman_structure_function(r + 1j, 0.1, 20.0)
