"""A K-L basis keeping fewer modes than the Zernikes it combines is refused at every count.

Reference (outside the code): Parseval on an orthonormal basis: the fitting error after
n modes is the mean of the squared coefficients beyond n, so dPhi(0) is the log's mean
squared sum (NumPy by hand) and a basis spanning all 6 Zernike dimensions reaches
dPhi(6) = 0 only because nothing is left; one keeping k < 6 of them would report
dPhi(k) = 0 with the variance of 6 - k dimensions missing.

Planted bug R8-38 (docs/MUTATION.md, round 8): the rule off by one (``n_modes <
len(kept) - 1``) let a K-L basis of 5 of 6 dimensions through; the test before kept 3.
"""
from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis
from modalinfo.ordering import fitting_error
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def case():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((300, 6)) @ rng.standard_normal((6, 6))
    log = ModalLog(a, rate=1e3, modes=list(range(2, 8)))
    return a, log, ZernikeBasis(Pupil(32), range(2, 8), orthonormalize=True)


@pytest.mark.parametrize("kept", [1, 4, 5])
def test_a_kl_basis_short_of_its_zernikes_is_refused(case, kept):
    a, log, zb6 = case
    with pytest.raises(ValueError, match=rf"keeps {kept} K-L modes of the 6 Zernike modes"):
        fitting_error(log, KLBasis.from_data(zb6, a, n_modes=kept))


def test_the_full_kl_basis_is_parseval(case):
    a, log, zb6 = case
    curve = fitting_error(log, KLBasis.from_data(zb6, a, n_modes=6)).curve(include_zero=True)
    assert curve[0] == pytest.approx(np.mean(np.sum(a**2, axis=1)), rel=1e-12)
    assert abs(curve[-1]) <= 1e-12 * curve[0]
