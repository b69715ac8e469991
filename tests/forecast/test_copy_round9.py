"""Fitted predictors survive pickle and deepcopy (adversarial round 9, rows f-deepcopy, pk-*).

Reference: round trips. A copy made mid-stream must give, update for update, the bits
the original gives on the same samples (before the fix a deep copy's ``update`` advanced
the original's state arrays, and pickling any fitted predictor raised AttributeError).
"""

import copy
import pickle

import numpy as np
import pytest

from modalinfo.forecast import make_predictor


def _ar1(n: int = 600) -> np.ndarray:
    rng = np.random.default_rng(3)
    e = rng.standard_normal((n, 2))
    a = np.zeros((n, 2))
    for t in range(1, n):
        a[t] = 0.9 * a[t - 1] + e[t]
    return a


@pytest.mark.parametrize("name", ["linear", "arma", "multivariate", "rls"])
@pytest.mark.parametrize("how", ["pickle", "deepcopy"])
def test_a_copy_mid_stream_runs_as_the_original(name, how):
    a = _ar1()
    p = make_predictor(name).fit(a[:400])
    p.reset()
    for frame in a[400:410]:
        p.update(frame)
    q = pickle.loads(pickle.dumps(p)) if how == "pickle" else copy.deepcopy(p)
    for frame in a[410:450]:
        assert np.array_equal(p.update(frame), q.update(frame))
