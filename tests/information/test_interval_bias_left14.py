"""Leftovers 14-misc (issue 27): the histogram CMI interval says when its bias undoes it.

References, from outside the code under test: the exact bias of the plug-in variance,
``-sigma^2 / n`` (``numpy.var`` with ``ddof=0`` on iid unit normals), for the pieces'
bias estimate; the normal law's coverage of a shifted interval, ``Phi(1.96 - b) -
Phi(-1.96 - b)`` (``scipy.stats.norm``), for the rule's threshold and the coverage it
states; the measured coverage of the histogram TE interval of a persistent VAR(1)
(benchmarks/RESULTS.md, leftovers 13-est and 14-misc: 0.860 of the binned estimand at
n = 1e3, its finite-sample bias 1.5 sd), for the case that must warn.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

from modalinfo.information import (
    conditional_mutual_information_ci,
    transfer_entropy_variables,
)
from modalinfo.information.convergence import piece_bias
from modalinfo.information.resampling import (
    INTERVAL_BIAS_SDS,
    BlockBootstrapWarning,
    interval_bias_rule,
)


def var1(n, a, b, c, seed, burn=500):
    """The VAR(1) of benchmarks/bench_information_time.py: (source y, target x)."""
    e = np.random.default_rng(seed).standard_normal((n + burn, 2))
    y = lfilter([1.0], [1.0, -b], e[:, 1])
    drive = e[:, 0].copy()
    drive[1:] += c * y[:-1]
    return y[burn:], lfilter([1.0], [1.0, -a], drive)[burn:]


def test_the_pieces_estimate_the_plug_in_variances_bias():
    # E[var_ddof0] = sigma^2 (1 - 1/n): bias -1/n; 2000 draws of n = 400, bound 4 se of
    # the mean (the draws' own sd / sqrt(2000))
    n, got = 400, []
    for s in range(2000):
        a = np.random.default_rng(s).standard_normal(n)
        got.append(piece_bias(lambda i, j, a=a: float(np.var(a[i:j])), n, float(np.var(a))))
    got = np.asarray(got)
    se = got.std(ddof=1) / np.sqrt(got.size)
    assert abs(got.mean() - (-1.0 / n)) < 4.0 * se


def test_the_threshold_is_where_a_shifted_95_interval_covers_the_binomial_edge():
    z = stats.norm.ppf(0.975)
    cover = stats.norm.cdf(z - INTERVAL_BIAS_SDS) - stats.norm.cdf(-z - INTERVAL_BIAS_SDS)
    # the lower edge of the 95 % binomial range of a 0.95 coverage over 200 trials
    assert cover == pytest.approx(stats.binom.ppf(0.025, 200, 0.95) / 200, abs=0.002)
    assert interval_bias_rule(0.49, 1.0, "nats", "f") is None
    why = interval_bias_rule(-1.5, 1.0, "nats", "f")
    stated = stats.norm.cdf(z - 1.5) - stats.norm.cdf(-z - 1.5)
    assert f"covers {stated:.2f} of" in why and "1.5 bootstrap standard deviations" in why
    assert interval_bias_rule(float("nan"), 1.0, "nats", "f") is None


def test_the_persistent_var1_histogram_interval_warns_its_bias():
    # before: silent, and 0.860 of these intervals covered their estimand (200 seeds)
    x, y, z = transfer_entropy_variables(*var1(1000, 0.6, 0.8, 0.5, 500))
    with pytest.warns(BlockBootstrapWarning, match=r"finite-sample bias, about \+0\.0\d+ "
                                                   r"nats .* standard deviations"):
        conditional_mutual_information_ci(x, y, z, method="histogram", n_resamples=99,
                                          seed=0)


def test_the_rule_judges_the_histogram_only_and_changes_no_number():
    x, y, z = transfer_entropy_variables(*var1(1000, 0.6, 0.8, 0.5, 500))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        # the gaussian estimate's bias law is not judged here (its interval covered 0.93)
        conditional_mutual_information_ci(x, y, z, method="gaussian", n_resamples=20, seed=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BlockBootstrapWarning)
        a = conditional_mutual_information_ci(x, y, z, method="histogram", n_resamples=20,
                                              seed=0)
    # the same numbers as the selection's intervals, which do not judge (one per call)
    from modalinfo.information.conditional_uncertainty import _cmi_block_ci

    b = _cmi_block_ci(x, y, z, method="histogram", units="nats", confidence_level=0.95,
                      n_resamples=20, block_length=None, seed=0, check_assumptions=False)
    assert (a.estimate, a.low, a.high) == (b.estimate, b.low, b.high)
