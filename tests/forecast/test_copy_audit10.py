"""``copy.copy`` of a fitted predictor is independent (audit 10-state, rows copy-shallow-*).

Reference: a second predictor fitted on the same samples and fed the same frames, which
nothing else touches. Before the fix ``copy.copy`` shared the running state, so five
``update`` calls on the copy advanced the original's forecasts.
"""

import copy

import numpy as np
import pytest

from modalinfo.forecast import ARMAPredictor, make_predictor

from .conftest import ar1


def _started(make, a):
    p = make().fit(a[:400])
    p.reset()
    for frame in a[400:410]:
        p.update(frame)
    return p


@pytest.mark.parametrize("make", [
    lambda: make_predictor("linear"), lambda: make_predictor("arma"),
    lambda: make_predictor("multivariate"), lambda: make_predictor("rls"),
    lambda: ARMAPredictor(order=(2, 1), horizon=2, refit_every=20, window=100),
])
def test_a_shallow_copy_does_not_advance_the_original(make):
    a = ar1(5)
    p, untouched = _started(make, a), _started(make, a)
    q = copy.copy(p)
    for frame in a[410:415]:  # the copy runs ahead on other samples
        q.update(frame + 1.0)
    for frame in a[410:500]:
        assert np.array_equal(p.update(frame), untouched.update(frame))
    # and the copy continues its own stream: the same as a fresh one fed its samples
    fresh = _started(make, a)
    for frame in a[410:415]:
        fresh.update(frame + 1.0)
    for frame in a[500:520]:
        assert np.array_equal(q.update(frame), fresh.update(frame))
