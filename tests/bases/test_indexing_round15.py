"""Round 15 PART a: an empty list of mode indices is an empty index set, not a float index.

Reference: NumPy's own semantics for an empty selection (``np.zeros((P, 0))``, empty
int64 arrays); an empty list is float64 to ``np.asarray`` although it holds no float.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import noll_to_ansi, noll_to_zernike, zernike_matrix


@pytest.mark.parametrize("empty", [[], (), np.array([])])
def test_empty_modes_give_empty_columns(empty):
    rho, theta = np.full(4, 0.5), np.zeros(4)
    assert zernike_matrix(empty, rho, theta).shape == (4, 0)
    n, m = noll_to_zernike(empty)
    assert n.size == 0 and m.size == 0 and n.dtype == np.int64
    assert noll_to_ansi(empty).size == 0


def test_float_indices_still_refused():
    with pytest.raises(TypeError, match="`modes` must be an int or an integer array"):
        zernike_matrix([2.0, 3.0], np.full(2, 0.5), np.zeros(2))
