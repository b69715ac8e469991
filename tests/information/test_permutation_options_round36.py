"""The permutation test refuses ``min_shift`` with shuffles (round 36 PART a, M1).

Reference: the documented meaning of ``min_shift`` (the spacing of the circular shifts,
``mutual_information_permutation_test``'s docstring) and the common brief's contract (no
option silently ignored; an error naming the argument). Before the fix
``permutation="shuffle", min_shift=10`` ran and recorded ``min_shift=0``.
"""

import numpy as np
import pytest

from modalinfo.information import mutual_information_permutation_test


def _pair():
    rng = np.random.default_rng(2)
    x = rng.standard_normal(500)
    return x, 0.6 * x + 0.8 * rng.standard_normal(500)


def test_min_shift_with_shuffle_refused_naming_both():
    x, y = _pair()
    with pytest.raises(ValueError, match="`min_shift`=10.*`permutation`='shuffle'"):
        mutual_information_permutation_test(x, y, permutation="shuffle", min_shift=10,
                                            n_permutations=19, seed=0)


def test_min_shift_with_circular_kept():
    x, y = _pair()
    res = mutual_information_permutation_test(x, y, permutation="circular", min_shift=10,
                                              n_permutations=19, seed=0)
    assert res.min_shift == 10
