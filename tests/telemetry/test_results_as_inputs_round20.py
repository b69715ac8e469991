"""Results fed back as inputs (adversarial round 20 PART a, issue 27).

References: the residual variance of a per-mode integrator on white open-loop
turbulence is the sum of the squared impulse response of the rejection function
``(1 - z**-1) / (1 - z**-1 + g z**-(d+1))`` (scipy.signal.lfilter of an impulse), here
4.0 for g = 1.5 with no delay, a stable loop (limit 2) whose closed-loop -3 dB point
does not exist below Nyquist (NaN bandwidth): before the fix the NaN made the log's
metadata refused ("`metadata` must not hold NaN"), so the stable loop could not run.
A QualityReport passed where a log is taken is refused naming the argument and the type
(before: "`coeffs` must be a real numeric array; got dtype object").
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, assess_quality
from modalinfo.telemetry.synthetic import closed_loop_log, kaos_like


def test_stable_loop_without_a_3db_point_runs():
    rng = np.random.default_rng(3)
    open_log = ModalLog(rng.standard_normal((200_000, 2)), rate=1000.0)
    cl = closed_loop_log(open_log, gain=1.5, delay_frames=0, seed=1)
    h = lfilter([1.0, -1.0], [1.0, 0.5], np.r_[1.0, np.zeros(200)])
    # sum h^2 = 1 + 2.25 / 0.75 = 4; sampling error of a variance of 4e5 values ~ 1 %
    assert np.sum(h ** 2) == pytest.approx(4.0)
    assert np.var(cl.coeffs) == pytest.approx(4.0, rel=0.03)
    assert cl.metadata["closed_loop"]["bandwidth_closed_loop_3db_hz"] is None


def test_report_as_log_refused_naming_it():
    report = assess_quality(kaos_like(500, seed=0))
    with pytest.raises(TypeError, match=r"^`log_or_coeffs` must be a numeric array \(T, M\); "
                                         r"got QualityReport\.$"):
        assess_quality(report)
