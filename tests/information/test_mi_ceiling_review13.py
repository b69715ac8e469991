"""The histogram's Gaussian-copula rule at its documented edges (review13, R13-A1, A2, A5).

References, outside the code under test: the Gaussian-copula MI ``-0.5 ln(1 - r^2)`` of
the normal scores ``Phi^-1(rank / (n + 1))`` (Ince et al. 2017), computed here with
scipy (``rankdata``, ``ndtri``) and numpy; the exact MI of a bivariate normal pair,
``-0.5 ln(1 - rho^2)``; a k x k table holds ln k nats at most (Cover & Thomas 2006,
Thm 2.6.4). The documented rule (``histogram_copula_rule``): judged where the copula MI
g >= 0.5 nats, warned where the estimate is below g by more than
``max(0.05, 0.1 g, 3 |r| / sqrt(n))``; caller-chosen bins are not judged.
"""

import math
import warnings

import numpy as np
import pytest
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.information import mutual_information
from modalinfo.information.histogram import histogram_copula_rule


def _pair(rho: float, n: int, seed: int):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, rho * x + math.sqrt(1.0 - rho * rho) * rng.standard_normal(n)


def _copula(x, y) -> tuple[float, float]:
    sx = ndtri(rankdata(x) / (x.size + 1))
    sy = ndtri(rankdata(y) / (y.size + 1))
    r = float(np.corrcoef(sx, sy)[0, 1])
    return r, -0.5 * math.log(1.0 - r * r)


def test_the_tolerance_is_ten_percent_of_the_copula_mi():
    # n = 20000, rho = 0.99: g ~ 1.96, 3 |r| / sqrt(n) = 0.021 < 0.1 g = 0.196
    x, y = _pair(0.99, 20000, 1)
    r, g = _copula(x, y)
    assert 3 * abs(r) / math.sqrt(x.size) < 0.05 < 0.1 * g
    assert histogram_copula_rule(g * (1 - 0.115), x, y) is not None  # 11.5 % below: warned
    assert histogram_copula_rule(g * (1 - 0.085), x, y) is None  # 8.5 % below: silent


def test_the_rule_judges_from_half_a_nat():
    # rho = 0.83: g ~ 0.58 >= 0.5, judged; an estimate 0.2 nats below is beyond 0.1 g
    x, y = _pair(0.83, 20000, 2)
    _, g = _copula(x, y)
    assert 0.52 < g < 0.65
    assert histogram_copula_rule(g - 0.2, x, y) is not None
    # rho = 0.75: g ~ 0.42 < 0.5, not judged whatever the estimate
    x, y = _pair(0.75, 20000, 2)
    _, g = _copula(x, y)
    assert g < 0.48
    assert histogram_copula_rule(0.0, x, y) is None


@pytest.mark.parametrize("bins", [5, (5, 5)])
def test_bins_the_caller_chose_are_not_judged(bins):
    # rho = 0.99, n = 2000: exact 1.96 nats, 5 x 5 bins hold ln 5 = 1.61 at most; the
    # caller chose them, so no copula warning (the docstring: rule-chosen bins only)
    x, y = _pair(0.99, 2000, 3)
    _, g = _copula(x, y)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = mutual_information(x, y, method="histogram", bins=bins)
    assert got <= math.log(5) + 1e-9 < g - max(0.05, 0.1 * g)  # the rule's case
    assert not [w for w in caught if "Gaussian-copula" in str(w.message)]
