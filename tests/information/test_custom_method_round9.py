"""A registered method whose engine returns a non-number is named (round 9, r-custom-str).

Reference: the MIMethod contract (``score(y)`` gives I(x; y) in nats). A custom engine
returning the closed form -0.5 ln(1 - r^2) of the sample correlation equals the built-in
gaussian method's value on the same pair (the gaussian method's own rule); one returning
a string was refused with Python's "could not convert string to float: 'abc'", naming
nothing of the package.
"""

import numpy as np
import pytest

from modalinfo.information import (
    MIMethod,
    mutual_information,
    register_method,
    unregister_method,
)


class _Corr:
    def fit(self, x):
        self.x = x
        return self

    def score(self, y):
        r = np.corrcoef(self.x, y)[0, 1]
        return -0.5 * np.log(1.0 - r * r)


class _Text(_Corr):
    def score(self, y):
        return "abc"


def test_custom_engines():
    x, y = np.random.default_rng(0).multivariate_normal([0, 0], [[1, .6], [.6, 1]], 3000).T
    register_method(MIMethod(name="r9corr", engine=_Corr))
    register_method(MIMethod(name="r9text", engine=_Text))
    try:
        r = np.corrcoef(x, y)[0, 1]
        assert mutual_information(x, y, method="r9corr") == pytest.approx(
            -0.5 * np.log(1 - r * r), rel=1e-12)
        with pytest.raises(TypeError, match="method='r9text'.*real number.*'abc'"):
            mutual_information(x, y, method="r9text")
    finally:
        unregister_method("r9corr")
        unregister_method("r9text")
