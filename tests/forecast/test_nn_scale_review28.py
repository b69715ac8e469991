"""NN fit's warning: the scale note skips constant columns, the failed list (review28, round 28).

``NeuralNetPredictor._scale_note``'s docstring: "a non-constant column's root mean square
above ``_SCALE_LIMIT``" (5). A constant column (a static 10 rad offset, rms 10) is not
trained on (nothing to learn), so it must not be named. Planted bug R28-N3 (the
constant test dropped) escaped ``test_nn_failed_training_round45.py``, as did R28-N4
("and 0 more" after exactly five failed columns). References: the root mean squares
computed here with numpy; scikit-learn's ``MLPRegressor`` by hand for the failed line search.
"""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from modalinfo.forecast import NeuralNetPredictor

from .test_nn_failed_training_round45 import _ar2, _hand


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

def test_five_failed_columns_are_all_named_and_none_counted_as_more():
    """R28-N4: five failed columns are the five named, no "and 0 more" (the list shows
    five: ``abnormal[:5]``). Reference: scikit-learn's own failed line search on each of
    the five identical columns (``_hand`` above)."""
    x = _ar2(400, 9) * 1e4 + 1e5
    model, hand_warnings = _hand(x)
    assert hand_warnings and model.n_iter_ < 100
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        NeuralNetPredictor(standardize=False).fit(np.column_stack([x] * 5))
    ours = [str(w.message) for w in caught if "NeuralNetPredictor.fit" in str(w.message)]
    assert len(ours) == 1
    assert all(f"column {m} after {model.n_iter_}" in ours[0] for m in range(5))
    assert "training of 5 mode(s)" in ours[0] and "more" not in ours[0]
