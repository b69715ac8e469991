"""Planted-bug review 24 (issue 27): the unreadable-SR closure needs a steady residual.

Reference: residual histories built here and their means with numpy. A residual that
falls from 594 rad^2 to 25 rad^2 and then rises so that its second half's mean is 1.2x
its mean from the closure to mid-run is not steady (the rule's bound is 10 %): the
status stays "did not close", though the SR (exp(-v) < 1e-3) cannot show anything.
"""

from __future__ import annotations

import numpy as np

from .test_result_views import _result

N = 100


def test_a_residual_rising_by_a_fifth_is_not_called_closed():
    k = np.arange(N)
    v = 25.0 * (1.0 + 0.0045 * k)
    v[0] = 594.0
    assert np.all(v[2:] < 0.5 * v[0])
    ratio = v[N // 2:].mean() / v[1:N // 2].mean()
    assert 1.15 < ratio < 1.25
    assert np.median(np.exp(-v[N // 2:])) < 1e-3
    status = _result(v).loop_status
    assert status.startswith("did not close:"), status
