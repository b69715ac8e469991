"""Removing a replacement of a built-in MI method restores the built-in (round 45 PART a).

R20 / R31 / R32. Reference: the built-in ``gaussian`` method's value (its bits)
before any registry change; the replacement's closed form -ln(1 - r^2) of numpy's sample
correlation (twice the Gaussian MI, so it cannot pass for the built-in).
``register_method(..., replace=True)`` of ``gaussian`` then ``unregister_method("gaussian")``
removed ``gaussian`` for the process: ``mutual_information(..., "gaussian")`` was refused,
and ``select_inputs`` called without ``method`` answered "`method` must be one of 'kde',
'histogram', 'ksg'; got 'gaussian'" to a caller who never passed one.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import (
    MIMethod,
    mutual_information,
    register_method,
    select_inputs,
    unregister_method,
)
from modalinfo.information.methods import get_method


class _Double:
    """A replacement engine: twice the Gaussian closed form (so it cannot pass for it)."""

    def fit(self, x):
        self.x = x
        return self

    def score(self, y):
        r = np.corrcoef(self.x, y)[0, 1]
        return -np.log(1.0 - r * r)


def _pair():
    return np.random.default_rng(0).multivariate_normal([0, 0], [[1, .6], [.6, 1]], 2000).T


def test_unregistering_a_replacement_restores_the_builtin():
    x, y = _pair()
    r = np.corrcoef(x, y)[0, 1]
    builtin = get_method("gaussian")
    before = mutual_information(x, y, method="gaussian")
    data = np.column_stack([x, y])
    chosen = select_inputs(data, target=0, intervals=False, n_surrogates=19, seed=1).inputs
    replacement = register_method(MIMethod(name="gaussian", engine=_Double), replace=True)
    try:
        assert mutual_information(x, y, method="gaussian") == pytest.approx(
            -np.log(1 - r * r), rel=1e-12)
        assert unregister_method("gaussian") is replacement
        assert get_method("gaussian") is builtin
        assert mutual_information(x, y, method="gaussian") == before  # same bits
        again = select_inputs(data, target=0, intervals=False, n_surrogates=19, seed=1)
        assert again.inputs == chosen
    finally:
        if get_method("gaussian") is not builtin:
            register_method(builtin, replace=True)


def test_a_removed_builtin_is_named_as_removed():
    x, y = _pair()
    builtin = get_method("gaussian")
    assert unregister_method("gaussian") is builtin
    try:
        message = (r"`method`='gaussian': the built-in method 'gaussian' was unregistered "
                   r"in this process \(unregister_method\); re-register it with "
                   r"register_method\(modalinfo.information.gaussian.METHOD\)")
        with pytest.raises(ValueError, match=message):
            mutual_information(x, y, method="gaussian")
        with pytest.raises(ValueError, match=message):
            select_inputs(np.column_stack([x, y]), target=0)  # its default method
    finally:
        register_method(builtin)
    assert get_method("gaussian") is builtin
