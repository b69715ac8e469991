"""A pupil mask of one pixel (adversarial round 19 PART a, issue 27).

Reference: the mask the user passes (its shape, 32 x 32, and its single True pixel);
the refusal must name that array, not the 1 x 1 crop made from it.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import pupil_from_mask


def test_single_pixel_mask_is_refused_naming_the_users_array():
    mask = np.zeros((32, 32), bool)
    mask[3, 3] = True
    with pytest.raises(ValueError, match=r"`mask` must span at least 2 pixels.*\(32, 32\)"):
        pupil_from_mask(mask)


def test_two_pixel_mask_still_accepted():
    mask = np.zeros((32, 32), bool)
    mask[3, 3:5] = True
    assert pupil_from_mask(mask).n_valid == 2
