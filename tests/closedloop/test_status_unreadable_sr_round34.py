"""A loop that closes at an SR too small to show it (adversarial round 34 PART b, D06).

Reference: Noll's fitting law and residual histories built here. A 27-mode DM on an
8 m telescope at D/r0 = 87 (630 nm) leaves Noll's 0.2944 x 28^(-sqrt(3)/2) x
87^(5/3) = 28 rad^2: the simulated residual fell from 594 to 25 rad^2 and stayed, yet
the status read "did not close" - the SR exp(-25) = 1e-11 swings in its band down to
the open-loop SR. Here the residual falls from 594 rad^2 to 25 rad^2, drifting up
by 0.01 rad^2 a frame, so the SR's second half is below its first (not "still
converging"), while the residual's second-half mean is within 10 % of its earlier mean
(steady); it is below half the open-loop level from the first frame that sees a
command, so the loop closed (``exp(-median)`` of the second half recomputed here is
below 1e-3). A loop whose SR is readable keeps "did not close" (round 24's band rule).
Fast: hand-built results, no simulation.
"""

from __future__ import annotations

import numpy as np

from .test_result_views import _result

N = 100


def test_fitting_limited_loop_is_closed_not_did_not_close():
    k = np.arange(N)
    v = 25.0 + 0.01 * k + 0.5 * np.sin(2 * np.pi * k / 5)
    v[0] = 594.0
    assert np.all(v[2:] < 0.5 * v[0])  # below half the open loop from frame 2 on
    sr = np.exp(-v)
    assert np.median(sr[N // 2:]) < 1e-3 and sr[N // 2:].mean() < sr[2:N // 2].mean()
    r = _result(v)
    status = r.loop_status
    assert status.startswith("closed, SR too small to show it:"), status
    assert "did not close" not in status
    # the window stays the second half's: the numbers do not move
    assert not r.closed and r.averaging_start == N // 2
    assert v[N // 2:].mean() < 1.1 * v[2:N // 2].mean()


def test_readable_sr_that_swings_still_reads_did_not_close():
    k = np.arange(N)
    sr = 0.22 - 0.0004 * k + 0.15 * np.sin(2 * np.pi * k / 7)
    sr[0] = 1e-15
    assert _result(-np.log(sr)).loop_status.startswith("did not close:")
