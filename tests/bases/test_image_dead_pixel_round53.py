"""A NaN pixel inside one mode image is refused, not dropped from every mode (round 53 a).

Reference: the images themselves (Zernike Z2-Z31 of ``zernike_polynomial`` on a 64-px
``Pupil``): the pixel is inside the pupil (finite and non-zero in the other modes), so the
default support cannot leave it out of every mode without changing the pupil. Before
round 53, ``basis_from_images`` returned a ``MaskedPupil`` of ``n_valid - 1`` pixels and
``identify_zernike`` called all 30 modes Zernikes, without a word. NaN outside the pupil
in some images and 0 there in others stays outside (every finite value there is 0).
"""

import numpy as np
import pytest

from modalinfo.bases import Pupil, basis_from_images, identify_zernike, zernike_polynomial


def _images() -> tuple[np.ndarray, Pupil]:
    pupil = Pupil(64)
    out = np.zeros((30, 64, 64))
    for k, j in enumerate(range(2, 32)):
        out[k][pupil.mask] = zernike_polynomial(j, pupil.rho_valid, pupil.theta_valid)
    return out, pupil


@pytest.mark.parametrize("call", [basis_from_images, identify_zernike])
def test_nan_pixel_inside_one_image_is_refused(call):
    images, _ = _images()
    images[17, 30, 33] = np.nan
    with pytest.raises(ValueError, match=r"mode 17 is not finite at pixel \(30, 33\)"):
        call(images)


def test_nan_outside_in_some_images_zero_in_others_is_the_outside():
    images, pupil = _images()
    images[::2][:, ~pupil.mask] = np.nan  # every other image NaN outside, the rest 0
    basis = basis_from_images(images)
    assert basis.pupil.n_valid == pupil.n_valid
    assert list(identify_zernike(images).noll) == list(range(2, 32))
