"""``mutual_information_ci(bootstrap="iid")`` warns on autocorrelated pairs (stop 58).

review34 found the iid bootstrap's interval silent on a persistent pair (AR(1) 0.99 pairs,
16.8 effective pairs of 2,000: [0.54, 0.63] nats, the block bootstrap [0.10, 1.07] with its
warning). References: the iid bootstrap resamples rows as exchangeable, so its replicates'
variance is the iid one, short of the autocorrelated estimate's by Bartlett's (1935) factor
(1 + p) / (1 - p), p the product of the lag-1 autocorrelations (numpy's ``corrcoef`` of
each series with itself one frame later, here); the rule is the shuffle null's (largest
p above 0.05). The coverage check counts, over seeds, how often the warned interval holds
the exact Gaussian MI -0.5 ln(1 - rho^2), against the nominal 0.95.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import mutual_information_ci
from modalinfo.information.resampling import BlockBootstrapWarning

RHO = 0.6
EXACT = -0.5 * math.log(1.0 - RHO**2)


def _pair(phi: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    e = rng.multivariate_normal([0.0, 0.0], [[1.0, RHO], [RHO, 1.0]], size=n)
    z = np.zeros((n, 2))
    z[0] = e[0]
    for t in range(1, n):
        z[t] = phi * z[t - 1] + math.sqrt(1.0 - phi**2) * e[t]
    return z[:, 0], z[:, 1]


def _lag1(a: np.ndarray) -> float:
    return float(np.corrcoef(a[:-1], a[1:])[0, 1])


def test_a_persistent_pair_is_warned_with_its_effective_pairs():
    x, y = _pair(0.99, 2000, 1)
    p = _lag1(x) * _lag1(y)
    n_eff = 2000 * (1 - p) / (1 + p)
    with pytest.warns(BlockBootstrapWarning, match="bootstrap='iid'") as rec:
        mutual_information_ci(x, y, method="gaussian", n_resamples=49, seed=0,
                              bootstrap="iid")
    msg = str(rec[0].message)
    got = float(msg.split(" effective pairs")[0].rsplit(" ", 1)[1])
    # the package's lag-1 is the biased (Brockwell & Davis) one, numpy's the Pearson one
    assert got == pytest.approx(n_eff, rel=0.05)


@pytest.mark.parametrize("seed", range(5))
def test_independent_rows_are_not_warned(seed):
    # iid pairs: p has s.d. ~1 / n = 0.0005, far under the 0.05 threshold
    x, y = _pair(0.0, 2000, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mutual_information_ci(x, y, method="gaussian", n_resamples=49, seed=0,
                              bootstrap="iid")


def test_the_warned_interval_undercovers():
    # AR(1) 0.9 pairs, n = 500: p ~ 0.81, the variance understated ~9.5x; the iid
    # "normal" interval covers far under 0.95 (binomial s.e. over 40 seeds: 0.034)
    hits = 0
    for seed in range(40):
        x, y = _pair(0.9, 500, 100 + seed)
        with pytest.warns(BlockBootstrapWarning, match="bootstrap='iid'"):
            r = mutual_information_ci(x, y, method="gaussian", n_resamples=99, seed=seed,
                                      bootstrap="iid", interval="normal")
        hits += r.low <= EXACT <= r.high
    assert hits / 40 < 0.95 - 3 * 0.034
