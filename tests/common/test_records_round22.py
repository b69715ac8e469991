"""Round 22 PART a: results holding arrays refuse hash() naming themselves.

Reference: the Python data model (an object whose ``==`` compares mutable contents is
unhashable, and ``hash`` raises ``TypeError: unhashable type: '<its class>'``, as for a
list). Before the fix the message named ``numpy.ndarray``, not the result.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from modalinfo.information import (
    mutual_information_ci,
    mutual_information_permutation_test,
    transfer_entropy_map,
)


def test_hash_of_a_result_names_the_result_and_its_array_field():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(200)
    res = mutual_information_permutation_test(x, x + rng.standard_normal(200),
                                              n_permutations=19)
    with pytest.raises(TypeError, match=r"unhashable type: 'MIPermutationResult' "
                                        r"\(its field 'null_distribution'"):
        hash(res)


def test_replace_with_a_junk_statistic_or_mismatched_labels_is_refused():
    rng = np.random.default_rng(1)
    x = rng.standard_normal(300)
    res = mutual_information_permutation_test(x, x + rng.standard_normal(300),
                                              n_permutations=19)
    assert dataclasses.replace(res) == res
    with pytest.raises(ValueError, match=r"MIPermutationResult: `statistic` must be a real"):
        dataclasses.replace(res, statistic=())
    ci = mutual_information_ci(x, x + rng.standard_normal(300), n_resamples=49)
    with pytest.raises(ValueError, match=r"MIConfidenceResult: `estimate` must be a real"):
        dataclasses.replace(ci, estimate="0.3")
    te = transfer_entropy_map(rng.standard_normal((400, 3)), lags=[1], n_surrogates=19)
    assert dataclasses.replace(te) == te
    with pytest.raises(ValueError, match=r"TransferEntropyMap: `group` has shape \(3,\); "
                                         r"the other fields need \(2,\)"):
        dataclasses.replace(te, labels=te.labels[:2])
