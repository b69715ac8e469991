"""Unsigned integer ns timestamps are refused as the signed ones (review13, R13-A3).

Reference (outside the code): the unit arithmetic of a 1 kHz clock, whose frames are
10**6 ns apart, a frame rate of 1e-6 Hz if read as seconds, below the documented range of
a log (1 mHz - 1 MHz); numpy's dtype kinds ``"i"`` and ``"u"`` are both integers
(``np.issubdtype(..., np.integer)``), as a camera's uint64 counter is.
"""

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog


@pytest.mark.parametrize("dtype", [np.uint64, np.uint32, np.int32])
def test_unsigned_ns_counts_are_refused_naming_the_slip(dtype):
    t = np.arange(100, dtype=dtype) * dtype(1_000_000)
    assert np.issubdtype(t.dtype, np.integer)
    with pytest.raises(ValueError, match=r"integers with a median step of 1000000 .*ns or us"):
        ModalLog(np.random.default_rng(0).standard_normal((100, 2)), timestamps=t)
