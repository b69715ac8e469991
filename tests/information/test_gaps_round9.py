"""Lagged analyses refuse a log with a gap in its timestamps (round 9, q-gap-*, q-drop-*).

Reference: the lag structure of an AR(1) series x[t] = 0.9 x[t-1] + e[t]. Removing 100
frames from the middle leaves a log whose lag-1 pairs straddle a 0.1 s hole, which
select_inputs and transfer_entropy_map used without a word (the forecast evaluation and
the ordering bootstrap refuse it); the longest contiguous segment, which the message
names, is accepted and gives the AR(1) gain -0.5 ln(1 - 0.9^2) = 0.830 nats within its
sampling error.
"""

import numpy as np
import pytest

from modalinfo.information import select_inputs, transfer_entropy_map
from modalinfo.telemetry import ModalLog


def test_gapped_log_refused_segment_accepted():
    rng = np.random.default_rng(4)
    n = 3000
    x = np.zeros((n, 2))
    e = rng.standard_normal((n, 2))
    for t in range(1, n):
        x[t] = 0.9 * x[t - 1] + e[t]
    cut = np.r_[0:1000, 1100:n]
    log = ModalLog(x[cut], timestamps=np.arange(n)[cut] / 1000.0, modes=[2, 3])
    with pytest.raises(ValueError, match="gap.*frames 1000..2899"):
        select_inputs(log, 0, max_lag=2, n_surrogates=19, n_resamples=19, seed=0)
    with pytest.raises(ValueError, match="gap"):
        transfer_entropy_map(log, lags=2, n_surrogates=19, seed=0)
    seg = log.longest_segment()
    sel = select_inputs(seg, 0, max_lag=2, n_surrogates=19, n_resamples=19, seed=0)
    assert sel.inputs[0].label == "Z2[t]"
    assert sel.inputs[0].gain == pytest.approx(-0.5 * np.log(1 - 0.81), abs=0.06)
