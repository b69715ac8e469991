"""Orders given as dates or durations are refused, not read as indices.

Reference (outside the code): NumPy's dtype kinds (``numpy.dtype.kind``): 'i'/'u' are
integers, 'm' a timedelta64 and 'M' a datetime64, whose values are durations or
instants, not positions; yet ``numpy.timedelta64`` derives from ``numpy.signedinteger``
(``np.issubdtype('m8[s]', np.integer)`` is True), so a check by that test lets them in.
Identical integer orderings agree exactly (Spearman rho = Kendall tau = 1).

Planted bug R8-45 (docs/MUTATION.md, round 8): ``fitting_error.check_order`` back on
``np.issubdtype(dtype, np.integer)`` accepted a timedelta64 order; the tests before
gave float and masked orders only.
"""
from __future__ import annotations

import numpy as np
import pytest

from modalinfo.ordering import rank_agreement


def test_timedelta_orders_are_refused_naming_the_argument():
    assert np.issubdtype(np.dtype("m8[s]"), np.integer)  # the trap the rule avoids
    assert rank_agreement(np.array([2, 0, 1]), [2, 0, 1]) == pytest.approx((1.0, 1.0))
    with pytest.raises(TypeError, match="`order_a` must be a 1-D sequence of ints"):
        rank_agreement(np.array([2, 0, 1], dtype="m8[s]"), [2, 0, 1])
    with pytest.raises(TypeError, match="`order_b` must be a 1-D sequence of ints"):
        rank_agreement([2, 0, 1], np.array([2, 0, 1], dtype="m8[ms]"))
