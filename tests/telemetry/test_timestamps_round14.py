"""Round 14 PART a: integer timestamps that are ns counts are refused, not read as seconds.

Reference (outside the code): the unit arithmetic of a 1 kHz clock, whose frames are
10**6 ns apart; read as seconds that is a frame rate of 1e-6 Hz, outside the documented
physical range of a log, 1 mHz - 1 MHz (the command lines' ``--rate`` range).
"""

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog


def _coeffs(n=100):
    return np.random.default_rng(0).standard_normal((n, 2))


def test_int64_ns_counted_from_zero_are_refused_naming_the_slip():
    with pytest.raises(ValueError, match=r"^`timestamps` are integers with a median step "
                                         r"of 1000000 .*1e-06 Hz.*ns or us\?"):
        ModalLog(_coeffs(), timestamps=np.arange(100, dtype=np.int64) * 1_000_000)


@pytest.mark.parametrize("step, rate", [(1, 1.0), (1000, 1e-3)])
def test_integer_seconds_within_the_range_are_kept(step, rate):
    # kept with the warning of slow frame times (Leftovers 26-rate; below 10 Hz since
    # fixes 40-a: 1 kHz stamps in ms read as 1 Hz)
    if rate < 10.0:
        with pytest.warns(UserWarning, match=f"`timestamps` give a frame rate of {rate:g} Hz"):
            log = ModalLog(_coeffs(), timestamps=np.arange(100) * step)
    else:
        log = ModalLog(_coeffs(), timestamps=np.arange(100) * step)
    assert log.rate == pytest.approx(rate, rel=1e-12)


def test_the_same_times_in_seconds_give_one_kilohertz():
    t = np.arange(100, dtype=np.int64) * 1_000_000
    assert ModalLog(_coeffs(), timestamps=t / 1e9).rate == pytest.approx(1000.0, rel=1e-9)
