"""Round 14 PART a: a (1, n) row given to the transfer entropy is named as such.

Reference (outside the code): NumPy's shape convention, rows are samples: a
``numpy.matrix`` row vector of 999 values has shape (1, 999), one sample of 999
columns, and the refusal must say that rather than only "got 1".
"""

import numpy as np
import pytest

from modalinfo.information import transfer_entropy


def test_a_matrix_row_is_refused_naming_its_shape():
    rng = np.random.default_rng(0)
    x, y = rng.standard_normal((2, 1000))
    with pytest.raises(ValueError, match=r"got 1 \(a row of shape \(1, 999\): rows are "
                                         r"samples; pass a 1-D series or shape \(n, 1\)\)"):
        transfer_entropy(np.atleast_2d(x[:-1]), np.atleast_2d(y[1:]))


def test_a_short_column_keeps_the_plain_message():
    with pytest.raises(ValueError, match=r"needs at least 11 samples .* got 5\.$"):
        transfer_entropy(np.arange(5.0), np.arange(5.0) ** 2)
