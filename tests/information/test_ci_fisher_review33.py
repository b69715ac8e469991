"""Where ``mutual_information_ci`` takes the Fisher-z interval, and what it refuses (review33).

Mutation round 33 (docs/MUTATION.md): plants in fix50-a's ``_resolve_interval``,
``_fisher_bounds`` and ``check_tail_replicates`` that ``test_ci_fisher_fix50a.py`` let
through. References, from outside the code:

- the docstring's rule: ``"auto"`` is ``"fisher"`` for ``method="gaussian"`` of a continuous
  pair with ``bootstrap="iid"`` at n <= 2,000 (inclusive) or ``"block"`` (fix51-b), else
  ``"normal"``; ``"fisher"``
  is refused for another method and for a discrete pair; it is a spread interval, so
  no tail-replicate count is asked of it (as of ``"normal"``);
- the block bootstrap's Fisher interval from its own replicates with numpy only:
  ``z = arctanh sqrt(1 - e^(-2 I))`` (the inverse of ``I = -0.5 ln(1 - r^2)``), ``z -+
  z_0.975 s_z`` with ``s_z`` the larger of the replicates' s.d. of z and Bartlett's
  ``1 / sqrt(n_eff - 3)`` (fix51-b; no jackknife: the docstring takes it for the iid
  bootstrap only), mapped back by ``ln cosh`` (scipy's ``norm.ppf``); n_eff from the
  lag-1 sample autocorrelations with Kendall's (1954) correction ``r + (1 + 3 r) / n``,
  or Bartlett's full sum to lag n / 10 where fewer (round 52 PART a; numpy's copy in
  test_ci_coverage_fix51b).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from modalinfo.information import mutual_information_ci

from .test_ci_coverage_fix51b import _n_eff


def _pair(rho: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    e = np.random.default_rng(seed).standard_normal((n, 2))
    return e[:, 0], rho * e[:, 0] + math.sqrt(1.0 - rho * rho) * e[:, 1]


def test_auto_takes_fisher_at_n_2000_inclusive() -> None:
    """n = 2,000 is inside the rule (``<=``): the interval is "fisher"."""
    x, y = _pair(0.6, 2000, 1)
    res = mutual_information_ci(x, y, method="gaussian", bootstrap="iid", n_resamples=10,
                                seed=0)
    assert res.interval == "fisher"


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_block_fisher_takes_the_bootstraps_spread_or_bartletts(seed: int) -> None:
    """interval="fisher" with the block bootstrap: numpy's interval of its replicates."""
    x, y = _pair(0.5, 120, 40 + seed)
    res = mutual_information_ci(x, y, method="gaussian", bootstrap="block", block_length=40,
                                interval="fisher", n_resamples=49, seed=seed)

    def z_of(mi):
        return np.arctanh(np.sqrt(1.0 - np.exp(-2.0 * np.asarray(mi))))

    n_eff = _n_eff(x, y)  # the fewer of the lag-1 count and the full sum (round 52 a)
    z_hat = float(z_of(res.estimate))
    s_z = max(float(np.std(z_of(res.bootstrap_distribution), ddof=1)),
              1.0 / math.sqrt(max(n_eff - 3.0, 1.0)))
    half = stats.norm.ppf(0.975) * s_z
    low = 0.0 if z_hat - half <= 0 else math.log(math.cosh(z_hat - half))
    assert res.interval == "fisher"
    assert (res.low, res.high) == pytest.approx((low, math.log(math.cosh(z_hat + half))),
                                                abs=1e-9)


def test_fisher_asks_no_tail_replicates() -> None:
    """10 replicates: a spread interval is given ("fisher" as "normal"), a tail one refused."""
    x, y = _pair(0.6, 100, 2)
    res = mutual_information_ci(x, y, method="gaussian", bootstrap="iid", interval="fisher",
                                n_resamples=10, seed=0)
    assert res.interval == "fisher" and 0.0 <= res.low < res.estimate < res.high
    with pytest.raises(ValueError, match="n_resamples"):
        mutual_information_ci(x, y, method="gaussian", bootstrap="iid", interval="basic",
                              n_resamples=10, seed=0)


def test_fisher_refused_for_a_discrete_pair_and_for_kde() -> None:
    """A discrete pair (its table's MI) and method="kde": "fisher" is refused, "auto" normal."""
    rng = np.random.default_rng(3)
    x = rng.integers(0, 3, 300).astype(float)
    y = (x + rng.integers(0, 2, 300)).astype(float)  # 4 levels: a 3 x 4 table
    with pytest.raises(ValueError, match="`interval`='fisher'.*discrete pair"):
        mutual_information_ci(x, y, method="gaussian", bootstrap="iid", interval="fisher",
                              n_resamples=10, seed=0)
    res = mutual_information_ci(x, y, method="gaussian", bootstrap="iid", n_resamples=10,
                                seed=0)
    assert res.interval == "normal"
    xc, yc = _pair(0.6, 300, 4)
    with pytest.raises(ValueError, match="`interval`='fisher'.*'kde'"):
        mutual_information_ci(xc, yc, method="kde", bootstrap="iid", interval="fisher",
                              n_resamples=10, seed=0)
