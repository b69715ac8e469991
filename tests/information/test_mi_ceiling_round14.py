"""Round 14 PART a: a histogram MI that its bins cannot hold is said to be a lower bound.

References (outside the code): the exact MI of a bivariate normal pair,
``-0.5 ln(1 - rho^2)`` (Cover & Thomas 2006, Example 8.5.1); the Gaussian-copula MI
as a lower bound of any continuous pair's MI (Ince et al., Hum. Brain Mapp. 38, 1541,
2017), computed here with numpy / scipy (``scipy.stats.rankdata``, ``ndtri``); the
plug-in MI of a discrete variable with itself, its entropy (Cover & Thomas, eq. 2.42).
"""

import math
import warnings

import numpy as np
import pytest
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.information import BiasRuleWarning, mutual_information, mutual_information_ci


def _pair(rho: float, n: int, seed: int):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, rho * x + math.sqrt(1.0 - rho * rho) * rng.standard_normal(n)


def _copula_mi(x, y) -> float:
    sx = ndtri(rankdata(x) / (x.size + 1))
    sy = ndtri(rankdata(y) / (y.size + 1))
    r = np.corrcoef(sx, sy)[0, 1]
    return -0.5 * math.log(1.0 - r * r)


def test_a_nearly_deterministic_pair_is_warned_to_be_a_lower_bound():
    # rho = 0.999999, n = 2000: exact 6.56 nats; the 45 x 45 table holds ln 45 = 3.81 at
    # most (the estimate was 3.71 with no word); the copula MI (~6) is a lower bound
    x, y = _pair(0.999999, 2000, 3)
    exact = -0.5 * math.log(1.0 - 0.999999**2)
    with pytest.warns(BiasRuleWarning, match="Gaussian-copula MI.*lower bound"):
        got = mutual_information(x, y, method="histogram")
    assert got < math.log(45) < _copula_mi(x, y) < exact


def test_its_confidence_interval_says_so_in_the_note_and_a_warning():
    # the bootstrap interval takes only the spread: it lay ~35 half-widths below 6.56
    x, y = _pair(0.999999, 2000, 3)
    exact = -0.5 * math.log(1.0 - 0.999999**2)
    with pytest.warns(BiasRuleWarning, match="Gaussian-copula MI"):
        res = mutual_information_ci(x, y, seed=0, n_resamples=49)
    assert res.high < exact  # the interval misses the MI: hence the note
    assert "lower bound" in res.note


@pytest.mark.parametrize("rho", [0.0, 0.6, 0.9, 0.99])
def test_resolved_gaussian_pairs_are_not_warned(rho):
    # within 10 % of the exact MI (the rule's tolerance): no word at n = 2000
    x, y = _pair(rho, 2000, 5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = mutual_information(x, y, method="histogram")
    exact = -0.5 * math.log(1.0 - rho * rho)
    assert abs(got - exact) <= max(0.05, 0.1 * exact)


def test_a_discrete_variable_with_itself_is_not_judged():
    # I(X; X) of a variable on a lattice is its entropy, which the table holds exactly
    x = np.round(np.random.default_rng(10).standard_normal(5000), 1)
    _, counts = np.unique(x, return_counts=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = mutual_information(x, x, method="histogram")
    p = counts / x.size
    assert got <= -np.sum(p * np.log(p)) + 1e-9
