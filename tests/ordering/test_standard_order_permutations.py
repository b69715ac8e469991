"""The standard order of a Zernike log stored in any column order is Noll's index order.

Reference (outside the code): Python's ``sorted`` of the column labels by their Noll
index (Z2, Z3, ...; Noll 1976), for every permutation of five columns: the transpositions
and involutions a single test permutation may be, and the 3-, 4- and 5-cycles whose
order (the sorting permutation) differs from its inverse (the ranks).

Planted bug R8-21 (docs/MUTATION.md, round 8): ``BasisView.standard_order`` returning the
ranks of the Noll indices (``argsort(argsort(modes))``) for their order passed
``test_orderings.py``'s one permutation, ``[3, 1, 4, 0, 2]``, an involution (its own
inverse), where ranks and order coincide.
"""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def coeffs():
    # distinct mean squares 4, 1, 0.25, ... so the variance order is the Noll order too
    return np.random.default_rng(8).standard_normal((200, 5)) * [2.0, 1.0, 0.5, 0.25, 0.125]


@pytest.mark.parametrize("method", ["standard", "variance"])
def test_every_column_order_gives_the_noll_order(coeffs, method):
    pupil = Pupil(16)
    for perm in itertools.permutations(range(5)):
        modes = [2 + p for p in perm]
        log = ModalLog(coeffs[:, list(perm)], rate=1e3, modes=modes)
        r = order_modes(log, ZernikeBasis(pupil, modes), method, n_resamples=0)
        expected = sorted((f"Z{m}" for m in modes), key=lambda s: int(s[1:]))
        assert list(r.labels) == expected, perm
