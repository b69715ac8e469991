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

from .conftest import ar1


@pytest.mark.parametrize("name", ["linear", "arma", "multivariate", "rls"])
@pytest.mark.parametrize("how", ["pickle", "deepcopy"])
def test_a_copy_mid_stream_runs_as_the_original(name, how):
    a = ar1(3)
    p = make_predictor(name).fit(a[:400])
    p.reset()
    for frame in a[400:410]:
        p.update(frame)
    q = pickle.loads(pickle.dumps(p)) if how == "pickle" else copy.deepcopy(p)
    for frame in a[410:450]:
        assert np.array_equal(p.update(frame), q.update(frame))
