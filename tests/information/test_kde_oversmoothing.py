"""The KDE's oversmoothing rule: a multimodal law is said, not silently smoothed away.

References: the exact entropy of the mixture 0.5 N(0, 1) + 0.5 N(100, 1) by numerical
integration (scipy.integrate.quad, 2.1121 nats = ln 2 + 0.5 ln(2 pi e) to 1e-9), the
exact MI of x and y = x + N(0, 1) for that x (ln 2 + 0.5 ln 2: the mixture of two
N(., 2)), and scikit-learn's cross-validated KernelDensity (bandwidth by grid search on
held-out likelihood), which recovers the mixture's entropy where the overall-spread
rules do not. Unimodal laws (normal, Laplace, uniform) must not be flagged.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import integrate, stats

from modalinfo.information import (
    conditional_mutual_information,
    entropy,
    mutual_information,
)
from modalinfo.information.methods import BiasRuleWarning

N = 2000


@pytest.fixture(scope="module")
def bimodal():
    rng = np.random.default_rng(0)
    x = np.r_[rng.normal(0.0, 1.0, N // 2), rng.normal(100.0, 1.0, N // 2)]
    rng.shuffle(x)
    return x, x + rng.normal(size=N), rng.normal(size=N)


def _mixture_entropy() -> float:
    def f(t):
        return 0.5 * stats.norm.pdf(t) + 0.5 * stats.norm.pdf(t, 100.0)

    def g(t):
        p = f(t)
        return -p * math.log(p) if p > 0 else 0.0

    return sum(integrate.quad(g, a, b, limit=200)[0] for a, b in ((-15, 15), (85, 115)))


def test_entropy_of_two_far_modes_is_flagged_and_ksg_is_right(bimodal):
    x = bimodal[0]
    truth = _mixture_entropy()
    assert truth == pytest.approx(math.log(2) + 0.5 * math.log(2 * math.pi * math.e), 1e-9)
    with pytest.warns(BiasRuleWarning, match="oversmooths x"):
        kde = entropy(x, method="kde")
    assert kde - truth > 1.0  # what the warning is about: 4.0 nats for 2.11
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert entropy(x, method="ksg") == pytest.approx(truth, abs=0.05)


def test_a_cross_validated_bandwidth_confirms_the_regime(bimodal):
    # sklearn's KernelDensity with a held-out-likelihood bandwidth resolves the modes
    from sklearn.model_selection import GridSearchCV
    from sklearn.neighbors import KernelDensity

    x = bimodal[0][:, None]
    search = GridSearchCV(KernelDensity(), {"bandwidth": np.geomspace(0.05, 20, 13)}, cv=3)
    search.fit(x)
    h_cv = search.best_params_["bandwidth"]
    assert h_cv < 1.0 < 0.2 * N ** -0.2 * float(np.std(x))  # cv: below the modes' width
    resub = -float(np.mean(search.best_estimator_.score_samples(x)))
    assert resub == pytest.approx(_mixture_entropy(), abs=0.1)


@pytest.mark.parametrize("what", ["mi", "cmi"])
def test_mi_and_cmi_on_raw_values_are_flagged(bimodal, what):
    x, y, z = bimodal
    truth = 1.5 * math.log(2)
    with pytest.warns(BiasRuleWarning, match="oversmooths"):
        if what == "mi":
            value = mutual_information(x, y, method="kde", copula=False)
        else:
            value = conditional_mutual_information(x, y, z, method="kde", copula=False)
    assert abs(value - truth) > 0.2
    with warnings.catch_warnings():  # normal scores are unimodal: no warning
        warnings.simplefilter("error")
        if what == "mi":
            mutual_information(x, y, method="kde")
        else:
            conditional_mutual_information(x, y, z, method="kde")


@pytest.mark.parametrize("law", ["normal", "laplace", "uniform", "near_modes"])
@pytest.mark.parametrize("n", [50, 2000])
def test_unimodal_and_near_modes_are_not_flagged(law, n):
    rng = np.random.default_rng(n)
    x = {"normal": lambda: rng.normal(size=n), "laplace": lambda: rng.laplace(size=n),
         "uniform": lambda: rng.uniform(size=n),
         "near_modes": lambda: np.r_[rng.normal(0, 1, n // 2), rng.normal(4, 1, n - n // 2)],
         }[law]()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        entropy(x, method="kde")
        mutual_information(x, x + rng.normal(size=n), method="kde", copula=False)
