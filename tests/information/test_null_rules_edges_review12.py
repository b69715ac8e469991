"""The shuffle and rotation null rules judge at their stated edges (review12, round 12).

Reference (outside the code): statsmodels' ``acf`` (lag 1, not adjusted: the sample
lag-1 autocorrelation of each series) and the rules as documented (Bartlett 1935):
the shuffle null is liberal where the product ``p`` of the two series' lag-1
autocorrelations exceeds ``max(0.05, 5 / n)``; the circular (rotation) null where the
effective pairs ``n (1 - p) / (1 + p)`` are fewer than 50. AR(1) series of several
coefficients and lengths are drawn (seeded) and each case is checked on its side of
the edge; the grid is asserted to hold cases close to each edge on both sides, so the
test cannot pass far from them.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter
from statsmodels.tsa.stattools import acf

from modalinfo.information.resampling import rotation_null_rule, shuffle_null_rule


def _ar1(phi: float, n: int, rng: np.random.Generator) -> np.ndarray:
    e = rng.standard_normal(n + 500)
    return lfilter([1.0], [1.0, -phi], e)[500:]


def _r1(a: np.ndarray) -> float:
    return float(acf(a, nlags=1, adjusted=False, fft=False)[1])


def test_shuffle_rule_edge_is_the_larger_of_0_05_and_5_over_n():
    near = {"below": 0, "above": 0}
    for n in (50, 200, 5000):
        edge = max(0.05, 5.0 / n)
        for phi in np.linspace(0.1, 0.45, 8):
            for seed in range(6):
                rng = np.random.default_rng(seed)
                x, y = _ar1(phi, n, rng), _ar1(phi, n, rng)
                p = _r1(x) * _r1(y)
                assert (shuffle_null_rule(x, y, "t") is not None) == (p > edge), (n, p)
                if edge * 0.7 < p <= edge:
                    near["below"] += 1
                elif edge < p < edge * 1.4:
                    near["above"] += 1
    assert near["below"] >= 5 and near["above"] >= 5, near


def test_rotation_rule_edge_is_50_effective_pairs():
    near = {"below": 0, "above": 0}
    for n in (100, 135, 200, 400):
        for phi in np.linspace(0.5, 0.95, 10):
            for seed in range(4):
                rng = np.random.default_rng(seed)
                x, y = _ar1(phi, n, rng), _ar1(phi, n, rng)
                p = min(max(_r1(x) * _r1(y), 0.0), 1.0 - 1e-12)
                n_eff = n * (1.0 - p) / (1.0 + p)
                assert (rotation_null_rule(x, y, "t") is not None) == (n_eff < 50.0), (n, p)
                if 38.0 < n_eff < 50.0 and n * (1.0 - p) >= 50.0:
                    near["below"] += 1
                elif 50.0 <= n_eff < 65.0:
                    near["above"] += 1
    assert near["below"] >= 5 and near["above"] >= 5, near


def test_conditional_shuffle_rule_reads_x_residual_not_x():
    # x = z + e (e white), y = z + u (u AR(1) 0.9), z AR(1) 0.9: x's residual on z is e,
    # white, so permuting y's residual against it is a null (Bartlett's factor
    # (1 + 0 b) / (1 - 0 b) = 1) and nothing is said; x itself is persistent (lag-1
    # ~0.8), whose product with u's 0.9 would be far above 0.05
    import warnings

    from modalinfo.information import conditional_mutual_information_test

    for seed in range(3):
        rng = np.random.default_rng(seed)
        z, u = _ar1(0.9, 2000, rng), _ar1(0.9, 2000, rng)
        x, y = z + rng.standard_normal(2000), z + u
        assert _r1(x) * _r1(u) > 0.5  # the series are persistent
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            conditional_mutual_information_test(x, y, z, method="gaussian", n_surrogates=19,
                                                surrogate="shuffle", seed=1)
