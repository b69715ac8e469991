"""Review 21: the frame-times warning is quiet where a refusal follows, on both sides.

References: the rate of frame times by hand, (n - 1) / (t[-1] - t[0]): times 0.1 us apart
are 1e7 Hz, above ``RATE_RANGE``'s 1 MHz, times 1e4 s apart 1e-4 Hz, below its 1 mHz;
such a log is refused by ``log_rate_problem`` (every command and batch), and the
documented rule (``telemetry.log._warn_timestamps_rate``) says the refusal alone, no
plausibility warning first. Inside the range the warning is given (1e-5 s: 1e5 Hz is the
edge of ``WFS_RATE_RANGE``, 5e-6 s above it).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.common.validation import log_rate_problem
from modalinfo.telemetry import ModalLog


def _coeffs(n: int = 20) -> np.ndarray:
    return np.random.default_rng(0).standard_normal((n, 3))


@pytest.mark.parametrize("step, rate", [(1e-7, 1e7), (1e4, 1e-4)])
def test_times_outside_the_analysable_range_are_refused_not_warned(step, rate):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        log = ModalLog(_coeffs(), timestamps=np.arange(20) * step)
    assert log.rate == pytest.approx(rate)
    assert log_rate_problem(log.rate, True, "log") is not None


def test_times_just_inside_the_range_are_warned():
    with pytest.warns(UserWarning, match=r"frame rate of 2e\+05 Hz"):
        log = ModalLog(_coeffs(), timestamps=np.arange(20) * 5e-6)
    assert log_rate_problem(log.rate, True, "log") is None
