"""``marechal_strehl`` refuses text by name (round 41 PART a C24, C25).

Reference: the Marechal law ``exp(-sigma^2)`` (numpy) for numbers; a str is not a
variance: '0.1' was parsed to 0.9048 and 'abc' raised numpy's "could not convert string
to float" naming no argument.
"""

import math

import numpy as np
import pytest

from closedloop.optics.science import marechal_strehl


@pytest.mark.parametrize("value", ["0.1", "abc", ["0.1", "0.2"]])
def test_text_is_refused_naming_variance(value):
    with pytest.raises(TypeError, match="`variance`"):
        marechal_strehl(value)


def test_numbers_still_follow_marechal():
    got = marechal_strehl([0.0, 0.1, 1.0, np.inf])
    np.testing.assert_allclose(got, [1.0, math.exp(-0.1), math.exp(-1.0), 0.0], rtol=1e-15)
