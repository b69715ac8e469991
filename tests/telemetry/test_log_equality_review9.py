"""ModalLog ``==`` tells apart logs that differ only in their wavelength.

Round 9 of planted bugs (review9, bug P5): ``ModalLog.__eq__`` is documented to compare
"modes, convention, units, wavelength and metadata"; the existing tests (round trips,
a one-ulp difference in the values) never changed the wavelength alone, so comparing a
log's wavelength with itself went unseen. Reference: the phase-to-OPD law, OPD = phase
x lambda / (2 pi) (written out here with NumPy): the same phases at 500 nm and 600 nm
are other optical paths, hence other logs.
"""

import math

import numpy as np

from modalinfo.telemetry import ModalLog


def test_logs_of_other_wavelengths_are_not_equal():
    x = np.random.default_rng(7).standard_normal((64, 3))
    a = ModalLog(x, rate=1000.0, wavelength=500e-9)
    b = ModalLog(x, rate=1000.0, wavelength=600e-9)
    np.testing.assert_allclose(a.to_units("nm").coeffs, x * 500.0 / (2 * math.pi), rtol=1e-12)
    np.testing.assert_allclose(b.to_units("nm").coeffs, x * 600.0 / (2 * math.pi), rtol=1e-12)
    assert a != b and b != a
    assert a != ModalLog(x, rate=1000.0)  # no wavelength at all
    assert a == ModalLog(x.copy(), rate=1000.0, wavelength=500e-9)
