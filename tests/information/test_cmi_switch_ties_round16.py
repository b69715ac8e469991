"""The histogram CMI's switch to KSG is not undone by one repeated value.

References (outside the code under test): the exact CMI of a Gaussian triple,
``-0.5 ln(1 - rho^2)`` with the partial correlation rho = 0.8 (0.511 nats), and the
loss of equiprobable bins at k = 7 per axis (19 % at rho = 0.8, module notes of
``modalinfo.information.conditional``, "Resolution rule", exact cell probabilities).
Round 16 PART a: a single duplicated value in x (or a log at 1e12 +- 1, whose float
spacing repeats values) made the column "not continuous", so the rule's switch was
skipped and the 7-bin histogram returned 0.437 nats without a word. The bound 0.06 is
about three standard deviations of the KSG CMI at n = 2000 (its spread over seeds in
tests/information/test_conditional.py's regime is ~0.02 nats).
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, conditional_mutual_information

EXACT = -0.5 * np.log(1 - 0.64)


@pytest.fixture(scope="module")
def triple():
    rng = np.random.default_rng(7)
    n = 2000
    z, e1, e2 = rng.standard_normal((3, n))
    return z + e1, z + 0.8 * e1 + 0.6 * e2, z


@pytest.mark.parametrize("how", ["one duplicated value", "offset 1e12"])
def test_switch_holds_with_a_few_ties(triple, how):
    x, y, z = triple
    if how == "one duplicated value":
        x = x.copy()
        x[1] = x[0]
    else:
        x, y, z = x + 1e12, y + 1e12, z + 1e12
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = conditional_mutual_information(x, y, z, method="histogram")
    assert abs(got - EXACT) < 0.06
    assert any(issubclass(w.category, BiasRuleWarning) and "KSG CMI instead" in str(w.message)
               for w in caught)
