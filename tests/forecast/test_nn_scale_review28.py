"""The scale note of ``standardize=False`` skips constant columns (review28, round 28).

``NeuralNetPredictor._scale_note``'s docstring: "a non-constant column's root mean square
above ``_SCALE_LIMIT``" (5). A constant column (a static 10 rad offset, rms 10) is not
trained on (nothing to learn), so it must not be named. Planted bug R28-N3 (the
constant test dropped) escaped ``test_nn_failed_training_round45.py``. Reference: the
root mean squares computed here with numpy.
"""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from modalinfo.forecast import NeuralNetPredictor


def _ar2(n, seed):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n + 200)
    x = np.zeros(n + 200)
    for t in range(2, n + 200):
        x[t] = 1.6 * x[t - 1] - 0.7 * x[t - 2] + e[t]
    return x[200:]


def test_a_constant_column_far_from_unit_scale_is_not_named():
    x = _ar2(2000, 9)
    X = np.column_stack([x, np.full_like(x, 10.0)])
    rms = np.sqrt(np.mean(X ** 2, axis=0))
    assert rms[0] < 5 < rms[1]  # the varying column within the limit, the constant beyond
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        NeuralNetPredictor(standardize=False, max_iter=20).fit(X)
    scale = [w for w in caught if issubclass(w.category, ConvergenceWarning)
             and "root mean square" in str(w.message)]
    assert scale == []
