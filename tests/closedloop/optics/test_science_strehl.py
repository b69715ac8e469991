"""``fft_strehl`` and ``marechal_strehl`` (closedloop/optics/science.py): right or refused.

References (outside the code):
- a flat or piston-only phase has Strehl ratio 1 (the PSF of an unaberrated pupil);
- a tilt of exactly one cycle across a ``padding * N`` FFT grid moves the PSF by one
  sample without lowering its peak (shift theorem): Strehl 1 again;
- the Strehl ratio has no value for an empty pupil, a non-finite phase inside it, or a
  negative variance (``exp(+v) > 1``): refused naming the argument (audit 9: NaN, NaN
  and 2.72 were returned).
"""

from __future__ import annotations

import numpy as np
import pytest

from closedloop.optics.science import fft_strehl, marechal_strehl

N = 16
_YY, _XX = np.mgrid[0:N, 0:N]
DISC = np.hypot(_XX - 7.5, _YY - 7.5) <= 8.0


def test_flat_piston_and_whole_cycle_tilt_give_one():
    assert fft_strehl(np.zeros((N, N)), DISC) == pytest.approx(1.0, abs=1e-12)
    assert fft_strehl(np.full((N, N), 2.5), DISC) == pytest.approx(1.0, abs=1e-12)
    tilt = 2 * np.pi * _XX / (4 * N)  # one cycle over the padded grid (padding 4)
    assert fft_strehl(tilt, DISC) == pytest.approx(1.0, abs=1e-12)
    # NaN outside the pupil is ignored (the simulator's snapshots hold NaN there)
    assert fft_strehl(np.where(DISC, 0.0, np.nan), DISC) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize(("phase", "mask", "kwargs", "exc", "match"), [
    (np.zeros((N, N)), np.zeros((N, N), bool), {}, ValueError, r"`mask` must hold at least"),
    (np.where(DISC, np.nan, 0.0), DISC, {}, ValueError, r"`phase` must be finite inside"),
    (np.zeros((N, N)), DISC[:8], {}, ValueError, r"must be square \(N, N\) arrays of one"),
    (np.zeros((N, 2 * N)), np.ones((N, 2 * N), bool), {}, ValueError, r"must be square"),
    (np.zeros((N, N)), DISC, {"padding": 0}, ValueError, r"`padding` must be an int >= 1"),
    (np.zeros((N, N)), DISC, {"padding": 1.5}, TypeError, r"`padding` must be an int"),
])
def test_fft_strehl_refuses_what_has_no_strehl(phase, mask, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        fft_strehl(phase, mask, **kwargs)


def test_marechal_strehl_of_a_variance():
    np.testing.assert_array_equal(marechal_strehl([0.0, 1.0]), np.exp([-0.0, -1.0]))
    for bad in (-1.0, [0.5, np.nan]):
        with pytest.raises(ValueError, match=r"`variance` must be >= 0 rad\^2"):
            marechal_strehl(bad)
