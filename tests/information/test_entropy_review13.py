"""The wide-bins rule's numbers, each against its outside reference (review13, R13-E1..E5).

References, outside the code under test:
- the Monte Carlo spread of the Kozachenko-Leonenko (k = 3) estimate over 3000 seeded
  draws of n = 1000 (``ksg_entropy``, checked against scipy by tests/information/test_ksg.py):
  the stated standard error's ``n se^2`` must match ``n Var`` on the uniform law (where
  ``Var(ln f) = 0``: the density-free part alone) and on the normal law
  (``Var(ln f(X)) = Var(X^2) / 2^2 = 1/2``); the MC's own relative error is
  ``sqrt(2 / 2999)`` = 2.6 %; the asymptotic formula sat 4.5 % above it at n = 1000;
- the Kozachenko-Leonenko estimate written here from its formula, ``psi(n) - psi(3) +
  mean ln(2 rho_i)`` (scipy's digamma, numpy's brute-force neighbour distances), for the
  excess the warning prints;
- the documented allowances: ``0.2 + z se`` with z = ``scipy.stats.norm.ppf(0.975)``, and
  ``0.2 + 1 / sqrt(n)`` where x has ties.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.special import digamma

from modalinfo.information import BiasRuleWarning
from modalinfo.information.histogram import _wide_bins_reference, histogram_entropy
from modalinfo.information.ksg import ksg_entropy


def _rule(x: np.ndarray) -> tuple[float, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        h = histogram_entropy(x)
    return h, [str(w.message) for w in caught if issubclass(w.category, BiasRuleWarning)]


@pytest.mark.parametrize("law", ["uniform", "normal"])
def test_the_stated_standard_error_is_the_estimates_spread(law):
    def draw(seed, n=1000):
        rng = np.random.default_rng(seed)
        return rng.random(n) if law == "uniform" else rng.standard_normal(n)

    mc = 1000 * np.var([ksg_entropy(draw(s)) for s in range(3000)], ddof=1)
    stated = np.mean([1000 * _wide_bins_reference(draw(10**6 + s), 10, "miller-madow")[1] ** 2
                      for s in range(50)])
    assert 0.9 < stated / mc < 1.15, (stated, mc)


def _kl(x: np.ndarray, k: int = 3) -> float:
    d = np.abs(x[:, None] - x[None, :])
    rho = np.sort(d, axis=1)[:, k]  # column 0 is the point itself
    n = x.size
    return float(digamma(n) - digamma(k) + np.mean(np.log(2 * rho)))


def _warned_draws(law, n, ties=None):
    out = []
    for seed in range(30):
        x = law.rvs(size=n, random_state=np.random.default_rng(seed))
        if ties is not None:
            x = np.round(x, ties)
        h, rule = _rule(x)
        if rule:
            out.append((x, h, rule[0]))
        if len(out) == 3:
            break
    assert len(out) == 3
    return out


def test_the_printed_excess_is_over_the_kozachenko_leonenko_estimate():
    for x, h, message in _warned_draws(stats.lognorm(1.5), 300):
        excess = float(re.search(r"give ([0-9.e-]+) nats more than", message).group(1))
        assert excess == pytest.approx(h - _kl(x), abs=6e-4)  # printed to 3 digits


def test_the_allowance_is_1_96_standard_errors():
    z = stats.norm.ppf(0.975)
    for _, _, message in _warned_draws(stats.lognorm(1.5), 300):
        found = re.search(r"above the rule ([0-9.e-]+) \(0\.2 \+ 1\.96 x its standard error "
                          r"([0-9.e-]+);", message)
        allowed, se = float(found.group(1)), float(found.group(2))
        # se printed to 2 significant digits, allowed to 3: half a unit of each
        half_se = 0.5 * 10 ** (math.floor(math.log10(se)) - 1)
        half_allowed = 0.5 * 10 ** (math.floor(math.log10(allowed)) - 2)
        assert allowed == pytest.approx(0.2 + z * se, abs=half_allowed + z * half_se)
        assert half_allowed + z * half_se < (z - 1.645) * se  # z = 1.645 would fail


def test_with_ties_the_allowance_is_one_over_root_n():
    n = 300
    for _, _, message in _warned_draws(stats.lognorm(1.5), n, ties=2):
        found = re.search(r"above the rule ([0-9.e-]+) \(0\.2 \+ 1/sqrt\(n\)\)", message)
        assert float(found.group(1)) == pytest.approx(0.2 + 1 / math.sqrt(n), abs=6e-4)
