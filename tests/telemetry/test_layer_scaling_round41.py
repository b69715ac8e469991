"""``Layer.d_over_r0_at`` checks its wavelength and diameter (round 41 PART a C30, C31).

Reference: ``D / r0`` scales as ``lambda^(-6/5)`` (Fried 1966): ``D / (r0 (lambda /
lambda_0)^(6/5))``, computed here with plain floats. A wavelength typed in nm (500) gave
1.3e-9 and a negative diameter a negative ``D / r0``, without a word.
"""

import pytest

from modalinfo.telemetry.synthetic import Layer


def test_value_follows_the_six_fifths_law():
    got = Layer(r0=0.1, wind_speed=10.0).d_over_r0_at(8.0, 2.2e-6)
    assert got == pytest.approx(8.0 / (0.1 * (2.2e-6 / 500e-9) ** 1.2), rel=1e-14)


def test_wavelength_in_nanometres_is_refused():
    with pytest.raises(ValueError, match="`wavelength`"):
        Layer(r0=0.1, wind_speed=10.0).d_over_r0_at(8.0, 500)


@pytest.mark.parametrize("diameter", [-8.0, 0.0])
def test_non_positive_diameter_is_refused(diameter):
    with pytest.raises(ValueError, match="`diameter`"):
        Layer(r0=0.1, wind_speed=10.0).d_over_r0_at(diameter, 5e-7)
