"""The regime rules' cost without their redundant work (Leftovers 12-cost, item 3).

References from outside the rules: scipy's Chatterjee xi (``scipy.stats.chatterjeexi``)
for the neighbours rule's sort; numpy's seeded permutation split in four
(``numpy.random.default_rng(seed).permutation``, ``numpy.array_split``) for the
quarters; the public estimator (``MutualInformation(method).estimate``) on each quarter
for the convergence rule's mean, read back from its message; and counted calls: the
copy and curve checks of a ``mutual_information`` call run once, on the whole pair (its
quarters are parts of a pair that passed them), where they ran four times before.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import stats

from modalinfo.information import BiasRuleWarning, MutualInformation, api, mutual_information
from modalinfo.information import convergence as cv


def _gauss(n, rho, seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, rho * x + math.sqrt(1 - rho**2) * rng.standard_normal(n)


def _zigzag10(n, seed):
    rng = np.random.default_rng(seed)
    x = rng.uniform(0, 1, n)
    u = 10 * x
    k = np.floor(np.minimum(u, 10 - 1e-12))
    return x, np.where(k % 2 == 0, u - k, 1 - (u - k)) + 0.1 * rng.standard_normal(n)


@pytest.mark.parametrize("method", ["histogram", "kde"])
def test_the_copy_checks_run_once_per_call(monkeypatch, method):
    calls = []
    real = api._check_not_a_copy

    def counted(*args, **kwargs):
        calls.append(args[0].shape[0])
        return real(*args, **kwargs)

    monkeypatch.setattr(api, "_check_not_a_copy", counted)
    x, y = _gauss(8000, 0.6, 3)
    value = MutualInformation(method).estimate(x, y)
    xi, _ = cv._neighbours(x, y)
    assert value < cv.xi_gaussian_mi(xi)  # rule 2 runs on this pair
    calls.clear()
    mutual_information(x, y, method=method)
    assert calls == [8000]  # the whole pair only: 3 quarters of 2000 were checked too


def test_quarters_are_the_seeded_permutation_split_in_four():
    n = 10_001
    perm = np.random.default_rng(20261129).permutation(n)
    parts = cv._quarters(n)
    assert len(parts) == cv.QUARTERS == 3
    for got, want in zip(parts, np.array_split(perm, 4)[:3], strict=True):
        np.testing.assert_array_equal(got, np.sort(want))
        assert not got.flags.writeable  # cached: a caller cannot change the next call's
    assert cv._quarters(n) is parts


def test_neighbours_xi_is_scipys_either_way():
    x, y = _gauss(20_000, 0.75, 4)
    xi, ties = cv._neighbours(x, y)
    want = max(stats.chatterjeexi(x, y).statistic, stats.chatterjeexi(y, x).statistic)
    assert not ties and xi == pytest.approx(want, rel=1e-12)
    xt = np.round(x, 1)  # repeated values: reported (xi is then not used)
    assert cv._neighbours(xt, y)[1]


def test_the_quarters_are_scored_as_the_public_estimator_scores_them():
    # Poisson counts (ties: rule 3 does not judge them), kde: rule 2 warns
    rng = np.random.default_rng(10)
    x = rng.poisson(30, 5000).astype(float)
    y = x + rng.poisson(2.0, 5000)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method="kde")
    said = [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)]
    text = cv.convergence_rule(lambda a, b: MutualInformation("kde").estimate(a, b),
                               x, y, value)
    assert text is not None and "not resolved at this n" in text
    assert said == [f"mutual_information with method='kde': {text}."]
