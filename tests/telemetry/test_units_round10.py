"""Refusals of a wavelength one ulp outside the range name the value (round 10 PART a).

Reference: IEEE 754 neighbours (``numpy.nextafter``) of the documented bounds 1e-7 and
1e-4 m; a value printed must differ from the bound it breaks, and the nanometre hint
is given only where reading the value in nm gives a wavelength in the range.
"""

import re

import numpy as np
import pytest

from modalinfo.telemetry.units import WAVELENGTH_RANGE, check_wavelength


@pytest.mark.parametrize("value", [np.nextafter(WAVELENGTH_RANGE[0], 0.0),
                                   np.nextafter(WAVELENGTH_RANGE[1], 1.0)])
def test_value_past_a_bound_is_printed_in_full(value):
    with pytest.raises(ValueError) as err:
        check_wavelength(value)
    shown = re.search(r"got ([^ ]+?)\.?$", str(err.value)).group(1)
    assert float(shown) == value
    assert "did you mean" not in str(err.value)


def test_nanometre_hint_only_for_nanometres():
    with pytest.raises(ValueError, match=r"got 500 \(did you mean 500e-9 m\?\)"):
        check_wavelength(500.0)
    with pytest.raises(ValueError) as err:
        check_wavelength(0.5)  # 0.5 nm is no wavelength: no hint
    assert "did you mean" not in str(err.value)
