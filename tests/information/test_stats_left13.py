"""Leftovers 13-stats: the conditional block-bootstrap interval says when it undercovers.

Reference: Bartlett's (1935) effective pairs ``n (1 - rx ry) / (1 + rx ry)`` of two AR(1)
series (rx, ry their lag-1 autocorrelations, computed here with numpy on the parts of x
and y that z does not explain, least squares), against the 50 at which
``mutual_information_ci`` already warns; and the analytic partial correlation of the
triple (x = e1 + z, y = 0.6 e1 + 0.8 e2 + z: 0.6 given z). Measured before the fix
(``benchmarks/bench_audit12_size.py cmi_ci``, n = 500, 200 draws): coverage of the
nominal 95 % interval 0.82 (AR(1) 0.95), 0.685 (0.99), 0.825 (x4 variance step), never
warned; 0.90 on white series. Heavy tails: Student t3 innovations (infinite fourth
moment, Athreya 1987) pass the Bonferroni Gaussian threshold ``Phi^-1(1 - a / 2m)``
(statistics.NormalDist) in a few of m = 500 values (their tail from scipy.stats.t);
``mutual_information_ci`` covered 0.77 there, silent.
"""

import math
import warnings

import numpy as np
from scipy.signal import lfilter

from modalinfo.information import conditional_mutual_information_ci, select_inputs
from modalinfo.information.resampling import BlockBootstrapWarning


def _ar1(phi, n, rng):
    x0 = rng.standard_normal() / math.sqrt(1 - phi * phi)
    return lfilter([1.0], [1.0, -phi], rng.standard_normal(n), zi=[phi * x0])[0]


def _triple(phi, n=500, seed=0):
    rng = np.random.default_rng(seed)
    e1, e2, z = (_ar1(phi, n, rng) for _ in range(3))
    return e1 + z, 0.6 * e1 + 0.8 * e2 + z, z


def _bartlett_residual_pairs(x, y, z):
    design = np.column_stack([np.ones_like(z), z])
    rx, ry = (v - design @ np.linalg.lstsq(design, v, rcond=None)[0] for v in (x, y))
    r1 = [np.corrcoef(r[1:], r[:-1])[0, 1] for r in (rx, ry)]
    p = min(max(r1[0] * r1[1], 0.0), 1.0)
    return x.size * (1 - p) / (1 + p)


def test_persistent_triple_warns_once_and_the_interval_is_unchanged():
    x, y, z = _triple(0.99)
    assert _bartlett_residual_pairs(x, y, z) < 50  # the failed assumption, by numpy
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = conditional_mutual_information_ci(x, y, z, method="gaussian",
                                                n_resamples=39, seed=3)
    msgs = [str(w.message) for w in caught if issubclass(w.category, BlockBootstrapWarning)]
    assert len(msgs) == 1 and len(caught) == 1
    assert "conditional_mutual_information_ci" in msgs[0] and "effective pairs" in msgs[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BlockBootstrapWarning)
        again = conditional_mutual_information_ci(x, y, z, method="gaussian",
                                                  n_resamples=39, seed=3)
    assert (res.low, res.high) == (again.low, again.high)  # a warning, not a new interval


def test_white_triple_is_not_warned():
    x, y, z = _triple(0.0, seed=1)
    assert _bartlett_residual_pairs(x, y, z) > 400
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        conditional_mutual_information_ci(x, y, z, method="gaussian", n_resamples=39,
                                          seed=3)


def test_input_selection_draws_its_intervals_without_a_warning_each():
    # persistent modes: the public interval would warn for every picked input
    rng = np.random.default_rng(5)
    a = _ar1(0.99, 600, rng)
    b = np.r_[0.0, a[:-1]] + 0.3 * _ar1(0.99, 600, rng)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = select_inputs(np.column_stack([b, a]), 0, horizon=1, max_lag=3,
                            method="histogram", n_surrogates=19, n_resamples=19, seed=0)
    assert not [w for w in caught if issubclass(w.category, BlockBootstrapWarning)]
    assert res.inputs and all(np.isfinite(s.low) for s in res.inputs)


def _ar1_t3(n, rng):
    e = rng.standard_t(3, n)
    return lfilter([1.0], [1.0, -0.9], e)


def test_heavy_tailed_pair_warns_once():
    # Student t3 innovations: infinite fourth moment. P(|t3| > 5.4 robust sigmas) ~ 0.8 %
    # per value (scipy.stats.t), so ~4 of 500 innovations pass the Bonferroni Gaussian
    # threshold at 1e-4 (Phi^-1(1 - 1e-4 / 992) = 5.3): a miss has probability ~2 %
    from modalinfo.information import mutual_information_ci

    rng = np.random.default_rng(11)
    x, y = _ar1_t3(2000, rng), _ar1_t3(2000, rng)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mutual_information_ci(x, 0.6 * x + 0.8 * y, "gaussian", n_resamples=19, seed=0)
    msgs = [str(w.message) for w in caught if issubclass(w.category, BlockBootstrapWarning)]
    assert len(msgs) == 1 and "fourth moments" in msgs[0]


def test_gaussian_pair_of_many_effective_pairs_is_not_warned():
    # AR(1) 0.9, n = 2000: ~210 effective pairs, Gaussian: the rule's false alarm <= 2e-4
    rng = np.random.default_rng(11)
    x, y = _ar1(0.9, 2000, rng), _ar1(0.9, 2000, rng)
    from modalinfo.information import mutual_information_ci

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mutual_information_ci(x, 0.6 * x + 0.8 * y, "gaussian", n_resamples=19, seed=0)
