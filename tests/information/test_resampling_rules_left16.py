"""Left 16: the constants of the null and interval rules of ``information.resampling``, pinned.

Each test places an input just inside and just outside a rule's edge, the edge computed
here from a reference outside the code: Bartlett's ``n (1 - p) / (1 + p)`` effective pairs
and the shuffle rule's ``p > max(0.05, 5 / n)`` on the Brockwell & Davis lag-1
autocorrelation of a seeded AR(1) path whose coefficient is solved with
``scipy.optimize.brentq``; a constructed series whose only matched window discards a
known number of rows (the documented cap, 2000); the coverage
``Phi(1.96 - s) - Phi(-1.96 - s)`` of a shifted normal interval (``scipy.stats.norm``)
set to the lower edge of the binomial 95 % range of 200 trials (``scipy.stats.binom``);
the heavy-tail threshold's documented union bound, integrated over the MAD's normal law
with ``scipy.integrate.quad`` and solved with ``brentq``, its relative sd
``1 / (4 q phi(q))`` from ``scipy.stats.norm``; the histogram interval's bias read by
Quenouille's pieces at the documented rate 1.3 (``(mean of 4 quarters - whole) /
(4^1.3 - 1)``, the quarters estimated by the public ``histogram_cmi``). The inputs sit
2.5-5 % from each edge, so a constant x 0.9 or x 1.1 flips a decision
(docs/MUTATION.md, "Left 16").
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from scipy import integrate, optimize, stats
from scipy.signal import lfilter

from modalinfo.information import (
    conditional_mutual_information_ci,
    mutual_information_permutation_test,
    transfer_entropy_variables,
)
from modalinfo.information.histogram import histogram_cmi
from modalinfo.information.resampling import (
    BlockBootstrapWarning,
    heavy_tail_threshold,
    interval_bias_rule,
    matched_window,
    shuffle_null_rule,
)


def lag1(a: np.ndarray) -> float:
    """Brockwell & Davis eq. 1.4.4: sum (a_t - m)(a_t+1 - m) / sum (a_t - m)^2."""
    d = a - a.mean()
    return float(d[:-1] @ d[1:] / (d @ d))


def ar1_with_lag1(r: float, n: int, seed: int) -> np.ndarray:
    """A seeded AR(1) path whose sample lag-1 autocorrelation is r (to ~1e-12)."""
    e = np.random.default_rng(seed).standard_normal(n)

    def path(phi: float) -> np.ndarray:
        return lfilter([1.0], [1.0, -phi], e)

    phi = optimize.brentq(lambda f: lag1(path(f)) - r, -0.5, 0.999, xtol=1e-14)
    out = path(phi)
    assert abs(lag1(out) - r) < 1e-10
    return out


@pytest.mark.parametrize("n, p, warns", [
    (1000, 0.0475, False), (1000, 0.0525, True),  # 0.05 binds (5 / n = 0.005)
    (50, 0.095, False), (50, 0.105, True),  # 5 / n = 0.1 binds
])
def test_shuffle_rule_edge_is_a_lag1_product_of_max_5_percent_and_5_over_n(n, p, warns):
    x = ar1_with_lag1(math.sqrt(p), n, seed=16)
    assert (shuffle_null_rule(x, x.copy(), "t") is not None) == warns


@pytest.mark.parametrize("n_eff, warns", [(7.6, True), (8.4, False)])
def test_circular_mi_test_warns_below_8_effective_pairs(n_eff, warns):
    # n = 500: rx ry = (n - n_eff) / (n + n_eff); the warning names the effective pairs
    # (the scale and level rules after it word theirs otherwise)
    n = 500
    p = (n - n_eff) / (n + n_eff)
    x = ar1_with_lag1(0.99, n, seed=1)
    y = ar1_with_lag1(p / 0.99, n, seed=2)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        mutual_information_permutation_test(x, y, method="gaussian",
                                            n_permutations=19, permutation="circular",
                                            match_ends=False, seed=1)
    said = any("effective pairs" in str(w.message) for w in got)
    assert said == warns


@pytest.mark.parametrize("discard, found", [(2000, True), (2001, False)])
def test_matched_window_discards_at_most_2000_rows(discard, found):
    # a ramp (every join a jump of ~n typical steps) with one row lifted to the last
    # row's value and slope: the only window whose ends match starts at `discard`
    n = 12_000  # 20 % of n = 2400 rows: the cap of 2000 binds
    v = np.arange(n, dtype=float)
    v[discard] = v[n - 1]
    v[discard + 1] = v[n - 1] + 1.0
    start, stop = matched_window(v)
    assert ((start, stop) == (discard, n)) == found


def coverage(s: float) -> float:
    return float(stats.norm.cdf(1.959964 - s) - stats.norm.cdf(-1.959964 - s))


def test_interval_bias_rule_edge_is_where_coverage_leaves_the_200_trial_range():
    low = stats.binom.ppf(0.025, 200, 0.95) / 200.0  # 0.92
    edge = optimize.brentq(lambda s: coverage(s) - low, 0.0, 2.0)
    assert 0.47 < edge < 0.53, edge
    sd = 0.02
    assert interval_bias_rule(0.95 * edge * sd, sd, "nats", "t") is None
    assert interval_bias_rule(-1.05 * edge * sd, sd, "nats", "t") is not None


def union_bound_threshold(t: int, n_series: int, alpha: float) -> float:
    """k with n_series E_s[min(1, T erfc(z / sqrt 2))] = alpha, s ~ N(1, (v/sqrt T)^2).

    ``z = (k s (1 + v0 / T) + sqrt(pi / 2) / T) / c``: a tested value inside its sample
    pulls the MAD by a relative ``v0 / T`` and the median by ``sqrt(pi / 2) / T``
    (Bahadur's representation, leftovers 18-stats; ``z = k s / c`` before).
    """
    q = stats.norm.ppf(0.75)
    v0 = 1.0 / (4.0 * q * stats.norm.pdf(q))
    v = v0 / math.sqrt(t)
    c = math.sqrt(1.0 + math.pi / (2.0 * t))
    scale, offset = 1.0 + v0 / t, math.sqrt(math.pi / 2.0) / t

    def density(s: float) -> float:
        return math.exp(-0.5 * ((s - 1.0) / v) ** 2) / (v * math.sqrt(2.0 * math.pi))

    mass = 1.0 - 0.5 * math.erfc(1.0 / (v * math.sqrt(2.0)))  # P(s > 0)

    def rate(k: float) -> float:
        def f(s: float) -> float:
            z = (k * scale * s + offset) / c
            return density(s) * min(1.0, t * math.erfc(z / math.sqrt(2.0)))
        val = integrate.quad(f, 0.0, 1.0 + 12 * v, points=[1.0], limit=200)[0]
        return n_series * val / mass

    return optimize.brentq(lambda k: rate(k) - alpha, 2.0, 20.0, xtol=1e-10)


@pytest.mark.parametrize("t, n_series", [(496, 2), (1996, 2), (496, 4)])
def test_heavy_tail_threshold_sets_the_pair_rate_to_1e_minus_4(t, n_series):
    ref = union_bound_threshold(t, n_series, 1e-4)
    # alpha x 1.1 moves k by ~0.017 (0.3 %), the value's spread about the median
    # (pi / 2T) by ~1.4e-4: the two integrations agree to ~4e-12 (Gauss-Hermite, quad)
    assert heavy_tail_threshold(t, n_series) == pytest.approx(ref, rel=1e-9)
    assert abs(union_bound_threshold(t, n_series, 1.1e-4) - ref) > 1e-2


def var1(n, a, b, c, seed, burn=500):
    """The VAR(1) of benchmarks/bench_information_time.py: (source y, target x)."""
    e = np.random.default_rng(seed).standard_normal((n + burn, 2))
    y = lfilter([1.0], [1.0, -b], e[:, 1])
    drive = e[:, 0].copy()
    drive[1:] += c * y[:-1]
    return y[burn:], lfilter([1.0], [1.0, -a], drive)[burn:]


def test_histogram_interval_reads_the_bias_at_rate_1_3():
    # the stated bias against (mean of the 4 quarters - whole) / (4^1.3 - 1), the
    # quarters at the whole record's 6 bins per axis; rate 1.17 or 1.43 reads it 25 %
    # higher or 20 % lower, the message prints 3 digits
    n, bins = 1000, 6
    x, y, z = transfer_entropy_variables(*var1(n, 0.6, 0.8, 0.5, 501))
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        res = conditional_mutual_information_ci(x, y, z, method="histogram", bins=bins,
                                                n_resamples=49, seed=3)
    said = [str(w.message) for w in got if issubclass(w.category, BlockBootstrapWarning)
            and "finite-sample bias" in str(w.message)]
    assert len(said) == 1
    stated = float(re.search(r"about ([-+0-9.e]+) nats", said[0]).group(1))
    edges = np.linspace(0, x.shape[0], 5).astype(int)  # 999 rows after the lag
    quarters = [histogram_cmi(x[i:j], y[i:j], z[i:j], bins=bins)
                for i, j in zip(edges[:-1], edges[1:], strict=True)]
    expected = (np.mean(quarters) - res.estimate) / (4.0**1.3 - 1.0)
    assert stated == pytest.approx(expected, rel=6e-3)
