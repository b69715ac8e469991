"""The histogram's and kde's block "basic" / "percentile" MI intervals warn (fix53-b).

Their block replicates are biased upward (more than the estimate itself), which the
quantile intervals carry. Measured (docs/ADVERSARIAL.md, fix53-b; AR(1) pairs, n = 2,000,
default B = 199, 42 - 51 seeds per cell): the percentile interval covered 0.000 of an MI
of 0 at phi 0.9 and 0.97 (every replicate above the truth) and 0.76 - 0.86 of rho = 0.6's
MI; the basic interval 0.45 (histogram) and 0.64 (kde) of an MI of 0 at phi 0.9.

Reference (of the claim the warning makes, at small scale): the exact MI of an
independent pair is 0 (Cover & Thomas 2006, eq. 2.45); the percentile interval of the
replicates, numpy's type-6 quantiles, excludes it.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import mutual_information_ci
from modalinfo.information.resampling import BlockBootstrapWarning


def _ar_pair(phi: float, rho: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, 2))
    e[:, 1] = rho * e[:, 0] + math.sqrt(1.0 - rho * rho) * e[:, 1]
    s = np.empty_like(e)
    s[0] = e[0]
    for t in range(1, n):
        s[t] = phi * s[t - 1] + math.sqrt(1.0 - phi * phi) * e[t]
    return s[:, 0], s[:, 1]


@pytest.mark.parametrize("method", ["histogram", "kde"])
@pytest.mark.parametrize("interval", ["percentile", "basic"])
def test_block_quantile_intervals_of_binned_and_kernel_mi_warn(method, interval):
    x, y = _ar_pair(0.5, 0.0, 600, 5301)  # ~360 effective pairs: no other rule speaks
    with pytest.warns(BlockBootstrapWarning, match="block replicates are biased upward"):
        res = mutual_information_ci(x, y, method=method, interval=interval, n_resamples=40,
                                    seed=1)
    if interval == "percentile":
        # the claim: every replicate above the MI of 0, so the interval excludes it
        q_lo = np.quantile(res.bootstrap_distribution, 0.025, method="weibull")
        assert res.low >= q_lo > 0.0


@pytest.mark.parametrize("method, interval, bootstrap", [
    ("histogram", "normal", "block"), ("gaussian", "percentile", "block"),
    ("histogram", "percentile", "iid")])
def test_other_intervals_do_not_give_it(method, interval, bootstrap):
    x, y = _ar_pair(0.0, 0.6, 600, 5302)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        mutual_information_ci(x, y, method=method, interval=interval, n_resamples=40,
                              seed=2, bootstrap=bootstrap)
    assert not [w for w in got if "block replicates are biased upward" in str(w.message)]
