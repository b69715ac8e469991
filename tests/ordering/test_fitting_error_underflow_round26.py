"""Fitting error of coefficients so small that their squares underflow (round 26 PART b).

Reference: Parseval by hand for an orthonormal basis (dPhi after n modes is the sum of
the squares of the dropped coefficients, so a log scaled by ``s`` has ``s**2`` times the
curve of the unscaled log) and IEEE 754 binary64 (numpy.finfo): at s = 1e-300 every
square is below the smallest subnormal, so the honest curve is not representable and
is refused; at s = 1e-100 the squares (1e-200) are normal and the law holds. Before the
round the 1e-300 log returned a curve and total of exactly 0 with no word.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.ordering import fitting_error


def _basis(n_pix: int = 50, n_modes: int = 3) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(26).standard_normal((n_pix, n_modes)))
    return q * np.sqrt(n_pix)  # orthonormal on the pixels: Q.T Q / n_pix = I


COEFFS = np.array([[3.0, 2.0, 1.0], [1.0, -1.0, 2.0]])
HAND = np.array([(4 + 1 + 1 + 4) / 2, (1 + 4) / 2, 0.0])  # dropped squares, frame mean


def test_coefficients_whose_squares_underflow_are_refused():
    with pytest.raises(ValueError, match=r"coeffs_or_log.*underflow float64"):
        fitting_error(COEFFS * 1e-300, _basis())


def test_small_but_representable_coefficients_follow_the_scaling_law():
    res = fitting_error(COEFFS * 1e-100, _basis())
    np.testing.assert_allclose(res.mean, HAND * 1e-200, rtol=1e-9, atol=0.0)


def test_a_zeroed_log_keeps_its_exact_zero():
    res = fitting_error(np.zeros((2, 3)), _basis())
    assert np.all(res.mean == 0.0)
