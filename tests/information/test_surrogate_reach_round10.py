"""The least surrogate count named by the refusal reaches alpha (round 10 PART a).

Reference: the exact Monte-Carlo p-value's smallest value 1 / (S + 1) (Phipson & Smyth
2010) compared with alpha in IEEE arithmetic: the count the message names must pass
the same comparison, one fewer must fail it.
"""

import re

import numpy as np
import pytest

from modalinfo.information.resampling import check_surrogates_reach


@pytest.mark.parametrize("alpha", [0.05, np.nextafter(0.05, 0.0), 0.01, 1 / 3, 0.049])
def test_named_count_is_the_least_that_reaches(alpha):
    with pytest.raises(ValueError) as err:
        check_surrogates_reach(1, alpha)
    least = int(re.search(r"n_surrogates >= (\d+)", str(err.value)).group(1))
    check_surrogates_reach(least, alpha)  # reaches
    if least > 1:
        with pytest.raises(ValueError):
            check_surrogates_reach(least - 1, alpha)


def test_alpha_and_smallest_p_print_differently():
    with pytest.raises(ValueError) as err:
        check_surrogates_reach(19, np.nextafter(0.05, 0.0))
    m = re.search(r"`alpha`=([^:]+): .* = ([0-9.e-]+) \(", str(err.value))
    assert m.group(1) != m.group(2)
