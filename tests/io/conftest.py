"""Fixtures shared by the I/O tests: a bitwise log comparison and log strategies."""

from __future__ import annotations

import numpy as np
import pytest


def _assert_same_log(a, b, *, check_metadata=True):
    """Bitwise equality of everything a lossless writer must keep."""
    assert a.coeffs.dtype == b.coeffs.dtype
    assert a.coeffs.shape == b.coeffs.shape
    assert np.array_equal(
        np.ascontiguousarray(a.coeffs).view(np.uint8), np.ascontiguousarray(b.coeffs).view(np.uint8)
    ), "coefficients differ bitwise"
    assert a.modes == b.modes
    assert a.convention == b.convention
    assert a.units == b.units
    assert a.wavelength == b.wavelength
    assert a._rate == b._rate  # the nominal rate as given
    assert a.rate == b.rate
    assert a.start_time == b.start_time
    if a.timestamps is None:
        assert b.timestamps is None
    else:
        assert b.timestamps is not None
        assert np.array_equal(a.timestamps.view(np.uint8), b.timestamps.view(np.uint8))
    if check_metadata:
        assert a.metadata == b.metadata
        assert type(a.metadata) is dict


@pytest.fixture
def assert_same_log():
    return _assert_same_log
