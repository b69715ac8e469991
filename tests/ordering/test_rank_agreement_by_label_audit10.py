"""rank_agreement of two OrderingResults compares modes, not column positions (audit 10,
feedback, rows ra-same-modes-permuted-basis, ra-kl-vs-zern).

Reference: invariance under a permutation of the basis's columns, and scipy's Spearman
rho / Kendall tau of the modes' ranks computed here from the labels. The same variance
order computed on a Zernike basis and on its reversed copy ranks every mode alike, so
rho = tau = 1 (before: -0.83 and -0.64, the indices compared by position); the orders of
a K-L basis and a Zernike basis rank different modes and are refused (before: rho 0.83).
"""

import numpy as np
import pytest
from scipy import stats

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis
from modalinfo.ordering import order_modes, rank_agreement
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def setup():
    rng = np.random.default_rng(3)
    # 10 modes with distinct variances (1 .. 10 times): the variance order is known
    scale = np.array([3.0, 9.0, 1.0, 7.0, 2.0, 10.0, 5.0, 4.0, 8.0, 6.0])
    log = ModalLog(rng.standard_normal((400, 10)) * scale, rate=1000.0, modes=range(2, 12))
    pupil = Pupil(24)
    zb = ZernikeBasis(pupil, modes=range(2, 12))
    return log, zb, zb.reorder(np.arange(10)[::-1]), KLBasis.from_turbulence(
        pupil, 10, zernike_modes=range(2, 12))


def _label_ranks(result, labels):
    return np.array([list(result.labels).index(s) for s in labels])


def test_same_modes_in_another_column_order_agree(setup):
    log, zb, zbr, _ = setup
    a = order_modes(log, zb, "variance")
    b = order_modes(log, zbr, "variance")
    assert a.labels == b.labels  # the same modes in the same order
    rho, tau = rank_agreement(a, b)
    assert rho == pytest.approx(1.0) and tau == pytest.approx(1.0)


def test_matched_by_label_equals_scipy_on_label_ranks(setup):
    log, zb, zbr, _ = setup
    a = order_modes(log, zb, "variance")
    shuffled = ModalLog(np.asarray(log.coeffs)[::-1].copy(), rate=1000.0, modes=range(2, 12))
    b = order_modes(shuffled.select(time=None), zbr, "standard")
    labels = list(zb.labels)
    ra, rb = _label_ranks(a, labels), _label_ranks(b, labels)
    rho, tau = rank_agreement(a, b)
    assert rho == pytest.approx(stats.spearmanr(ra, rb).statistic, abs=1e-12)
    assert tau == pytest.approx(stats.kendalltau(ra, rb).statistic, abs=1e-12)


def test_orders_of_other_modes_refused(setup):
    log, zb, _, klb = setup
    with pytest.raises(ValueError, match="different bases"):
        rank_agreement(order_modes(log, zb, "variance"), order_modes(log, klb, "variance"))
