"""Planted-bug review round 25 (review25, issue 27): a 0-d or numpy integer seed is
recorded as its int on every synthetic road (round 38 PART a, R84-R86), where round 38's
test met ``kaos_like`` and ``open_loop_log`` but not ``closed_loop_log``.

Reference: numpy draws the same numbers for ``np.int64(7)``, ``np.array(7)`` and ``7``
(``default_rng``), checked here on the logs' values, so the run is reproducible and its
metadata records 7.
"""

import numpy as np
import pytest

from modalinfo.telemetry import synthetic


@pytest.mark.parametrize("seed", [np.int64(7), np.array(7)])
def test_closed_loop_log_records_a_numpy_seed_as_its_int(seed):
    """R25-S2: closed_loop_simulation's metadata["closed_loop"]["seed"]."""
    ol = synthetic.open_loop_log(range(2, 4), n_frames=64, rate=500.0, diameter=8.0,
                                 layers=synthetic.Layer(0.15, 10.0), seed=1)
    got = synthetic.closed_loop_log(ol, gain=0.4, noise_rms=0.1, seed=seed)
    ref = synthetic.closed_loop_log(ol, gain=0.4, noise_rms=0.1, seed=7)
    np.testing.assert_array_equal(got.coeffs, ref.coeffs)  # the same draws
    recorded = got.metadata["closed_loop"]["seed"]
    assert recorded == 7 and type(recorded) is int
