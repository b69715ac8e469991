"""Leftovers 12-ci: the block-bootstrap MI interval and the circular tests say when they fail.

Reference: the analytic Gaussian mutual information ``-0.5 ln(1 - rho^2)`` of a pair
``(x, rho x + sqrt(1 - rho^2) y)`` with x and y independent series of one kind (equal
variances: correlation rho at every lag 0 pair), which a 95 % interval should hold in
95 % of draws, and a binomial bound on counts of draws. Bartlett (1935) gives the
effective pairs ``n (1 - rx ry) / (1 + rx ry)`` of two AR(1) series. Measured before the
fix (``benchmarks/bench_audit12_size.py``, n = 500, 100-200 draws): interval coverage
0.70 (AR(1) 0.99), 0.80 (AR(1) 0.95), 0.80 (x4 variance step halfway); circular MI
test 9.5 % and conditional test 13 % rejections at 5 % on the variance step; all
silent.
"""

import math
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

from modalinfo._stats import PAIR_MIN_STATIONARITY_FRAMES, scale_stationarity
from modalinfo.information import (
    conditional_mutual_information_test,
    mutual_information_ci,
    mutual_information_permutation_test,
)
from modalinfo.information.resampling import BlockBootstrapWarning, RotationNullWarning

RHO = 0.6
EXACT = -0.5 * math.log(1 - RHO**2)  # nats, analytic Gaussian MI


def _ar1(phi, n, rng, step=False):
    e = rng.standard_normal(n)
    if step:  # the seeing changes halfway: innovations' variance x4
        e[n // 2:] *= 2.0
    x0 = rng.standard_normal() / math.sqrt(1 - phi * phi)
    return lfilter([1.0], [1.0, -phi], e, zi=[phi * x0])[0]


def _pair(phi, n, rng, step=False):
    x, y = _ar1(phi, n, rng, step), _ar1(phi, n, rng, step)
    return x, RHO * x + math.sqrt(1 - RHO**2) * y


def test_ci_of_few_effective_pairs_warns():
    # AR(1) 0.99, n = 500: ~5-15 effective pairs; coverage was 0.70 with no word
    x, y = _pair(0.99, 500, np.random.default_rng(7))
    with pytest.warns(BlockBootstrapWarning, match=r"effective pairs.*undercovers"):
        res = mutual_information_ci(x, y, "gaussian", n_resamples=50, seed=1)
    assert math.isfinite(res.low) and res.low < res.high  # the interval is still given
    # control: an iid pair of the same law is not warned, and its interval holds EXACT
    x, y = _pair(1e-9, 500, np.random.default_rng(8))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = mutual_information_ci(x, y, "gaussian", n_resamples=50, seed=1)
    assert res.low <= EXACT <= res.high


def test_ci_on_a_variance_step_warns_once():
    # AR(1) 0.9 (~55 effective pairs: not few), innovations x4 in variance halfway
    x, y = _pair(0.9, 500, np.random.default_rng(3), step=True)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        mutual_information_ci(x, y, "gaussian", n_resamples=50, seed=1)
    msgs = [str(w.message) for w in got]
    assert len(msgs) == 1 and issubclass(got[0].category, BlockBootstrapWarning), msgs
    assert "stationary" in msgs[0] and "change scale" in msgs[0]


def test_circular_tests_on_a_variance_step_warn():
    rng = np.random.default_rng(5)
    x, y = _ar1(0.9, 500, rng, True), _ar1(0.9, 500, rng, True)
    with pytest.warns(RotationNullWarning, match=r"stationary series.*change scale"):
        mutual_information_permutation_test(x, y, "gaussian", n_permutations=19,
                                            permutation="circular", seed=1)
    # the conditional test judges x's and y's residuals on z (normal scores): the rule
    # called 56 of 100 such triples at n = 500 (measured), 40 of 40 at n = 1000
    x, y, z = (_ar1(0.9, 1000, rng, True) for _ in range(3))
    with pytest.warns(RotationNullWarning, match="change scale"):
        conditional_mutual_information_test(x + z, y + z, z, method="gaussian",
                                            n_surrogates=19, seed=1)
    # the same pairs without the step: silent
    rng = np.random.default_rng(5)
    x, y = _ar1(0.9, 500, rng), _ar1(0.9, 500, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mutual_information_permutation_test(x, y, "gaussian", n_permutations=19,
                                            permutation="circular", seed=1)


def test_stationarity_rule_false_and_true_calls():
    # One stationary series called non-stationary at most ~1-3 % (99 % range of 8 log
    # MADs, Harter 1960; measured 0.25-3 % at n = 500): over 100 AR(1) 0.9 series the
    # count stays within Binomial(100, 0.03)'s 1 - 1e-4 quantile; a x4 variance step is
    # called in 94 % (measured): at least Binomial(40, 0.9)'s 1e-4 quantile of 40.
    false = sum(np.greater(*scale_stationarity(_ar1(0.9, 500, np.random.default_rng(k)),
                                               PAIR_MIN_STATIONARITY_FRAMES))
                for k in range(100))
    assert false <= stats.binom.isf(1e-4, 100, 0.03)
    true = sum(np.greater(*scale_stationarity(
        _ar1(0.9, 500, np.random.default_rng(k), True), PAIR_MIN_STATIONARITY_FRAMES))
        for k in range(40))
    assert true >= stats.binom.ppf(1e-4, 40, 0.9)


@pytest.mark.slow
def test_unwarned_intervals_cover():
    # 100 draws each of AR(1) 0.9 / 0.95 / 0.99 and the variance step: every draw whose
    # interval misses the analytic MI beyond the iid rate is warned. Pooled over the
    # unwarned draws, misses ~ Binomial(m, 0.09) at most (iid coverage 0.91 measured);
    # accept its 1 - 1e-4 quantile.
    missed = kept = 0
    for phi, step in ((0.9, False), (0.95, False), (0.99, False), (0.9, True)):
        for k in range(100):
            x, y = _pair(phi, 500, np.random.default_rng([int(phi * 100), step, k]), step)
            with warnings.catch_warnings(record=True) as got:
                warnings.simplefilter("always")
                r = mutual_information_ci(x, y, "gaussian", n_resamples=199, seed=k)
            if not got:
                kept += 1
                missed += not (r.low <= EXACT <= r.high)
    assert kept >= 50
    assert missed <= stats.binom.isf(1e-4, kept, 0.09)
