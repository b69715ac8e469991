"""A start time float64 cannot resolve at the frame rate is refused (round 9, l-start-huge).

Reference: IEEE float64 spacing (numpy.spacing): near 1e17 s consecutive doubles are 16 s
apart, so ``1e17 + k / 2000`` is the same number for every frame (all 2000 times were
equal, the log's duration 1 s); near a Unix-epoch start (1.7e9 s) they are 2.4e-7 s apart,
well below a 0.5 ms frame, and the times must stay exact to that spacing.
"""

from fractions import Fraction

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog


def test_unresolvable_start_refused():
    c = np.random.default_rng(0).standard_normal((2000, 2))
    assert np.spacing(1e17) == 16.0
    for start in (1e17, 1.7e18):  # the second: nanoseconds since 1970 given as seconds
        with pytest.raises(ValueError, match="start_time"):
            ModalLog(c, rate=2000.0, start_time=start)


def test_epoch_start_keeps_every_frame():
    c = np.random.default_rng(0).standard_normal((2000, 2))
    log = ModalLog(c, rate=2000.0, start_time=1.7e9)
    t = log.times
    assert np.unique(t).size == 2000
    exact = [float(Fraction(1.7e9) + Fraction(k, 2000)) for k in (0, 1, 1999)]
    assert np.all(np.abs(t[[0, 1, 1999]] - exact) <= np.spacing(1.7e9))
