"""The regime rules of ``mutual_information`` and the Gaussian-copula CMI (Leftovers 11-resolve).

References, all from outside the code: statsmodels' lag-1 autocorrelation (``acf``) and
Bartlett's effective size of a pair of AR(1) series, n (1 - rx ry) / (1 + rx ry);
scipy's Chatterjee xi (``scipy.stats.chatterjeexi``) and its Gaussian law
xi = (3 / pi) arcsin((1 + rho^2) / 2) - 1/2 (Chatterjee, J. Am. Stat. Assoc. 116, 2021);
the exact MI of a Gaussian pair, -0.5 ln(1 - rho^2), and of an AR(1) lag pair, of a
curve y = f(x) + 0.1 N with x uniform by quadrature (h(Y) - h(noise)), of a Poisson pair
by sums (scipy.stats.poisson), and the transfer entropy of a VAR(1) from its stationary
covariance (the Lyapunov equation, scipy.linalg.solve_discrete_lyapunov). Each warned
case is off its truth by more than max(0.05 nats, 10 %); each silent case is a law whose
default estimate is within it. Values are unchanged by the rules (compared bit for bit
with the estimator object, which does not run them).
"""

import math
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.linalg import solve_discrete_lyapunov
from scipy.signal import lfilter
from statsmodels.tsa.stattools import acf

from modalinfo.information import (
    BiasRuleWarning,
    MutualInformation,
    conditional_mutual_information,
    mutual_information,
    transfer_entropy,
)
from modalinfo.information.convergence import chatterjee_xi, effective_pairs, xi_gaussian_mi

N = 5000


def _ar1(rho, n, seed, burn=3000):
    rng = np.random.default_rng(seed)
    return lfilter([1.0], [1.0, -rho], rng.standard_normal(n + burn))[burn:]


def _tol(truth):
    return max(0.05, 0.1 * abs(truth))


def _warnings(fn):
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        value = fn()
    return value, [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)]


def test_effective_pairs_is_bartlett_with_statsmodels_autocorrelations():
    x, y = _ar1(0.9, 4000, 1), _ar1(0.7, 4000, 2)
    rx, ry = acf(x, nlags=1)[1], acf(y, nlags=1)[1]
    # each lag-1 corrected for its bias, + (1 + 3 r) / n (Marriott & Pope 1954; fixes 38-a)
    rx, ry = rx + (1 + 3 * rx) / 4000, ry + (1 + 3 * ry) / 4000
    assert effective_pairs(x, y) == pytest.approx(4000 * (1 - rx * ry) / (1 + rx * ry),
                                                  rel=1e-9)


def test_chatterjee_xi_matches_scipy_and_its_gaussian_law():
    rng = np.random.default_rng(3)
    x = rng.standard_normal(20_000)
    y = 0.75 * x + math.sqrt(1 - 0.75**2) * rng.standard_normal(x.size)
    assert chatterjee_xi(x, y) == pytest.approx(stats.chatterjeexi(x, y).statistic, rel=1e-12)
    # Gaussian law of xi, then its MI: within 4 sd (sqrt(2 / (5 n)) = 0.0045) of xi
    law = 3 / math.pi * math.asin((1 + 0.75**2) / 2) - 0.5
    assert chatterjee_xi(x, y) == pytest.approx(law, abs=4 * math.sqrt(2 / (5 * x.size)))
    assert xi_gaussian_mi(law) == pytest.approx(-0.5 * math.log(1 - 0.75**2), rel=1e-9)


def test_lagged_mi_of_a_very_persistent_series_is_warned():
    # rho = 0.999: exact lag-1 MI 3.108 nats, ~5 effective pairs in 5000 samples
    x = _ar1(0.999, N, 4, burn=20_000)
    truth = -0.5 * math.log(1 - 0.999**2)
    value, said = _warnings(lambda: mutual_information(x[1:], x[:-1], method="histogram"))
    assert abs(value - truth) > _tol(truth)
    assert len(said) == 1 and "effective samples" in said[0]


def test_lagged_mi_of_a_random_walk_is_warned():
    walk = np.cumsum(np.random.default_rng(5).standard_normal(N))  # no stationary MI
    _, said = _warnings(lambda: mutual_information(walk[1:], walk[:-1]))
    assert len(said) == 1 and "not stationary" in said[0]


def test_lagged_mi_of_a_moderately_persistent_series_is_silent():
    x = _ar1(0.9, N, 6)  # ~263 effective pairs; exact 0.830 nats
    value, said = _warnings(lambda: mutual_information(x[1:], x[:-1]))
    assert said == []
    assert abs(value - (-0.5 * math.log(1 - 0.81))) < _tol(0.830)


def test_sorted_samples_are_not_read_as_a_series():
    rng = np.random.default_rng(7)
    x = np.sort(rng.standard_normal(N))  # lag-1 autocorrelation ~1, but a sort
    y = 0.6 * x + 0.8 * rng.standard_normal(N)
    _, said = _warnings(lambda: mutual_information(x, y))
    assert said == []


def _zigzag(x, pieces):
    u = x * pieces
    k = np.floor(np.minimum(u, pieces - 1e-12))
    return np.where(k % 2 == 0, u - k, 1 - (u - k))


def _curve_mi(f, sigma=0.1, m=10_000):
    # h(Y) - h(noise), Y = f(U) + sigma N, U uniform on [0, 1]: density on a grid
    fx = f((np.arange(m) + 0.5) / m)
    ys = np.linspace(fx.min() - 7 * sigma, fx.max() + 7 * sigma, 3000)
    p = np.zeros_like(ys)
    for chunk in np.array_split(fx, 40):  # the normal density, unnormalised
        p += np.exp(-0.5 * ((ys[:, None] - chunk[None, :]) / sigma) ** 2).sum(axis=1)
    dy = ys[1] - ys[0]
    p /= p.sum() * dy
    return -np.sum(p * np.log(np.maximum(p, 1e-300))) * dy - stats.norm(scale=sigma).entropy()


@pytest.fixture(scope="module")
def zigzag10():
    rng = np.random.default_rng(8)
    x = rng.uniform(0, 1, N)
    return x, _zigzag(x, 10) + 0.1 * rng.standard_normal(N), _curve_mi(lambda u: _zigzag(u, 10))


@pytest.mark.parametrize("method", ["kde", "histogram"])
def test_a_curve_narrower_than_the_estimator_resolves_is_warned(zigzag10, method):
    x, y, truth = zigzag10  # 1.064 nats; kde ~0.60, histogram ~0.37
    value, said = _warnings(lambda: mutual_information(x, y, method=method))
    assert truth - value > _tol(truth)
    assert len(said) == 1 and "lower bound" in said[0]
    with warnings.catch_warnings():  # the class road warns too (round 39 PART a)
        warnings.simplefilter("ignore", BiasRuleWarning)
        same = MutualInformation(method).estimate(x, y)
    assert value == same  # the value is not changed


def test_fifty_periods_every_estimator_misses_are_warned_by_the_neighbours():
    rng = np.random.default_rng(9)
    x = rng.uniform(0, 1, N)
    y = np.sin(2 * math.pi * 50 * x) + 0.1 * rng.standard_normal(N)
    truth = _curve_mi(lambda u: np.sin(2 * math.pi * 50 * u))  # 1.70 nats
    for method in ("ksg", "kde", "histogram"):
        value, said = _warnings(lambda m=method: mutual_information(x, y, method=m))
        assert truth - value > _tol(truth), method
        assert len(said) == 1 and "the sample shows a dependence" in said[0], method


def _poisson_pair_mi(lam, mu):
    xs, ys = np.arange(0, 120), np.arange(0, 140)
    px = stats.poisson.pmf(xs, lam)
    joint = px[:, None] * stats.poisson.pmf(ys[None, :] - xs[:, None], mu)
    py = joint.sum(axis=0)
    ok = joint > 0
    return float(np.sum(joint[ok] * np.log(joint[ok] / np.outer(px, py)[ok])))


def test_kde_of_counts_on_a_lattice_is_warned():
    rng = np.random.default_rng(10)
    x = rng.poisson(30, N).astype(float)
    y = x + rng.poisson(2.0, N)
    truth = _poisson_pair_mi(30, 2.0)  # 1.444 nats
    value, said = _warnings(lambda: mutual_information(x, y, method="kde"))
    assert value - truth > _tol(truth)
    assert len(said) == 1 and "not resolved at this n" in said[0]


@pytest.mark.parametrize("method", ["ksg", "kde", "histogram", "gaussian"])
def test_a_resolved_gaussian_pair_is_silent(method):
    rng = np.random.default_rng(11)
    x = rng.standard_normal(N)
    y = 0.9 * x + math.sqrt(0.19) * rng.standard_normal(N)
    value, said = _warnings(lambda: mutual_information(x, y, method=method))
    assert said == []
    assert abs(value - (-0.5 * math.log(0.19))) < _tol(0.830)


def _var_pair(a, source_rho, seed, b=0.5, n=N, burn=3000):
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -source_rho], rng.standard_normal(n + burn))
    y = lfilter([1.0], [1.0, -a], np.r_[0.0, b * x[:-1]] + rng.standard_normal(n + burn))
    return x[burn:], y[burn:]


def _var_te(a, source_rho, b=0.5):
    # state (y, x): A = [[a, b], [0, rho]], unit innovations; TE = I(y_t; x_{t-1} | y_{t-1})
    A = np.array([[a, b], [0.0, source_rho]])
    S = solve_discrete_lyapunov(A, np.eye(2))
    AS = A @ S
    C = np.array([[S[0, 0], AS[0, 0], AS[0, 1]],
                  [AS[0, 0], S[0, 0], S[0, 1]],
                  [AS[0, 1], S[1, 0], S[1, 1]]])

    def ld(idx):
        return np.linalg.slogdet(C[np.ix_(idx, idx)])[1]

    return 0.5 * (ld([0, 1]) + ld([2, 1]) - ld([1]) - ld([0, 1, 2]))


def test_gaussian_copula_te_of_a_persistent_pair_is_warned():
    x, y = _var_pair(0.99, 0.9, 12)
    truth = _var_te(0.99, 0.9)  # 0.398 nats
    value, said = _warnings(lambda: transfer_entropy(x, y, method="gaussian"))
    assert truth - value > _tol(truth)
    assert len(said) == 1 and "the ranks distort this dependence" in said[0]


def test_gaussian_copula_te_of_a_white_source_is_silent():
    x, y = _var_pair(0.9, 0.0, 13)
    truth = _var_te(0.9, 0.0)  # 0.5 ln(1 + b^2) = 0.1116
    value, said = _warnings(lambda: transfer_entropy(x, y, method="gaussian"))
    assert said == []
    assert abs(value - truth) < _tol(truth)


def test_gaussian_copula_te_of_a_glitched_source_is_silent():
    # one source sample at 1e6 collapses the values' Gaussian TE (to ~0), not the
    # scores': the rule, which looks only for values above scores, leaves the robust
    # estimate alone (exact 0.5 ln(1 + b^2) = 0.1116)
    x, y = _var_pair(0.5, 0.0, 14)
    x[100] = 1e6
    value, said = _warnings(lambda: transfer_entropy(x, y, method="gaussian"))
    assert said == []
    assert abs(value - _var_te(0.5, 0.0)) < _tol(0.1116)


def test_conditional_mi_of_multivariate_student_t_is_not_judged():
    # a common chi-square scale: the values' Gaussian MI of a Student-t (df 1) 2 x 2
    # pair is far above the scores' by chance; the CMI's columns need not be series,
    # and only the transfer entropy judges the scores rule
    rng = np.random.default_rng(15)
    g = rng.standard_normal((N, 4)) / np.sqrt(rng.chisquare(1, (N, 1)))
    _, said = _warnings(lambda: conditional_mutual_information(g[:, :2], g[:, 2:],
                                                               method="gaussian"))
    assert said == []
