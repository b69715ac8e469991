"""Left 16: the constants of the bias rules of ``information.convergence``, pinned at their edges.

Each test places an input just inside and just outside a rule's edge, the edge computed
here from a reference outside the code: the rule as the module notes document it, written
out with numpy (Bartlett's ``n (1 - rx ry) / (1 + rx ry)`` effective pairs on the
Brockwell & Davis lag-1 autocorrelation, corrected by Marriott & Pope's + (1 + 3 r) / n
(fixes 38-a), of a seeded AR(1) path whose coefficient is
solved with ``scipy.optimize.brentq``; the rise ``max(0.05, 5 %)``; Chatterjee's xi from
``scipy.stats.chatterjeexi`` and its Gaussian inverse ``rho^2 = 2 sin(pi (xi + 1/2) / 3) - 1``
(Chatterjee 2021); the Miller-Madow 2 x 2 table MI, its delta-method sd and
``scipy.stats.chi2(1).ppf(0.999)``; the algebra of Quenouille's piece bias on an exact
``c / m + d / m^2`` law). The inputs sit 2.5-5 % from each edge, so a constant x 0.9 or
x 1.1 (and an off-by-one on the integer ones) flips a decision (docs/MUTATION.md,
"Left 16").
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize, stats
from scipy.signal import lfilter

from modalinfo.information.convergence import (
    cluster_rule,
    convergence_rule,
    effective_sample_rule,
    neighbour_rule,
    piece_bias,
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


def pair_with_effective_pairs(n_eff: float, n: int, seed: int) -> np.ndarray:
    """x (used as x and y) with n (1 - c^2) / (1 + c^2) = n_eff, c = r + (1 + 3 r) / n.

    c: the sample lag-1 r corrected for its bias (Marriott & Pope 1954), as the rule
    reads it since fixes 38-a.
    """
    p = (n - n_eff) / (n + n_eff)
    return ar1_with_lag1((math.sqrt(p) - 1.0 / n) / (1.0 + 3.0 / n), n, seed)


# rule 1: n = 1000 (share edge 100): the 20 pairs bind; n = 150: the 10 % share binds
@pytest.mark.parametrize("n, n_eff, warns", [
    (1000, 19.5, True), (1000, 20.5, False),
    (150, 14.5, True), (150, 15.5, False),
])
def test_effective_sample_rule_edges_are_20_pairs_and_10_percent(n, n_eff, warns):
    x = pair_with_effective_pairs(n_eff, n, seed=16)
    assert (effective_sample_rule(x, x.copy()) is not None) == warns


# rule 2: the quarters' mean is what the estimate returns on a quarter
@pytest.mark.parametrize("value, sub, warns", [
    (0.0475, 0.0, False), (0.0525, 0.0, True),  # max(0.05, 5 %) = 0.05 nats
    (2.0, 2.0 - 0.095, False), (2.0, 2.0 - 0.105, True),  # 5 % of 2 nats = 0.1
])
def test_convergence_rule_allows_a_rise_of_max_5_centinats_and_5_percent(value, sub, warns):
    x = np.zeros(4000)
    assert (convergence_rule(lambda a, b: sub, x, x, value) is not None) == warns


@pytest.mark.parametrize("n, warns", [(3999, False), (4000, True), (100_000, True),
                                      (100_001, False)])
def test_convergence_rule_judges_4000_to_100000_samples(n, warns):
    x = np.zeros(n)
    assert (convergence_rule(lambda a, b: 0.0, x, x, 1.0) is not None) == warns


def gaussian_mi_of_xi(xi: float) -> float:
    rho2 = 2.0 * math.sin(math.pi * (xi + 0.5) / 3.0) - 1.0
    return -0.5 * math.log(1.0 - rho2)


def test_neighbour_rule_takes_xi_three_sds_low():
    n = 1000
    rng = np.random.default_rng(1616)
    x = rng.standard_normal(n)
    y = x + 0.6 * rng.standard_normal(n)
    xi = max(stats.chatterjeexi(x, y).statistic, stats.chatterjeexi(y, x).statistic)

    def edge(k: float) -> float:
        bound = gaussian_mi_of_xi(xi - k * math.sqrt(2.0 / (5.0 * n)))
        return bound - max(0.05, 0.10 * bound)

    e27, e30, e33 = edge(2.7), edge(3.0), edge(3.3)
    assert e27 - e30 > 4e-3 and e30 - e33 > 4e-3  # far from rounding
    assert neighbour_rule(x, y, 0.5 * (e30 + e33)) is not None  # below the 3-sd edge
    assert neighbour_rule(x, y, 0.5 * (e27 + e30)) is None


def clustered(n: int, cluster: int, seed: int) -> np.ndarray:
    """n values: `cluster` of them far below a uniform bulk (the widest gap)."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(0.0, 1.0, n)
    x[:cluster] = rng.uniform(-11.0, -10.0, cluster)
    return x


@pytest.mark.parametrize("cluster, warns", [(200, True), (199, False)])
def test_cluster_rule_splits_at_a_gap_leaving_2_percent_aside(cluster, warns):
    # n = 1e4: ceil(0.02 n) = 200 samples must lie on each side of the split; y shares
    # x's cluster rows, so the split table is diagonal (MI H(0.02) = 0.098 nats, bound
    # ~0.081 after the sampling terms) while a split inside two independent uniform
    # bulks holds ~0 nats
    n = 10_000
    x, y = clustered(n, cluster, 1), clustered(n, cluster, 2)
    assert (cluster_rule(x, y, 0.0) is not None) == warns


def table_edge(counts: np.ndarray, chi2: float) -> float:
    """The documented rule-4 edge: MM MI - 3 sd - chi2 / 2n, less max(0.05, 10 %)."""
    n = counts.sum()
    p = counts / n
    outer = np.outer(p.sum(axis=1), p.sum(axis=0))
    occ = p > 0
    ratio = np.log(p[occ] / outer[occ])
    plugin = float(p[occ] @ ratio)
    k_xy, k_x, k_y = occ.sum(), (p.sum(axis=1) > 0).sum(), (p.sum(axis=0) > 0).sum()
    mm = plugin - (k_xy - k_x - k_y + 1) / (2.0 * n)
    sd = math.sqrt(max(float(p[occ] @ ratio**2) - plugin**2, 0.0) / n)
    bound = mm - 3.0 * sd - chi2 / (2.0 * n)
    return bound - max(0.05, 0.10 * bound)


def test_cluster_rule_subtracts_the_chi2_999_point_over_2n():
    n = 10_000
    x, y = clustered(n, 300, 3), clustered(n, 300, 4)
    y[290:300] = np.random.default_rng(5).uniform(0.0, 1.0, 10)  # 10 rows off-diagonal
    counts = np.array([[n - 300, 0], [10, 290]])  # (x above, y above) by construction
    chi2 = stats.chi2(1).ppf(0.999)
    e09, e10, e11 = (table_edge(counts, c * chi2) for c in (0.9, 1.0, 1.1))
    assert e09 - e10 > 4e-5 and e10 - e11 > 4e-5
    assert cluster_rule(x, y, 0.5 * (e10 + e11)) is not None
    assert cluster_rule(x, y, 0.5 * (e09 + e10)) is None


def test_piece_bias_uses_four_contiguous_pieces_by_default():
    # an exact law c / m + d / m^2 on m rows: p pieces read c / n + (p + 1) d / n^2
    # (Quenouille's first-order correction leaves the second order times p + 1)
    n, c, d = 1200, 0.3, 50.0
    calls = []

    def estimate(i: int, j: int) -> float:
        calls.append((i, j))
        m = j - i
        return c / m + d / m**2

    got = piece_bias(estimate, n, c / n + d / n**2)
    assert calls == [(0, 300), (300, 600), (600, 900), (900, 1200)]
    assert got == pytest.approx(c / n + 5.0 * d / n**2, rel=1e-12)
    # the same law at rate a: c m^-a is read exactly whatever a (the histogram's 1.3)
    got = piece_bias(lambda i, j: c * (j - i) ** -1.3, n, c * n ** -1.3, rate=1.3)
    assert got == pytest.approx(c * n ** -1.3, rel=1e-12)

