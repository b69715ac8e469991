"""The K-L mode count is capped at exactly 10^6, the first count whose Zernike
covariance no machine holds.

Reference (outside the code): the arithmetic of the cap's reason: ``n`` K-L modes are
combined from at least ``3 n`` Zernikes after piston (``default_zernike_modes``, complete
radial orders: order N closes at Noll ``(N + 1)(N + 2) / 2``), whose float64 covariance
is ``8 (3 n)^2`` bytes: 72 TB at n = 10^6. The count 10^6 itself is accepted (a list of
3,000,024 Zernikes, order 2448 closing at Noll 3,000,025, takes 20 ms) and 10^6 + 1 is
refused with the bound in the message, matched to its end (``<= 1000000;``), so that a
larger bound whose digits begin the same (10^7: "<= 10000000") does not match.

Planted bug R8-54 (docs/MUTATION.md, round 8): ``MAX_KL_MODES = 10**7`` passed
``test_kl.py``, whose regex "<= 1000000" is a prefix of "<= 10000000", with 2**70.
"""
from __future__ import annotations

import pytest

from modalinfo.bases import default_zernike_modes


def test_the_cap_is_ten_to_the_sixth_modes():
    n = 10**6
    assert 8 * (3 * n) ** 2 == 72e12  # bytes of the covariance of 3 n Zernikes
    modes = default_zernike_modes(n)
    order = 2448  # the first radial order closing at or above 3 n + 1 (Noll, with piston)
    assert (order + 1) * (order + 2) // 2 - 1 >= 3 * n > order * (order + 1) // 2 - 1
    assert len(modes) == (order + 1) * (order + 2) // 2 - 1 and modes[-1] == len(modes) + 1
    with pytest.raises(ValueError, match=r"`n_modes` must be an int <= 1000000; got 1000001\."):
        default_zernike_modes(n + 1)
