"""Zernike polynomials and ZernikeBasis.

References: the factorial-sum definition of R_n^m evaluated in exact rational arithmetic
(Python ``fractions``); continuum orthonormality by Gauss-Legendre quadrature in rho
(exact for polynomials) and the trapezoid rule in theta (exact for trigonometric
polynomials); Noll (1976) Table 1 closed forms (Z2 = 2x/R, Z3 = 2y/R, Z4, Z11);
``aotools.functions.zernike.zernike_noll`` (test-only reference, first 36 modes).
"""

from fractions import Fraction
from math import factorial

import numba
import numpy as np
import pytest

from modalinfo.bases import (
    Pupil,
    ZernikeBasis,
    _kernels,
    noll_to_zernike,
    zernike_matrix,
    zernike_polynomial,
    zernike_radial,
)


def _radial_exact(n, m, r):
    """Factorial sum sum_s (-1)^s (n-s)! / (s! ((n+m)/2-s)! ((n-m)/2-s)!) r^(n-2s)."""
    return sum(
        Fraction((-1) ** s * factorial(n - s),
                 factorial(s) * factorial((n + m) // 2 - s) * factorial((n - m) // 2 - s))
        * r ** (n - 2 * s)
        for s in range((n - m) // 2 + 1)
    )


def _radial_float_sum(n, m, rho):
    """The factorial sum in floating point (accurate at low orders only)."""
    return sum(
        (-1) ** s * factorial(n - s)
        / (factorial(s) * factorial((n + m) // 2 - s) * factorial((n - m) // 2 - s))
        * rho ** (n - 2 * s)
        for s in range((n - m) // 2 + 1)
    )


def _factorial_sum_cancellation(n, m):
    """sum_s |term_s| at rho = 1 over |R_n^m(1)| = 1, in exact integer arithmetic.

    The factorial sum adds terms of alternating sign whose magnitudes reach this size
    while the result is 1: evaluated in floating point it loses about log10 of this
    many digits, whatever the rounding of a particular platform.
    """
    return sum(
        Fraction(factorial(n - s),
                 factorial(s) * factorial((n + m) // 2 - s) * factorial((n - m) // 2 - s))
        for s in range((n - m) // 2 + 1)
    )


def test_radial_against_exact_rational_sum():
    """Our recurrence against the factorial sum evaluated exactly (``fractions``).

    No assertion on how much a floating-point evaluation of the factorial sum loses:
    that depends on the platform's rounding. Why the recurrence is needed is shown in
    exact arithmetic instead: at n = 40, m = 0 the magnitudes of the terms of the
    factorial sum add up to 2.6e14 for a result of 1, so double precision (eps =
    2.2e-16) bounds its error only by ~6e-2 there, while the recurrence is checked to
    1e-12.
    """
    grid = [Fraction(k, 32) for k in range(33)]
    rho = np.array([float(r) for r in grid])
    worst = 0.0
    for n in range(0, 41):
        for m in range(n % 2, n + 1, 2):
            exact = np.array([float(_radial_exact(n, m, r)) for r in grid])
            worst = max(worst, np.abs(zernike_radial(n, m, rho) - exact).max())
    assert worst < 1e-12
    assert _radial_exact(40, 0, Fraction(1)) == 1  # R_n^m(1) = 1 exactly
    assert zernike_radial(40, 0, 1.0) == pytest.approx(1.0, abs=1e-12)
    # cancellation of the factorial sum at n = 40, m = 0 (exact integers)
    assert _factorial_sum_cancellation(40, 0) * np.finfo(float).eps > 1e-2


def test_radial_orthogonality_high_order():
    # int_0^1 R_n^m R_n'^m rho drho = delta / (2 (n + 1)); Gauss-Legendre with 80 nodes
    # is exact for polynomials of degree <= 159.
    x, w = np.polynomial.legendre.leggauss(80)
    rho, w = 0.5 * (x + 1), 0.5 * w
    for m in (0, 1, 7, 20):
        ns = np.arange(m, 61, 2)
        r = np.stack([zernike_radial(int(n), m, rho) for n in ns])
        gram = (r * (w * rho)) @ r.T * 2 * (ns[:, None] + 1)
        np.testing.assert_allclose(gram, np.eye(ns.size), atol=1e-11)


def test_continuum_orthonormality_unit_rms():
    # (1/pi) int Z_j Z_j' rho drho dtheta = delta over j <= 231 (n <= 20)
    x, w = np.polynomial.legendre.leggauss(30)
    rho, w_r = 0.5 * (x + 1), 0.5 * w
    n_theta = 64
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    rr, tt = np.meshgrid(rho, theta, indexing="ij")
    weights = (w_r * rho)[:, None] * np.full(n_theta, 2 * np.pi / n_theta)[None, :] / np.pi
    z = zernike_matrix(range(1, 232), rr.ravel(), tt.ravel())
    gram = z.T @ (z * weights.ravel()[:, None])
    np.testing.assert_allclose(gram, np.eye(231), atol=1e-12)


def test_noll_closed_forms():
    p = Pupil(64, diameter=3.0)
    zb = ZernikeBasis(p, [1, 2, 3, 4, 5, 6, 11])
    radius = p.diameter / 2
    x, y, r = p.x[p.mask] / radius, p.y[p.mask] / radius, p.rho_valid
    np.testing.assert_allclose(zb.matrix[:, 0], 1.0)
    np.testing.assert_allclose(zb.matrix[:, 1], 2 * x, atol=1e-13)
    np.testing.assert_allclose(zb.matrix[:, 2], 2 * y, atol=1e-13)
    np.testing.assert_allclose(zb.matrix[:, 3], np.sqrt(3) * (2 * r**2 - 1), atol=1e-13)
    np.testing.assert_allclose(zb.matrix[:, 4], np.sqrt(6) * 2 * x * y, atol=1e-13)
    np.testing.assert_allclose(zb.matrix[:, 5], np.sqrt(6) * (x**2 - y**2), atol=1e-13)
    np.testing.assert_allclose(zb.matrix[:, 6], np.sqrt(5) * (6 * r**4 - 6 * r**2 + 1),
                               atol=1e-12)


def test_matches_aotools_first_36():
    """aotools builds the same pixel grid and the same Noll normalisation and sign.

    What had to be accounted for: aotools returns N x N images zeroed outside its own
    ``circle(N/2, N)`` mask (ours keeps rho <= 1 pixels), so we compare on the pixels
    inside both; its ``rot`` argument is left at 0; its radial function is the factorial
    sum, accurate at these orders.
    """
    from aotools.functions.zernike import zernike_noll

    n = 128
    p = Pupil(n)
    zb = ZernikeBasis(p, 36)
    ours = p.to_image(zb.matrix.T)
    theirs = np.stack([zernike_noll(j, n) for j in range(1, 37)])
    both = p.mask & (theirs[0] != 0)
    assert both.sum() > 0.99 * p.n_valid
    np.testing.assert_allclose(ours[:, both], theirs[:, both], atol=1e-11)


def test_discrete_gram_256():
    # Pixel-centre sampling of a disc on 256 pixels: the jagged rim leaves Gram
    # deviations of a few 1e-3 for j <= 100 (largest between high-|m| modes whose m
    # differ by 4, aliased by the square grid); they shrink as the grid is refined.
    zb = ZernikeBasis(Pupil(256), 100)
    err256 = np.abs(zb.gram() - np.eye(100)).max()
    assert err256 < 1e-2
    zb36 = ZernikeBasis(Pupil(256), 36)
    assert np.abs(zb36.gram() - np.eye(36)).max() < 5e-3
    err128 = np.abs(ZernikeBasis(Pupil(128), 100).gram() - np.eye(100)).max()
    assert err256 < 0.5 * err128
    zo = ZernikeBasis(Pupil(256), 100, orthonormalize=True)
    np.testing.assert_allclose(zo.gram(), np.eye(100), atol=1e-12)


def test_orthonormalize_annular_keeps_structure():
    p = Pupil(96, obscuration=0.35)
    raw = ZernikeBasis(p, range(1, 37))
    ortho = ZernikeBasis(p, range(1, 37), orthonormalize=True)
    assert ortho.orthonormalized and not raw.orthonormalized
    np.testing.assert_allclose(ortho.gram(), np.eye(36), atol=1e-12)
    # change of basis raw -> ortho is upper triangular with a positive diagonal
    t = np.linalg.lstsq(raw.matrix, ortho.matrix, rcond=None)[0]
    np.testing.assert_allclose(np.tril(t, -1), 0, atol=1e-9)
    assert np.all(np.diag(t) > 0)
    # tip stays tip (Z2 is orthogonal to piston on the symmetric annulus)
    np.testing.assert_allclose(ortho.matrix[:, 1] / ortho.matrix[:, 1].std(),
                               raw.matrix[:, 1] / raw.matrix[:, 1].std(), atol=1e-12)


def test_zernike_polynomial_shapes():
    rho = np.linspace(0, 1, 12).reshape(3, 4)
    theta = np.full((3, 4), 0.3)
    z = zernike_polynomial(8, rho, theta)
    assert z.shape == (3, 4)
    np.testing.assert_allclose(z, np.sqrt(8) * (3 * rho**3 - 2 * rho) * np.cos(0.3), atol=1e-14)
    np.testing.assert_allclose(zernike_polynomial(7, 0.5, 0.3),
                               np.sqrt(8) * (3 * 0.125 - 1.0) * np.sin(0.3))


def test_kernels_against_numpy_reference():
    rng = np.random.default_rng(1)
    rho = rng.uniform(0, 1, 200)
    theta = rng.uniform(-np.pi, np.pi, 200)
    modes = np.arange(1, 67)
    n, m = noll_to_zernike(modes)
    ref = np.empty((200, modes.size))
    for k, (nn, mm) in enumerate(zip(n, m, strict=True)):
        radial = _radial_float_sum(int(nn), abs(int(mm)), rho)
        if mm == 0:
            ref[:, k] = np.sqrt(nn + 1) * radial
        elif mm > 0:
            ref[:, k] = np.sqrt(2 * (nn + 1)) * radial * np.cos(mm * theta)
        else:
            ref[:, k] = np.sqrt(2 * (nn + 1)) * radial * np.sin(-mm * theta)
    out = np.empty_like(ref)
    _kernels.zernike_matrix(rho, theta, n, m, out)
    np.testing.assert_allclose(out, ref, atol=1e-12)
    single = np.empty(200)
    _kernels.radial(9, 3, rho, single)
    np.testing.assert_allclose(single, _radial_float_sum(9, 3, rho), atol=1e-13)

    @numba.njit
    def inside(r):
        o = np.empty(r.shape[0])
        _kernels.radial(4, 0, r, o)
        return o

    np.testing.assert_allclose(inside(rho), 6 * rho**4 - 6 * rho**2 + 1, atol=1e-14)


def test_basis_modes_and_labels():
    p = Pupil(32)
    assert ZernikeBasis(p).modes.tolist() == list(range(2, 29))
    zb = ZernikeBasis(p, 10)
    assert zb.modes.tolist() == list(range(1, 11))
    assert zb.labels[3] == "Z4" and zb.n_modes == 10
    zr = zb.reorder([4, 1])
    assert isinstance(zr, ZernikeBasis)
    assert zr.modes.tolist() == [5, 2] and zr.labels == ["Z5", "Z2"]
    np.testing.assert_array_equal(zr.matrix, zb.matrix[:, [4, 1]])


@pytest.mark.parametrize(
    ("modes", "exc", "match"),
    [
        ([0, 2], ValueError, r"`modes` must be >= 1; got 0"),
        (0, ValueError, r"`modes` as a count must be an int >= 1; got 0"),
        ([], ValueError, r"`modes` must hold at least one Noll index"),
        ([2, 2], ValueError, r"`modes` must not repeat an index"),
        ([2.5], TypeError, r"`modes` must be an int or an integer array"),
        ("Z2", TypeError, r"`modes` must be an int or an integer array"),
    ],
)
def test_bad_modes(modes, exc, match):
    with pytest.raises(exc, match=match):
        ZernikeBasis(Pupil(16), modes)


def test_bad_other_inputs():
    with pytest.raises(TypeError, match="`pupil` must be a modalinfo.bases.Pupil"):
        ZernikeBasis(16)
    with pytest.raises(ValueError, match="`modes` are linearly dependent"):
        # 15 modes (radial order 4, resolved on 8 pixels) on the 8 pixels of a 0.9 annulus
        ZernikeBasis(Pupil(8, obscuration=0.9), 15, orthonormalize=True)
    with pytest.raises(ValueError, match=r"\|m\| <= n with n - \|m\| even; got n=3, m=0"):
        zernike_radial(3, 0, 0.5)
    with pytest.raises(ValueError, match="`rho` must be finite"):
        zernike_radial(2, 0, [0.1, np.nan])


def test_modes_beyond_the_grid_resolution_are_refused():
    # audit 9, centre: ZernikeBasis(Pupil(8), range(2, 200)) built 198 aliased modes of
    # rank 52; the Nyquist rule (radial order n resolved on >= 2 n pixels across, the CLI's
    # and closedloop's rule): on 16 pixels the last mode is that of radial order 8, Noll
    # (n + 1)(n + 2) / 2 = 45 (Noll 1976: radial order n closes at that index)
    assert ZernikeBasis(Pupil(16), range(2, 46)).n_modes == 44
    with pytest.raises(ValueError, match=r"`n_pixels` must be >= 18 to sample Z46 \(radial "
                                         r"order 9"):
        ZernikeBasis(Pupil(16), range(2, 47))
    with pytest.raises(ValueError, match=r"`n_pixels` must be >= 38 to sample Z199"):
        ZernikeBasis(Pupil(8), range(2, 200))


def test_points_of_different_lengths_name_rho_and_theta():
    # audit 9-inputs r01: NumPy's broadcast message ("arg 0", "arg 1") and a refusal of
    # `theta` when `rho` was the empty one; now both names and both shapes
    with pytest.raises(ValueError, match=r"^`rho` and `theta` must broadcast together; got "
                                         r"shapes \(3,\) and \(4,\)\.$"):
        zernike_polynomial(4, np.full(3, 0.5), np.zeros(4))
    with pytest.raises(ValueError, match=r"^`rho` and `theta` must broadcast together; got "
                                         r"shapes \(4,\) and \(3,\)\.$"):
        zernike_polynomial(4, np.full(4, 0.5), np.zeros(3))
    with pytest.raises(ValueError, match=r"^`rho` and `theta` must have the same length "
                                         r"\(P,\); got shapes \(0,\) and \(3,\)\.$"):
        zernike_matrix([2, 3], [], np.zeros(3))
    # what broadcasts still does (documented): Z4 = sqrt(3) (2 rho^2 - 1), Noll 1976
    rho, theta = np.array([[0.2], [0.7]]), np.zeros(3)
    expected = np.sqrt(3) * (2 * rho**2 - 1) * np.ones(3)
    np.testing.assert_allclose(zernike_polynomial(4, rho, theta), expected, rtol=1e-14)
