"""Fixes 37-a2 of adversarial round 37 PART a (issue 27): S1-S8.

References: the Gram error ``max |Z^T Z / n - I|`` of the Zernikes sampled on a
512-pixel annulus, formed here with numpy (it has converged: 0.2632 at 97 pixels
and 0.2632 at 512 for obscuration 0.3, so it is the annulus's own, not sampling); the
pixel residual of the dropped modes against the sum of their squares (Parseval),
formed here with numpy; the 17-pixel clear pupil of round 37 U01 (numpy Gram 0.19).
"""

import warnings

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.bases.zernike import zernike_matrix
from modalinfo.ordering import fitting_error
from modalinfo.ordering.fitting_error import PupilSamplingWarning

MODES = np.arange(2, 29)


def _numpy_gram_error(pupil):
    z = zernike_matrix(MODES, pupil.rho_valid, pupil.theta_valid)
    return float(np.max(np.abs(z.T @ z / z.shape[0] - np.eye(MODES.size))))


@pytest.fixture(scope="module")
def coeffs():
    rng = np.random.default_rng(37)
    return rng.standard_normal((400, MODES.size)) / np.arange(1, MODES.size + 1)


@pytest.mark.parametrize("n_pixels", [64, 128])
def test_s1_s8_obscured_pupil_blames_the_pupil_and_names_no_grid(coeffs, n_pixels):
    fine = _numpy_gram_error(Pupil(512, obscuration=0.3))
    assert fine > 0.25  # converged, well above the 1e-2 that a grid would reach
    basis = ZernikeBasis(Pupil(n_pixels, obscuration=0.3), modes=MODES)
    with pytest.warns(PupilSamplingWarning) as rec:
        fe = fitting_error(coeffs, basis, method="pixels")
    assert len(rec) == 1
    w = rec[0].message
    assert w.suggested_pixels == 0
    assert w.pupil_deviation == pytest.approx(fine, abs=2e-3)
    text = str(w)
    assert "not orthonormal on this pupil" in text and "obscuration 0.3" in text
    assert "sampled pupil" not in text and "pixels (extrapolated)" not in text
    assert " on 0 pixels" not in text
    # the difference it states is the pixel residual's from numpy's Parseval
    z = zernike_matrix(MODES, basis.pupil.rho_valid, basis.pupil.theta_valid)
    r = coeffs @ z.T
    assert np.mean(np.mean(r**2, axis=1)) == pytest.approx(fe.curve(include_zero=True)[0],
                                                             rel=1e-9)
    par0 = np.mean(np.sum(coeffs**2, axis=1))
    first = np.mean(np.mean(r**2, axis=1)) / par0 - 1
    assert f"{100 * first:+.1f} % at dPhi(0)" in text


def test_clear_pupil_still_warned_as_sampling_with_a_grid(coeffs):
    basis = ZernikeBasis(Pupil(17), modes=MODES)
    with pytest.warns(PupilSamplingWarning) as rec:
        fitting_error(coeffs, basis, method="pixels")
    w = rec[0].message
    assert w.pupil_deviation == 0.0 and w.suggested_pixels > 17
    assert w.gram_deviation == pytest.approx(_numpy_gram_error(Pupil(17)), rel=1e-9)
    assert "sampled pupil" in str(w)


def test_fine_clear_pupil_silent(coeffs):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PupilSamplingWarning)
        fitting_error(coeffs, ZernikeBasis(Pupil(256), modes=MODES), method="pixels")
