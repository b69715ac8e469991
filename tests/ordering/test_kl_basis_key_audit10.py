"""An ordering of one K-L basis is refused on another K-L basis with the same labels
(audit 10, feedback, row kl-other-log).

Reference: the K-L modes' definition, the eigenvectors of a covariance, with variances
its eigenvalues (checked here with numpy's ``eigvalsh`` of the two logs' mean-square
matrices: they differ, so the two bases' ``KL1``... are other modes). The data K-L of
two logs, and the theoretical K-L of two outer scales, are all labelled ``KL1``...;
before, an order of one was applied to the other by label. The same theoretical basis
sampled on another pupil is the same modes and is accepted.
"""

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis
from modalinfo.ordering import (
    OrderingResult,
    fitting_error,
    mi_along_order,
    order_modes,
    rank_agreement,
)
from modalinfo.telemetry import ModalLog

# these coarse pupils serve other checks; fitting_error's note on them
# (PupilSamplingWarning) is tested in tests/ordering/test_fixes33a.py
pytestmark = pytest.mark.filterwarnings(
    "ignore::modalinfo.ordering.fitting_error.PupilSamplingWarning")


@pytest.fixture(scope="module")
def setup():
    rng = np.random.default_rng(8)
    a = ModalLog(rng.standard_normal((400, 6)) * [4.0, 3.0, 2.0, 1.5, 1.0, 0.5], rate=1e3)
    b = ModalLog(rng.standard_normal((400, 6)) * [1.0, 2.0, 5.0, 1.0, 3.0, 0.7], rate=1e3)
    zb = ZernikeBasis(Pupil(16), modes=range(2, 8))
    return a, b, KLBasis.from_data(zb, a.coeffs), KLBasis.from_data(zb, b.coeffs)


def test_the_two_data_kl_are_other_modes(setup):
    a, b, ka, kb = setup
    assert ka.labels == kb.labels
    ev = [np.sort(np.linalg.eigvalsh(x.coeffs.T @ x.coeffs / x.n_frames))[::-1]
          for x in (a, b)]
    np.testing.assert_allclose(ka.variances, ev[0], rtol=1e-9)
    assert not np.allclose(ev[0], ev[1], rtol=0.1)


def test_order_of_one_refused_on_the_other(setup, tmp_path):
    a, b, ka, kb = setup
    ra = order_modes(a, ka, "variance")
    path = ra.to_json(tmp_path / "o.json")
    for r in (ra, OrderingResult.from_json(path)):
        with pytest.raises(ValueError, match="another K-L basis"):
            fitting_error(b, kb, r)
        with pytest.raises(ValueError, match="another K-L basis"):
            mi_along_order(b, kb, r, estimator="gaussian", sample_budget=500, seed=0)
        with pytest.raises(ValueError, match="another K-L basis"):
            r.apply(kb)
        with pytest.raises(ValueError, match="two different K-L bases"):
            rank_agreement(r, order_modes(b, kb, "variance"))
    np.testing.assert_array_equal(fitting_error(a, ka, ra).mean,
                                  fitting_error(a, ka, ra.order).mean)
    # the same basis with its columns permuted: the same modes, matched by label
    np.testing.assert_allclose(fitting_error(a, ka.reorder(np.arange(6)[::-1]), ra).mean,
                               fitting_error(a, ka, ra).mean, rtol=1e-12)


def test_theoretical_kl_on_another_pupil_accepted_other_outer_scale_refused(setup):
    a = setup[0]
    modes = range(2, 8)
    r = order_modes(a, KLBasis.from_turbulence(Pupil(16), 6, zernike_modes=modes), "variance")
    fitting_error(a, KLBasis.from_turbulence(Pupil(24), 6, zernike_modes=modes), r)
    with pytest.raises(ValueError, match="another K-L basis"):
        fitting_error(a, KLBasis.from_turbulence(Pupil(16), 6, outer_scale=2.0,
                                                 zernike_modes=modes), r)
