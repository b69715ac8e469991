"""The block bootstrap's heavy-tail and residual rules, where left13-stats' tests were blind.

Review13 (planted bugs R13-S1, S2, S5). References, outside the code under test:
Student t3 innovations have an infinite fourth moment (Athreya 1987: the bootstrap of a
correlation is then inconsistent), in either series of the pair; Bartlett's (1935)
effective pairs ``n (1 - rx ry) / (1 + rx ry)`` computed here with numpy least squares
on the parts of x and y that z does not explain; the binomial law of the false alarms
of the documented family-wise 1e-4 per series on Gaussian pairs.
"""

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information import conditional_mutual_information_ci, mutual_information_ci
from modalinfo.information.resampling import BlockBootstrapWarning, block_bootstrap_rule


def _ar1(phi, n, rng, innovations=None):
    e = rng.standard_normal(n) if innovations is None else innovations
    return lfilter([1.0], [1.0, -phi], e)


@pytest.mark.parametrize("heavy", ["x", "y"])
def test_a_heavy_tail_in_either_series_warns(heavy):
    # t3 innovations, n = 2000: ~16 values beyond the Bonferroni Gaussian threshold at
    # 1e-4 (5.5 robust sigmas; P(|t3| > 5.5 s) ~ 0.8 %, scipy.stats.t): a miss ~1e-7
    rng = np.random.default_rng(21)
    g = _ar1(0.5, 2000, rng)
    t = _ar1(0.5, 2000, rng, rng.standard_t(3, 2000)) + 0.3 * g
    x, y = (t, g) if heavy == "x" else (g, t)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mutual_information_ci(x, y, "gaussian", n_resamples=19, seed=0)
    msgs = [str(w.message) for w in caught if issubclass(w.category, BlockBootstrapWarning)]
    assert len(msgs) == 1 and "fourth moments" in msgs[0]


def _residual_lag1(v, z):
    design = np.column_stack([np.ones_like(z), z])
    r = v - design @ np.linalg.lstsq(design, v, rcond=None)[0]
    return np.corrcoef(r[1:], r[:-1])[0, 1]


def test_conditional_rule_reads_y_residual_not_y():
    # z and x's own part persistent, y = white + z: y itself is persistent (its lag-1
    # autocorrelation ~0.97) but its part that z does not explain is white, so the
    # effective pairs of the residuals are ~n: no BlockBootstrapWarning
    rng = np.random.default_rng(8)
    n = 500
    z = _ar1(0.99, n, rng)
    x = _ar1(0.99, n, rng) + z
    y = rng.standard_normal(n) + z
    p_resid = _residual_lag1(x, z) * _residual_lag1(y, z)
    assert n * (1 - p_resid) / (1 + p_resid) > 400
    p_levels = _residual_lag1(x, z) * np.corrcoef(y[1:], y[:-1])[0, 1]
    assert n * (1 - p_levels) / (1 + p_levels) < 50  # what y's levels would say
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        conditional_mutual_information_ci(x, y, z, method="gaussian", n_resamples=19,
                                          seed=3)
    msgs = [str(w.message) for w in caught if issubclass(w.category, BlockBootstrapWarning)]
    assert not [m for m in msgs if "effective pairs" in m]


def test_gaussian_pairs_rarely_fail_the_heavy_tail_rule():
    # 600 Gaussian AR(1) 0.5 pairs of n = 500 (~300 effective pairs): the documented
    # family-wise 1e-4 per series, measured up to 1e-3 per pair (2 of 2000 AR(1) 0.9
    # pairs, leftovers 13-stats: the robust sigma's own spread): 0.6 expected,
    # P(>= 4) = 0.3 % (binomial). At the quality pass's 1 % (2-2.5 % of pairs): ~13
    # expected, P(<= 3) = 0.2 %.
    rng = np.random.default_rng(13)
    warned = 0
    for _ in range(600):
        x, y = _ar1(0.5, 500, rng), _ar1(0.5, 500, rng)
        why = block_bootstrap_rule(x, y, "test")
        warned += why is not None and "fourth moments" in why
    assert warned <= 3
