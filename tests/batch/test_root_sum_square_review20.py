"""Review20: batch's ``rms_total`` / ``std_total`` root-sum-square against ``math.hypot``.

Reference, outside the code: Python's ``math.hypot`` (exact scaling, no overflow or
underflow; ``hypot(..., inf) = inf``) of the non-NaN values; NaN modes are skipped, as
``nansum`` skipped them before round 26 PART b.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.batch.analyses import _root_sum_square


@pytest.mark.parametrize("values", [
    [3.0, 4.0],
    [3.0, np.nan, 4.0],
    [1e300, 1e300, np.nan],
    [1e-300, 2e-300],
    [0.0, 0.0],
    [2.0, np.inf, np.nan],   # a mode whose RMS overflowed: the total is infinite too
    [np.nan, np.nan],
])
def test_root_sum_square_is_hypot_of_the_non_nan_values(values):
    arr = np.array(values, dtype=float)
    want = math.hypot(*arr[~np.isnan(arr)])
    got = _root_sum_square(arr)
    assert got == pytest.approx(want, rel=1e-15) or (math.isinf(want) and got == want)
