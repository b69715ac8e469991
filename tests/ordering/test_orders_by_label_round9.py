"""An OrderingResult follows its modes, not column positions (round 9, rows
fb-ordres-other-basis, fb-ordres-fewer, fb-stab-rank).

Reference: invariance under a permutation of the basis's modes. The same Zernike modes in
reversed column order are the same basis, so the fitting-error curve (and the MI along the
order) of one OrderingResult must be the same numbers on both; before, the result's
indices picked other modes of the reversed basis (dPhi(1) 0.0447 instead of 0.0393 on the
shipped log). An ordering of 10 modes is refused on a
27-mode basis by name, and rank_agreement takes OrderingResults (Spearman rho 1 with
itself, scipy's value for identical ranks).
"""

import numpy as np
import pytest

import modalinfo.io as mio
from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import fitting_error, mi_along_order, order_modes, rank_agreement
from modalinfo.telemetry import ModalLog

# these coarse pupils serve other checks; fitting_error's note on them
# (PupilSamplingWarning) is tested in tests/ordering/test_fixes33a.py
pytestmark = pytest.mark.filterwarnings(
    "ignore::modalinfo.ordering.fitting_error.PupilSamplingWarning")


@pytest.fixture(scope="module")
def setup():
    log = mio.load("data/kaos_like_closed_loop.npz")
    sub = ModalLog(log.coeffs[:1000], rate=log.rate, modes=log.modes)
    pupil = Pupil(32, diameter=0.7)
    return sub, ZernikeBasis(pupil, modes=log.modes), ZernikeBasis(pupil, modes=log.modes[::-1])


def test_standard_order_and_results_match_by_label(setup):
    log, zb, zbr = setup
    r = order_modes(log, zb, "variance")
    assert np.allclose(fitting_error(log, zbr, r).mean, fitting_error(log, zb, r).mean,
                       rtol=1e-12, atol=0)
    a = mi_along_order(log, zb, r, estimator="gaussian", seed=0, sample_budget=5000)
    b = mi_along_order(log, zbr, r, estimator="gaussian", seed=0, sample_budget=5000)
    assert np.allclose(a, b, rtol=1e-9, equal_nan=True)  # the last: the whole MI, infinite


def test_foreign_result_refused_and_rank_agreement_of_results(setup):
    log, zb, _ = setup
    small = ModalLog(log.coeffs[:, :10], rate=log.rate, modes=log.modes[:10])
    r10 = order_modes(small, ZernikeBasis(Pupil(32, diameter=0.7), modes=log.modes[:10]),
                      "variance")
    with pytest.raises(ValueError, match="`order` orders the 10 modes"):
        fitting_error(log, zb, r10)
    r = order_modes(log, zb, "variance")
    assert rank_agreement(r, r) == pytest.approx((1.0, 1.0))
