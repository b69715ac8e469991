"""KDE MI and entropy: the FFT-grid computation against a direct O(n^2) numpy evaluation.

References: a direct numpy leave-one-out resubstitution estimate with the same
kernel (covariance h^2 S of the standardised pair, marginals with h^2 s^2), which is
what the grid approximates; ``scipy.stats.gaussian_kde`` bandwidth factors; the
analytic entropy of a normal variable. ``bandwidth="cv"``: the direct leave-one-out
likelihood maximised over h by ``scipy.optimize.minimize_scalar`` (same search
interval, tight tolerance), and the direct estimate at that optimum. Discrete pairs
(few distinct values): the Miller-Madow plug-in MI of the contingency table written
out with ``scipy.stats.entropy`` (Miller 1955), and the exact MI of a binary symmetric
channel, ln 2 - H_b(p).
"""

import numpy as np
import pytest
from scipy import stats
from scipy.optimize import minimize_scalar

from modalinfo.information import entropy, mutual_information
from modalinfo.information.kde import bandwidth_factor, copula_scores


def _direct_loo_mi(x, y, h, *, joint_loglik=False):
    n = x.size
    u = (x - x.mean()) / x.std()
    v = (y - y.mean()) / y.std()
    r = np.mean(u * v)
    cov = h**2 * np.array([[1.0, r], [r, 1.0]])
    z = np.column_stack([u, v])
    d = z[:, None, :] - z[None, :, :]
    q = np.einsum("ijk,kl,ijl->ij", d, np.linalg.inv(cov), d)
    kxy = np.exp(-0.5 * q) / (2 * np.pi * np.sqrt(np.linalg.det(cov)))
    kx = np.exp(-0.5 * (u[:, None] - u[None, :]) ** 2 / h**2) / (np.sqrt(2 * np.pi) * h)
    ky = np.exp(-0.5 * (v[:, None] - v[None, :]) ** 2 / h**2) / (np.sqrt(2 * np.pi) * h)
    for k in (kxy, kx, ky):
        np.fill_diagonal(k, 0.0)
    fxy, fx, fy = (k.sum(1) / (n - 1) for k in (kxy, kx, ky))
    if joint_loglik:
        return np.mean(np.log(fxy))
    return np.mean(np.log(fxy / (fx * fy)))


def _direct_loo_loglik_1d(u, h):
    k = np.exp(-0.5 * (u[:, None] - u[None, :]) ** 2 / h**2) / (np.sqrt(2 * np.pi) * h)
    np.fill_diagonal(k, 0.0)
    return np.mean(np.log(k.sum(1) / (u.size - 1)))


def _clustered_pair(n=500, seed=2):
    """Three clusters: the likelihood-CV bandwidth (0.18) is half Scott's (0.35)."""
    rng = np.random.default_rng(seed)
    c = rng.integers(0, 3, n)
    x = c + 0.25 * rng.standard_normal(n)
    return x, 0.5 * c + 0.25 * rng.standard_normal(n) + 0.2 * np.sin(3 * x)


def _normal_scores(a):
    return stats.norm.ppf(stats.rankdata(a) / (a.size + 1))


@pytest.mark.parametrize("copula", [True, False])
@pytest.mark.parametrize("rho", [0.0, 0.5, 0.95])
@pytest.mark.parametrize("h", [None, 0.6])
def test_grid_matches_direct_loo_estimate(rho, h, copula):
    # default (copula=True): the direct sum on scipy's normal scores of the ranks;
    # copula=False (the former default): on the values
    rng = np.random.default_rng(11)
    n = 600
    x = rng.standard_normal(n)
    y = rho * x + np.sqrt(1 - rho**2) * rng.standard_normal(n)
    y = y + 0.3 * np.tanh(3 * x)  # make it non-Gaussian
    hh = bandwidth_factor("scott", n, 2) if h is None else h
    ref = (_direct_loo_mi(_normal_scores(x), _normal_scores(y), hh) if copula
           else _direct_loo_mi(x, y, hh))
    opts = {} if copula else {"copula": False}
    got = mutual_information(x, y, method="kde", bandwidth="scott" if h is None else h, **opts)
    # the default grid (128 points, delta/h ~ 0.2) reproduces the direct sum to ~1e-5
    assert got == pytest.approx(ref, abs=1e-4)


def test_bandwidth_factors_match_scipy():
    data = np.random.default_rng(1).standard_normal((2, 500))
    kde = stats.gaussian_kde(data)
    assert bandwidth_factor("scott", 500, 2) == pytest.approx(kde.scotts_factor())
    assert bandwidth_factor("silverman", 500, 2) == pytest.approx(kde.silverman_factor())
    kde1 = stats.gaussian_kde(data[0])
    assert bandwidth_factor("silverman", 500, 1) == pytest.approx(kde1.silverman_factor())


def test_kde_entropy_against_direct_and_analytic():
    rng = np.random.default_rng(2)
    x = 2.0 * rng.standard_normal(800)
    h = bandwidth_factor("scott", 800, 1)
    u = (x - x.mean()) / x.std()
    k = np.exp(-0.5 * (u[:, None] - u[None, :]) ** 2 / h**2) / (np.sqrt(2 * np.pi) * h)
    np.fill_diagonal(k, 0.0)
    ref = -np.mean(np.log(k.sum(1) / 799)) + np.log(x.std())
    assert entropy(x, method="kde") == pytest.approx(ref, abs=1e-3)
    big = 2.0 * rng.standard_normal(20_000)
    truth = 0.5 * np.log(2 * np.pi * np.e * 4.0)  # Cover & Thomas 2006, Example 8.1.2
    assert entropy(big, method="kde") == pytest.approx(truth, abs=0.015)
    assert entropy(big, method="kde", bandwidth="cv") == pytest.approx(truth, abs=0.015)


def test_copula_scores_are_normal_scores_of_ranks():
    x = np.array([3.0, -1.0, 10.0, 0.5])
    np.testing.assert_allclose(copula_scores(x), stats.norm.ppf(np.array([3, 1, 4, 2]) / 5.0))


def test_cv_bandwidth_gives_sensible_estimate():
    rng = np.random.default_rng(3)
    x = rng.standard_normal(3000)
    y = 0.6 * x + 0.8 * rng.standard_normal(3000)
    truth = -0.5 * np.log(1 - 0.36)
    assert mutual_information(x, y, method="kde", bandwidth="cv") == pytest.approx(truth,
                                                                                  abs=0.03)


def test_cv_bandwidth_is_the_leave_one_out_likelihood_optimum():
    x, y = _clustered_pair()
    n = x.size
    h0 = bandwidth_factor("scott", n, 2)
    bounds = (np.log(0.2), np.log(3.0))  # the documented search interval, x Scott's
    res = minimize_scalar(lambda t: -_direct_loo_mi(x, y, h0 * np.exp(t), joint_loglik=True),
                          bounds=bounds, method="bounded", options={"xatol": 1e-4})
    h_cv = h0 * np.exp(res.x)
    ref = _direct_loo_mi(x, y, h_cv)
    scott = _direct_loo_mi(x, y, h0)
    assert abs(ref - scott) > 0.01  # the test tells the CV optimum from Scott's rule
    # the grid search stops at 2 % in h: the MI moves by < 1e-3 nats there
    assert mutual_information(x, y, method="kde", bandwidth="cv", copula=False) == pytest.approx(
        ref, abs=3e-3)
    # 1-D entropy: H = -max_h LOO log-likelihood of the standardised sample + ln(sd)
    u = (x - x.mean()) / x.std()
    h1 = bandwidth_factor("scott", n, 1)
    res1 = minimize_scalar(lambda t: -_direct_loo_loglik_1d(u, h1 * np.exp(t)), bounds=bounds,
                           method="bounded", options={"xatol": 1e-4})
    ref_h = res1.fun + np.log(x.std())
    scott_h = -_direct_loo_loglik_1d(u, h1) + np.log(x.std())
    assert abs(ref_h - scott_h) > 0.01
    assert entropy(x, method="kde", bandwidth="cv") == pytest.approx(ref_h, abs=3e-3)


def test_separable_fft_smoothing_equals_scipy_fftconvolve():
    from scipy.signal import fftconvolve

    from modalinfo.information.kde import _smooth_2d

    rng = np.random.default_rng(4)
    grid = rng.random((57, 73))
    ker = np.exp(-0.5 * np.linspace(-3, 3, 13) ** 2)
    np.testing.assert_allclose(_smooth_2d(grid, ker),
                               fftconvolve(grid, np.outer(ker, ker), mode="same"), atol=1e-12)


def test_1d_fft_smoothing_equals_scipy_fftconvolve():
    from scipy.signal import fftconvolve

    from modalinfo.information.kde import _smooth_1d

    rng = np.random.default_rng(5)
    grid = rng.random(301)
    ker = np.exp(-0.5 * np.linspace(-4, 4, 41) ** 2)
    np.testing.assert_allclose(_smooth_1d(grid, ker), fftconvolve(grid, ker, mode="same"),
                               atol=1e-12)


def test_reused_work_arrays_give_the_same_estimates_across_sizes_and_threads():
    # Reference: the same estimator called serially with fresh engines.
    from concurrent.futures import ThreadPoolExecutor

    from modalinfo.information import MutualInformation

    rng = np.random.default_rng(8)
    pairs = []
    for n in (3000, 5000, 3000):
        x = rng.standard_normal(n)
        pairs.append((x, 0.5 * x + rng.standard_normal(n) + 0.2 * x**2))
    serial = [mutual_information(x, y, method="kde") for x, y in pairs]
    assert [mutual_information(x, y, method="kde") for x, y in pairs] == serial
    est = MutualInformation("kde").fit(pairs[0][0])
    with ThreadPoolExecutor(4) as pool:
        got = list(pool.map(lambda k: mutual_information(*pairs[k % 3], method="kde"),
                            range(24)))
        scores = list(pool.map(lambda _: est.score(pairs[0][1]), range(8)))
    assert got == [serial[k % 3] for k in range(24)]
    assert scores == [serial[0]] * 8


def _mm_plugin(x, y):
    _, cx = np.unique(x, return_inverse=True)
    _, cy = np.unique(y, return_inverse=True)
    joint = np.zeros((cx.max() + 1, cy.max() + 1))
    np.add.at(joint, (cx, cy), 1.0)
    n = x.size
    h = [stats.entropy(c[c > 0]) + ((c > 0).sum() - 1) / (2 * n)
         for c in (joint.sum(1), joint.sum(0), joint.ravel())]
    return h[0] + h[1] - h[2]


def test_discrete_pair_is_the_miller_madow_plugin_of_its_table():
    # x with 4 levels, y with 5 at n = 200: 20 cells, exactly 10 samples per cell on
    # average, the rule's boundary (m_x m_y <= n / 10) -> the table's plug-in
    rng = np.random.default_rng(3)
    xi = rng.integers(0, 4, 200)
    x = xi * 0.7 - 3.0
    y = np.clip(xi + rng.integers(-1, 3, 200), 0, 4).astype(float)
    assert np.unique(x).size * np.unique(y).size == 20
    assert mutual_information(x, y, method="kde") == pytest.approx(_mm_plugin(x, y), rel=1e-12)
    # one sample fewer: 20 cells > 199 / 10, the kernel path (a different number)
    assert mutual_information(x[:199], y[:199], method="kde") != pytest.approx(
        _mm_plugin(x[:199], y[:199]), rel=1e-3)


def test_binary_symmetric_channel_mi():
    # X ~ Bernoulli(1/2), Y = X xor Bernoulli(0.1): I = ln 2 - H_b(0.1) = 0.3681 nats; the
    # plug-in's sd at n = 4000 is ~0.01 (sqrt(Var[ln p(x,y)/(p(x)p(y))] / n))
    rng = np.random.default_rng(5)
    x = rng.integers(0, 2, 4000)
    y = x ^ (rng.random(4000) < 0.1)
    exact = np.log(2.0) + 0.1 * np.log(0.1) + 0.9 * np.log(0.9)
    assert mutual_information(x, y.astype(float), method="kde") == pytest.approx(exact, abs=0.03)
