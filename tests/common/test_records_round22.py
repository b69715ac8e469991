"""Round 22 PART a: results holding arrays refuse hash() naming themselves.

Reference: the Python data model (an object whose ``==`` compares mutable contents is
unhashable, and ``hash`` raises ``TypeError: unhashable type: '<its class>'``, as for a
list). Before the fix the message named ``numpy.ndarray``, not the result.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import mutual_information_permutation_test


def test_hash_of_a_result_names_the_result_and_its_array_field():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(200)
    res = mutual_information_permutation_test(x, x + rng.standard_normal(200),
                                              n_permutations=19)
    with pytest.raises(TypeError, match=r"unhashable type: 'MIPermutationResult' "
                                        r"\(its field 'null_distribution'"):
        hash(res)
