"""Review20's tests of the scalar checks: the r0 refusal at another wavelength, masked 0-d.

References, outside the code: Fried's law r0 proportional to lambda^(6/5) (Fried 1966;
Roddier 1981, eq. 3.24), applied here by hand to the documented 1 mm at 500 nm bound;
numpy's own ``np.ma`` indexing (a 0-d masked array's ``[()]`` is a plain float64),
against the documented rule that a masked array stays an array and is refused.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.common.validation import check_int, check_r0, check_real


def _bound_at(wavelength: float) -> float:
    """1 mm at 500 nm carried to ``wavelength`` by r0 ~ lambda^(6/5)."""
    return 1e-3 * (wavelength / 500e-9) ** 1.2


def test_the_1_mm_refusal_is_at_500_nm_in_the_infrared():
    # 3 mm quoted at 2.2 um is 0.51 mm at 500 nm: worse than 100" seeing, refused
    assert _bound_at(2.2e-6) > 3e-3
    with pytest.raises(ValueError, match=r"`r0` must be >= 0\.001 m at 500 nm.*at 500 nm"):
        check_r0(3e-3, wavelength=2.2e-6)


def test_just_below_1_mm_in_the_blue_is_kept():
    # 0.9 mm quoted at 400 nm is 1.18 mm at 500 nm: inside the range, silent
    assert _bound_at(400e-9) < 0.9e-3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_r0(0.9e-3, wavelength=400e-9) == 0.9e-3


@pytest.mark.parametrize("check", [check_real, check_int])
def test_a_0d_masked_array_stays_an_array_and_is_refused(check):
    value = np.ma.array(5)
    assert isinstance(value[()], np.integer)  # numpy would hand the scalar over
    with pytest.raises(TypeError, match=r"`x` must be a"):
        check(value, "x")
