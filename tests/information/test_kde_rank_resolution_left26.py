"""The kde MI warns where the ranks of n samples cannot resolve it (near |rho| = 1).

Issue 27, left26-kde item 1 (adversarial round 26 PART a: at n = 2000, rho = 0.999999,
3 seeds read 6.24-7.02 against the exact 6.56, with no word). References, outside the
code: the exact MI of a bivariate normal pair, -0.5 ln(1 - rho^2), and the entropy of
a rank uniform on n values, ln n, the most the ranks (hence normal scores) of n
samples can tell about a pair. The rule warns within 2 nats of ln n; at rho = 0.999999
the exact MI 6.56 is above ln 2000 - 2 = 5.60 and 20 of 20 seeds warned (estimates
5.93-7.09), at rho = 0.999 (exact 3.11) 0 of 100 did (largest estimate 3.13, 2.5 nats
below the rule): the cases below are far from the line, not on rounding luck.
``copula=False`` (raw values), the way out the warning names, does not warn and is
within 0.1 nats of the exact MI there (round 26: 6.55-6.58; 0.1 is 4.5 times the
standard error rho / sqrt(n) = 0.022 of a Gaussian MI estimate, from Fisher's z).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, mutual_information

N = 2000


def _pair(rho: float, seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(N)
    return x, rho * x + math.sqrt(1.0 - rho * rho) * rng.standard_normal(N)


def _rank_warnings(x, y, **options) -> tuple[float, list]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method="kde", **options)
    return value, [w for w in caught if "ranks of n" in str(w.message)]


def test_warns_where_the_ranks_bind():
    x, y = _pair(0.999999)
    with pytest.warns(BiasRuleWarning, match=r"within 2 nats of ln n = 7\.601.*n = 2000.*"
                      r"copula=False") as record:
        mutual_information(x, y, method="kde")
    assert record[0].filename == __file__
    assert math.log(N) - 2.0 < -0.5 * math.log1p(-0.999999**2)  # the exact MI is past it


@pytest.mark.parametrize("rho", [0.9, 0.999])
def test_silent_below(rho):
    x, y = _pair(rho)
    value, got = _rank_warnings(x, y)
    assert got == []
    assert value < math.log(N) - 2.0


def test_copula_false_is_the_way_out():
    x, y = _pair(0.999999)
    value, got = _rank_warnings(x, y, copula=False)
    assert got == []
    assert value == pytest.approx(-0.5 * math.log1p(-0.999999**2), abs=0.1)
