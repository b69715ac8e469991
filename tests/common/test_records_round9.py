"""Result records holding arrays compare with == (round 9, rows a-eq-*, eq-*).

Reference: the package's same-seed-same-bits contract. Two calls with the same inputs and
seed return equal records; a record with one array value changed (dataclasses.replace) or
of another class is not equal. Before, ``r == r`` raised numpy's "truth value of an
array is ambiguous" for every such record (MI intervals and tests, the transfer-entropy
map, orderings, fitting errors, stability, quality reports, summaries, evaluations).
"""

import dataclasses

import numpy as np

from modalinfo.common.records import same_value
from modalinfo.information import mutual_information_ci, mutual_information_permutation_test
from modalinfo.telemetry import assess_quality


def test_same_calls_equal_changed_records_not():
    rng = np.random.default_rng(0)
    x, y = rng.multivariate_normal([0, 0], [[1, 0.6], [0.6, 1]], 500).T
    a = mutual_information_ci(x, y, seed=1, n_resamples=20)
    b = mutual_information_ci(x, y, seed=1, n_resamples=20)
    assert a == b
    moved = b.bootstrap_distribution.copy()
    moved[0] += 1.0
    assert a != dataclasses.replace(b, bootstrap_distribution=moved)
    p = mutual_information_permutation_test(x, y, n_permutations=20, seed=1)
    assert p == mutual_information_permutation_test(x, y, n_permutations=20, seed=1)
    assert (p == a) is False
    q = assess_quality(np.c_[x, y])
    assert q == assess_quality(np.c_[x, y])


def test_same_value_rules():
    nan = np.array([1.0, np.nan])
    assert same_value(nan, nan.copy()) and same_value(float("nan"), float("nan"))
    assert not same_value(np.array([1, 2]), np.array([1.0, 2.0]))  # dtype differs
    assert not same_value(np.zeros(2), np.zeros((1, 2)))
    assert same_value((1, np.zeros(2)), (1, np.zeros(2)))
    assert not same_value({"a": np.ones(2)}, {"a": np.zeros(2)})
