"""KSG on data with ties, and scale invariance of every MI estimator.

References:
- the exact MI of a discretised standard bivariate normal pair (rho = 0.6), computed
  from its joint pmf: cell probabilities by inclusion-exclusion of
  ``scipy.stats.multivariate_normal.cdf`` at the cell edges (values rounded to 1 and
  to 0.5); for signs (booleans) Sheppard's formula P(X > 0, Y > 0) = 1/4 +
  arcsin(rho) / (2 pi);
- scikit-learn's ``mutual_info_regression`` (KSG with the same tie noise) as a peer;
- MI is invariant under a change of scale of either variable (Cover & Thomas 2006,
  sec. 8.6): the estimates on data multiplied by 1e-300 ... 1e300 equal those on the
  data itself.
"""

import warnings

import numpy as np
import pytest
from scipy import stats
from sklearn.feature_selection import mutual_info_regression

from modalinfo.information import METHODS, mutual_information

RHO = 0.6


def _pair(n, seed, rho=RHO):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, rho * x + np.sqrt(1 - rho**2) * rng.standard_normal(n)


def _discretised_normal_mi(rho, step, lim=8.0):
    """Exact MI (nats) of (round(X / step), round(Y / step)) for a standard normal pair."""
    cuts = np.arange(-lim, lim + 1e-9, step) + step / 2  # edges between rounded values
    edges = np.concatenate([[-12.0], cuts[cuts < lim], [12.0]])  # +-12 sd: P < 1e-32
    gx, gy = np.meshgrid(edges, edges, indexing="ij")
    cdf = stats.multivariate_normal([0.0, 0.0], [[1.0, rho], [rho, 1.0]]).cdf(
        np.stack([gx, gy], axis=-1))
    cdf[0, :] = 0.0
    cdf[:, 0] = 0.0
    p = np.clip(np.diff(np.diff(cdf, axis=0), axis=1), 0.0, None)
    p /= p.sum()
    px, py = p.sum(1), p.sum(0)
    nz = p > 0
    return float(np.sum(p[nz] * np.log(p[nz] / np.outer(px, py)[nz])))


def _sign_mi(rho):
    q = 0.25 + np.arcsin(rho) / (2 * np.pi)
    p = np.array([[q, 0.5 - q], [0.5 - q, q]])
    return float(np.sum(p * np.log(p / 0.25)))


@pytest.mark.parametrize("kind", ["round1", "round0.5", "bool"])
def test_ksg_on_tied_data_estimates_the_discrete_mi(kind):
    # n = 5000: the estimate's sd over seeds is ~0.012 nats (measured, 6 seeds), so
    # 0.05 is ~4 sd; without tie handling the estimates were -4.7, -3.4 and -0.9.
    x, y = _pair(5000, 7)
    if kind == "bool":
        xd, yd, truth = (x > 0).astype(float), (y > 0).astype(float), _sign_mi(RHO)
    else:
        step = 1.0 if kind == "round1" else 0.5
        xd, yd = np.round(x / step) * step, np.round(y / step) * step
        truth = _discretised_normal_mi(RHO, step)
    got = mutual_information(xd, yd, method="ksg")
    peer = mutual_info_regression(xd[:, None], yd, n_neighbors=3, random_state=0)[0]
    assert got == pytest.approx(truth, abs=0.05)
    assert got == pytest.approx(peer, abs=0.05)
    # reproducible (seeded noise), and the seed is an option
    assert mutual_information(xd, yd, method="ksg") == got
    assert mutual_information(xd, yd, method="ksg", seed=3) == pytest.approx(truth, abs=0.05)


def test_ksg_integer_data_near_independence_is_not_large_negative():
    rng = np.random.default_rng(8)
    x, y = rng.integers(0, 5, (2, 3000)).astype(float)
    assert abs(mutual_information(x, y, method="ksg")) < 0.03


def test_ksg_without_ties_is_unchanged_by_the_tie_handling():
    # continuous data: no noise is added, the estimate equals scikit-learn's (whose
    # 1e-10 noise changes nothing at this precision)
    x, y = _pair(2000, 9)
    ref = mutual_info_regression(x[:, None], y, n_neighbors=3, random_state=0)[0]
    got = mutual_information(x, y, method="ksg", copula=False)  # sklearn's scaling
    assert got == pytest.approx(ref, rel=1e-9)


@pytest.mark.parametrize("method", METHODS)
def test_estimators_are_scale_invariant(method):
    rng = np.random.default_rng(10)
    x, y = rng.standard_normal((2, 3000))
    xd, yd = _pair(3000, 11)
    base_indep = mutual_information(x, y, method=method)
    base_dep = mutual_information(xd, yd, method=method)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow / underflow / division warnings
        for sx, sy in [(1e-300, 1e-300), (1e-170, 1e-170), (1e150, 1e150), (1e300, 1e300),
                       (1e-300, 1e300)]:
            assert mutual_information(x * sx, y * sy, method=method) == pytest.approx(
                base_indep, rel=1e-6, abs=1e-9), (sx, sy)
            assert mutual_information(xd * sx, yd * sy, method=method) == pytest.approx(
                base_dep, rel=1e-6), (sx, sy)
    if method == "gaussian":
        assert abs(base_indep) < 0.005
        assert base_dep == pytest.approx(-0.5 * np.log(1 - RHO**2), abs=0.03)
