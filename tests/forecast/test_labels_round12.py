"""Round 12 PART a (issue 27): ``evaluate`` keeps a pandas DataFrame's column names.

Reference: pandas' ``DataFrame.columns``, the labels the scientist gave; an array
without names keeps the generic ``mode0, mode1, ...``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from modalinfo.forecast import LinearPredictor, evaluate


def test_evaluate_labels_are_the_dataframe_columns():
    a = np.random.default_rng(0).standard_normal((400, 2)).cumsum(axis=0)
    ev = evaluate([LinearPredictor()], pd.DataFrame(a, columns=["Z5", "Z6"]), horizons=[1])
    assert ev.labels == ("Z5", "Z6")
    assert evaluate([LinearPredictor()], a, horizons=[1]).labels == ("mode0", "mode1")
