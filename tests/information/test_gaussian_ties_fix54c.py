"""The plain Gaussian MI / CMI (``copula=False``) of a discrete column is judged (fix54-c).

Reference: the exact MI of a discrete x through additive Gaussian noise,
``h(y) - h(y | x)`` with h(y) of the normal mixture integrated by ``scipy.integrate.quad``;
the rule judged is the copula path's (``ksg.gaussian_ties_why``: the value against the
KSG of the same columns, max(0.05 nats, 10 %)). Measured in docs/ADVERSARIAL.md,
"Discrete levels and ties in the estimators (fix54-c)".
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import integrate, stats

from modalinfo.information import conditional_mutual_information, mutual_information
from modalinfo.information.methods import BiasRuleWarning

N = 2000


def _exact_mi(weights, means, sd: float) -> float:
    """I(x; x + N(0, sd^2)) of a discrete x with levels ``means`` of shares ``weights``."""

    def f(y: float) -> float:
        return sum(w * stats.norm.pdf(y, m, sd) for w, m in zip(weights, means, strict=True))

    h_y = integrate.quad(lambda y: -f(y) * math.log(f(y)) if f(y) > 0 else 0.0, -20, 20,
                         points=list(means), limit=400)[0]
    return h_y - 0.5 * math.log(2 * math.pi * math.e * sd * sd)


def _pile_of_three(seed: int):
    """90 % of x at 0, 5 % at each of -1 and +1; y = x + N(0, 0.3^2)."""
    rng = np.random.default_rng(seed)
    u = rng.random(N)
    x = np.where(u < 0.9, 0.0, np.where(u < 0.95, -1.0, 1.0))
    return x, x + 0.3 * rng.standard_normal(N), rng.standard_normal(N)


def test_plain_gaussian_mi_of_a_90_percent_level_is_warned():
    """copula=False read 0.383 for the exact 0.307 (+25 %) without a word before."""
    exact = _exact_mi([0.05, 0.9, 0.05], [-1.0, 0.0, 1.0], 0.3)
    x, y, _ = _pile_of_three(0)
    with pytest.warns(BiasRuleWarning, match=r"copula=False.*method='ksg'") as rec:
        got = mutual_information(x, y, method="gaussian", copula=False)
    assert got - exact > max(0.05, 0.1 * exact)  # what the warning is about
    assert "`x` 3" in str(rec[0].message)


def test_plain_gaussian_cmi_of_a_90_percent_level_is_warned():
    """The CMI's point estimate with an independent z: the same value, the same rule."""
    exact = _exact_mi([0.05, 0.9, 0.05], [-1.0, 0.0, 1.0], 0.3)
    x, y, z = _pile_of_three(1)
    with pytest.warns(BiasRuleWarning, match="copula=False"):
        got = conditional_mutual_information(x, y, z, method="gaussian", copula=False)
    assert got - exact > max(0.05, 0.1 * exact)


def test_plain_gaussian_within_tolerance_is_silent():
    """A 5-level uniform x through N(0, 0.7^2): 0.819 for the exact 0.778, within 10 %."""
    exact = _exact_mi([0.2] * 5, [0.0, 1.0, 2.0, 3.0, 4.0], 0.7)
    rng = np.random.default_rng(2)
    x = rng.integers(0, 5, N).astype(float)
    y = x + 0.7 * rng.standard_normal(N)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = mutual_information(x, y, method="gaussian", copula=False)
    assert abs(got - exact) < max(0.05, 0.1 * exact)
