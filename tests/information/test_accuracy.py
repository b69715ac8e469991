"""Accuracy of the MI and entropy estimators against analytic truth.

References: bivariate normal MI ``-0.5 ln(1 - rho^2)`` and normal entropy
``0.5 ln(2 pi e sigma^2)`` (Cover & Thomas 2006, Examples 8.5.1 and 8.1.2); the
invariance of MI under monotone transforms of one variable (ibid., sec. 8.6) and its
symmetry; y = x^2 + noise has zero correlation but large MI.
"""

import numpy as np
import pytest

from modalinfo.information import MutualInformation, entropy, mutual_information

RHOS = (0.0, 0.3, 0.6, 0.9)


def _gaussian_pair(rho, n, seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, rho * x + np.sqrt(1.0 - rho**2) * rng.standard_normal(n)


@pytest.fixture(scope="module")
def bias_table():
    """Mean error over 20 seeds at n = 1e4 for every rho, KDE and histogram defaults.

    About 3 s on the reference machine, so it runs in the default tier.
    """
    table = {}
    for rho in RHOS:
        truth = -0.5 * np.log(1.0 - rho**2)
        err = {"kde": [], "histogram": []}
        for seed in range(20):
            x, y = _gaussian_pair(rho, 10_000, seed)
            for method in err:
                err[method].append(mutual_information(x, y, method=method) - truth)
        table[rho] = {m: (np.mean(v), np.std(v, ddof=1)) for m, v in err.items()}
    return table


@pytest.mark.parametrize("rho", RHOS)
def test_gaussian_bias_at_n_1e4(bias_table, rho):
    # Targets of GitHub issue 4: |mean bias| <= 0.02 (KDE) and <= 0.03 (histogram)
    # for rho <= 0.6, both within 0.05 at rho = 0.9. The standard error of a 20-seed
    # mean is <= 0.002 nats here, so the check is not decided by noise.
    kde_bias, kde_sd = bias_table[rho]["kde"]
    hist_bias, hist_sd = bias_table[rho]["histogram"]
    assert kde_sd / np.sqrt(20) < 0.003 and hist_sd / np.sqrt(20) < 0.003
    if rho <= 0.6:
        assert abs(kde_bias) <= 0.02
        assert abs(hist_bias) <= 0.03
    else:
        assert abs(kde_bias) <= 0.05
        assert abs(hist_bias) <= 0.05


@pytest.mark.parametrize("method", ["ksg", "gaussian"])
def test_reference_estimators_on_gaussian_pair(method):
    # single n = 1e4 sample; KSG sd ~0.012 nats, Gaussian sd ~0.01: 4-sigma tolerance
    for rho in (0.3, 0.9):
        x, y = _gaussian_pair(rho, 10_000, 99)
        truth = -0.5 * np.log(1.0 - rho**2)
        assert mutual_information(x, y, method=method) == pytest.approx(truth, abs=0.05)


def test_copula_kde_invariant_under_monotone_transforms():
    x, y = _gaussian_pair(0.6, 5000, 1)
    truth = -0.5 * np.log(1 - 0.36)
    base = mutual_information(x, y, method="kde", copula=True)
    for fx in (np.exp(x), x**3, np.arctan(2 * x)):
        # ranks are unchanged, so the copula estimate is unchanged to rounding
        assert mutual_information(fx, y, method="kde", copula=True) == pytest.approx(
            base, abs=1e-9)
    assert base == pytest.approx(truth, abs=0.03)
    # without the copula the exp transform (lognormal) changes the estimate, but it
    # must stay close to the invariant truth: the KDE is consistent for any density
    raw = mutual_information(np.exp(x), y, method="kde")
    assert raw == pytest.approx(truth, abs=0.06)


def test_nonlinear_dependence_seen_by_nonparametric_estimators():
    rng = np.random.default_rng(4)
    x = rng.standard_normal(10_000)
    y = x**2 + 0.1 * rng.standard_normal(10_000)
    # r ~ N(0, 1/sqrt(n)): the Gaussian estimate is r^2/2 ~ 1e-4
    assert abs(mutual_information(x, y, method="gaussian")) < 0.005
    # the MI is > 1 nat (KSG gives ~2.0, KDE ~1.0); the default histogram (16 bins,
    # chosen from r ~ 0) resolves the thin parabola coarsely and gives ~0.9.
    # "Clearly positive" = above 0.5, 100 times the Gaussian estimate bound.
    for method in ("histogram", "kde", "ksg"):
        assert mutual_information(x, y, method=method) > 0.5, method


@pytest.mark.parametrize(("method", "tol"), [("kde", 0.01), ("histogram", 0.02),
                                             ("ksg", 0.03), ("gaussian", 0.01)])
def test_entropy_of_normal(method, tol):
    sigma = 1.7
    x = sigma * np.random.default_rng(5).standard_normal(20_000)
    truth = 0.5 * np.log(2 * np.pi * np.e * sigma**2)
    assert entropy(x, method=method) == pytest.approx(truth, abs=tol)


def test_mi_nonnegative_and_increasing_with_rho():
    # invariant: estimates increase with the dependence, and are ~0 at independence
    est = MutualInformation("kde")
    x, _ = _gaussian_pair(0.0, 4000, 7)
    noise = np.random.default_rng(8).standard_normal(4000)
    est.fit(x)
    vals = [est.score(r * x + np.sqrt(1 - r**2) * noise) for r in (0.0, 0.2, 0.5, 0.8, 0.95)]
    assert np.all(np.diff(vals) > 0)
    # KDE bias at rho = 0, n = 4000 is about -0.008 nats (LOO resubstitution)
    assert vals[0] > -0.02
