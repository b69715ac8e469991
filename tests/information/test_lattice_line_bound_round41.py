"""A 4-valued line's unresolved MI is not called a lower bound alone (round 41 PART a V13).

Reference: ``x_t = cos(pi t / 2 + 0.4)`` (a line at a quarter of the frame rate) takes 4
values, so ``I(x_t; x_t+1) <= H(x_t) = ln 4 = 1.386`` (Cover & Thomas 2006, Thm 2.6.5
with entropy of 4 equiprobable values). The histogram estimate is 1.62, above that
bound, and the convergence rule's warning said "the value is a lower bound" without
qualification.
"""

import math
import warnings

import numpy as np

from modalinfo.information import BiasRuleWarning, mutual_information


def test_lattice_warning_says_the_estimate_can_exceed_the_mi():
    n = 20_000
    x = np.cos(np.pi * np.arange(n + 1) / 2 + 0.4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = mutual_information(x[:-1], x[1:], method="histogram")
    assert value > math.log(4)  # the estimate is above the MI's ceiling
    said = [str(w.message) for w in caught if issubclass(w.category, BiasRuleWarning)]
    assert len(said) == 1
    assert "can exceed their MI" in said[0]
