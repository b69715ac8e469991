"""An ``extra`` log must share the frames of ``data`` (round 9, v-extra-other-rate/-start).

Reference: the definition of a lag. A driver d and a target y = 0.8 d[t-1] + 0.6 e give
the transfer entropy 0.5 ln(1 + 0.64 / 0.36) = 0.511 nats from d at lag 1 when both are
sampled at the same instants. Labelled 500 Hz against 1 kHz, or starting 5 s later, the
same arrays were lagged as if simultaneous without a word; they are refused, and the
aligned pair gives the analytic value within its sampling error.
"""

import numpy as np
import pytest

from modalinfo.information import select_inputs, transfer_entropy_map
from modalinfo.telemetry import ModalLog


def test_misaligned_extra_refused_aligned_extra_right():
    rng = np.random.default_rng(8)
    n = 3000
    d = rng.standard_normal(n)
    y = np.r_[0.0, 0.8 * d[:-1]] + 0.6 * rng.standard_normal(n)
    data = ModalLog(y[:, None], rate=1000.0, modes=["y"], convention="labels")
    for kw in ({"rate": 500.0}, {"rate": 1000.0, "start_time": 5.0}):
        extra = ModalLog(d[:, None], modes=["d"], convention="labels", **kw)
        with pytest.raises(ValueError, match="`extra` must be sampled at the frames"):
            select_inputs(data, "y", extra=extra, max_lag=2, n_surrogates=19,
                          n_resamples=19, seed=0)
        with pytest.raises(ValueError, match="`extra` must be sampled at the frames"):
            transfer_entropy_map(data, extra=extra, lags=2, n_surrogates=19, seed=0)
    extra = ModalLog(d[:, None], rate=1000.0, modes=["d"], convention="labels")
    sel = select_inputs(data, "y", extra=extra, max_lag=2, n_surrogates=19, n_resamples=19,
                        seed=0)
    assert sel.inputs[0].label == "extra:d[t]"
    assert sel.inputs[0].gain == pytest.approx(0.5 * np.log(1 + 0.64 / 0.36), abs=0.05)
