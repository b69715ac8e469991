"""Tests of modalinfo.telemetry.summary: a constant column summarised exactly.

Reference: exact arithmetic. A column whose every value is c has mean c, standard
deviation 0 and no lag-1 autocorrelation (0 / 0); rounding in the running mean must
not turn it into a smooth mode (adversarial round 5, row i21: 400 frames of 0.3 gave
std 1.9e-15 and lag1 0.9975).
"""

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, summarize


@pytest.mark.parametrize("value", [0.3, -7.1, 1e-3, 123456.789])
def test_a_constant_column_has_std_zero_and_no_lag1(value):
    rng = np.random.default_rng(0)
    coeffs = np.column_stack([np.full(400, value), rng.standard_normal(400)])
    s = summarize(ModalLog(coeffs, rate=1e3, modes=[1, 2]), chunk_frames=64)
    assert s.mean[0] == value and s.std[0] == 0.0 and s.rms[0] == abs(value)
    assert np.isnan(s.lag1[0])
    # the varying column is left as numpy computes it
    assert s.std[1] == pytest.approx(np.std(coeffs[:, 1]), rel=1e-12)


def test_a_column_varying_by_one_ulp_is_not_constant():
    coeffs = np.full((400, 1), 0.3)
    coeffs[200, 0] = np.nextafter(0.3, 1.0)
    s = summarize(coeffs)
    assert s.std[0] > 0  # one distinct value: not a constant, whatever its size
