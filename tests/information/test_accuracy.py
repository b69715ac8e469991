"""Accuracy of the MI and entropy estimators against analytic truth.

References: bivariate normal MI ``-0.5 ln(1 - rho^2)`` and normal entropy
``0.5 ln(2 pi e sigma^2)`` (Cover & Thomas 2006, Examples 8.5.1 and 8.1.2); the
invariance of MI under monotone transforms of one variable (ibid., sec. 8.6) and its
symmetry; y = x^2 + noise has zero correlation but large MI. Tolerances are
multiples of the estimates' standard errors (computed, or measured and stated).
"""

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    MutualInformation,
    entropy,
    mutual_information,
)

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


# Standard deviation of single estimates at n = 1e4 (12 seeds, measured): KSG 0.0105
# and 0.0111 nats at rho = 0.3 and 0.9; Gaussian 0.0041 and 0.0070 (the delta method
# gives rho / sqrt(n) = 0.003 and 0.009). Scaled by sqrt(1e4 / n).
_SD_1E4 = {("ksg", 0.3): 0.0105, ("ksg", 0.9): 0.0111,
           ("gaussian", 0.3): 0.0041, ("gaussian", 0.9): 0.0070}


@pytest.mark.parametrize("method", ["ksg", "gaussian"])
@pytest.mark.parametrize("rho", [0.3, 0.9])
def test_reference_estimators_on_gaussian_pair(method, rho):
    # n = 4e4: the tolerance, 5 standard deviations, is well below the truth at
    # rho = 0.3 (0.047 nats), so an estimator returning 0 fails
    n = 40_000
    x, y = _gaussian_pair(rho, n, 99)
    truth = -0.5 * np.log(1.0 - rho**2)
    tol = 5 * _SD_1E4[(method, rho)] * np.sqrt(1e4 / n)
    assert tol < 0.6 * truth
    assert mutual_information(x, y, method=method) == pytest.approx(truth, abs=tol)


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
    assert mutual_information(x, y, method="ksg") > 0.5
    # the KDE's 1.73 is below KSG's ~2.0 by more than max(0.05, 10 %), and since fix49-a
    # is said to: the normal scores' squares depend on the scores (the parabola)
    with pytest.warns(BiasRuleWarning, match="spread rule"):
        assert mutual_information(x, y, method="kde") > 0.5
    # the histogram's 1.35 misses part of the dependence and is said to (Leftovers
    # 11-resolve, neighbour rule): the MI is at least h(chi2_1) - h(noise) = 1.667 nats
    # (noise added to x^2 cannot lower its entropy; scipy's chi2(1).entropy() = 0.784)
    with pytest.warns(BiasRuleWarning, match="the value is a lower bound"):
        assert 0.5 < mutual_information(x, y, method="histogram") < 1.667


@pytest.mark.parametrize("method", ["kde", "histogram", "ksg", "gaussian"])
def test_entropy_of_normal(method):
    # n = 2e5. Standard error of a plug-in entropy of a normal sample: sqrt(Var[-ln f(X)]
    # / n) = sqrt(0.5 / n) = 0.0016 nats (-ln f(X) = c + chi2_1 / 2); the
    # Kozachenko-Leonenko estimator adds Var[ln eps] = psi'(k) (k = 3: 0.395). The
    # tolerance is 5 standard errors plus 0.002 for the estimators' biases (measured
    # below 0.001 at this n over 8 seeds).
    from scipy.special import polygamma

    n, sigma = 200_000, 1.7
    x = sigma * np.random.default_rng(5).standard_normal(n)
    truth = 0.5 * np.log(2 * np.pi * np.e * sigma**2)
    var = 0.5 + (float(polygamma(1, 3)) if method == "ksg" else 0.0)
    tol = 5 * np.sqrt(var / n) + 0.002
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
