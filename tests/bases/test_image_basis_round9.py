"""basis_from_images refuses a zero mode and dependent modes (round 9, bz-from-images-*).

Reference: linear algebra. Images of Z2, Z3, Z4 plus a second copy of Z2 span three
dimensions, not four: the fitting error of that "basis" truncated after its first three
modes left the copy's coefficient (1.10 rad^2 on standard normal coefficients) for a
phase the three modes represent exactly. An all-zero image is no mode. Both were
accepted as 4-mode bases; the three independent images give a basis whose fitting error
equals the ZernikeBasis's on the same coefficients (the same phase maps).
"""

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis, basis_from_images
from modalinfo.ordering import fitting_error
from modalinfo.ordering.fitting_error import PupilSamplingWarning


def _images(zb, pupil):
    out = np.zeros((zb.n_modes, pupil.n_pixels, pupil.n_pixels))
    for k in range(zb.n_modes):
        out[k][pupil.mask] = zb.matrix[:, k]
    return out


def test_dependent_and_zero_modes_refused():
    pupil = Pupil(32, diameter=1.0)
    zb = ZernikeBasis(pupil, modes=range(2, 5))
    ims = _images(zb, pupil)
    with pytest.raises(ValueError, match="linearly dependent.*modes 0 and 3"):
        basis_from_images(np.concatenate([ims, 2.0 * ims[:1]]), mask=pupil.mask)
    with pytest.raises(ValueError, match="mode 3 is zero"):
        basis_from_images(np.concatenate([ims, 0.0 * ims[:1]]), mask=pupil.mask)
    a = np.random.default_rng(0).standard_normal((40, 3))
    good = basis_from_images(ims, mask=pupil.mask)
    # the Zernikes are continuous modes, sampled on 32 pixels (Gram error 0.018): said
    # (fix33-a); the images' basis holds its own samples: not said
    with pytest.warns(PupilSamplingWarning, match="32-pixel"):
        zernike = fitting_error(a, zb).mean
    assert np.allclose(fitting_error(a, good).mean, zernike, rtol=1e-10)
