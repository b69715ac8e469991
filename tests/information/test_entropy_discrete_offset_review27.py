"""The discrete-levels tolerance is a fraction of the range, not of the magnitude (review27).

Planted bug of review27 (docs/MUTATION.md, round 27) that the round-41 file let through:
the 1e-9 tolerance taken of ``max |x|`` instead of the range (every tested sample was
centred on 0, where the two agree within a factor 2). A normal sample about 1e7 then had
its neighbours within 1e-2 merged into a few "levels" and was refused as discrete.
Reference: the entropy is translation-invariant; the normal's ``0.5 ln(2 pi e)`` (Cover &
Thomas, eq. 8.9), as the round-41 file.
"""

from __future__ import annotations

import math

import numpy as np

from modalinfo.information import entropy


def test_a_continuous_sample_far_from_zero_is_not_refused():
    x = np.random.default_rng(27).standard_normal(20000)
    moved = x + 1e7
    assert np.unique(moved).size > 0.99 * x.size  # float64 keeps them apart at 1e7
    value = entropy(moved, method="kde")
    assert abs(value - 0.5 * math.log(2 * math.pi * math.e)) < 0.1
    assert abs(value - entropy(x, method="kde")) < 1e-3
