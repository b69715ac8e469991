"""The spread rule's neighbour terms against the docstring's D, both ways (review33).

Mutation round 33 (docs/MUTATION.md): fix50-c added ``|eta2(b | a) - r^2|`` and
``|eta2(a | b) - r^2|`` to ``copula.spread_dependence``'s D; review32's numpy reference
of D (``test_spread_dependence_review32._reference``: scipy ``rankdata`` / ``norm.ppf``
scores, numpy's sorts and means) was run on pairs whose D is a moment term, and fix50-c's
sine pair only as y = sin(2 pi x) + e, so D computing eta2(b | a) twice (one direction
lost) passed both. Here the reference is compared where the neighbour terms are the
maximum: the sine pair in both orders (x = sin(2 pi y) + e has eta2(x | y) ~0.33 and
eta2(y | x) ~0), and D is symmetric in its arguments as its formula is.
"""

import math

import numpy as np
import pytest

from modalinfo.information.copula import spread_dependence, spread_dependence_limit

from .test_spread_dependence_review32 import _reference


def _sine(n, seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, np.sin(2 * math.pi * x) + rng.standard_normal(n)


@pytest.mark.parametrize("n", [2000, 20000])
@pytest.mark.parametrize("reverse", [False, True])
def test_d_is_the_docstrings_where_a_neighbour_term_is_largest(n, reverse):
    x, y = _sine(n, 7)
    if reverse:
        x, y = y, x
    d, m, ties = spread_dependence(x, y)
    d_ref, m_ref = _reference(x, y)
    assert not ties and m == m_ref
    assert d == pytest.approx(d_ref, rel=1e-9, abs=1e-12)
    assert d > spread_dependence_limit(m)  # the curve read one way or the other


def test_d_is_symmetric():
    x, y = _sine(5000, 8)
    assert spread_dependence(x, y)[0] == pytest.approx(spread_dependence(y, x)[0],
                                                       rel=1e-12, abs=1e-14)
