"""A labelled log's extra column the basis lacks (review19, planted bug LB1).

Reference: numpy on the same coefficients. A labelled column the basis does not
represent is refused by ``fitting_error`` as soon as it holds one non-zero value (its
power would be lost from dPhi(0)), and an all-zero one is harmless: the curve equals
the array road (``log.coeffs`` of the basis's columns). The round 21 test's extra
column was non-zero in every frame, so "refuse if all values are non-zero" passed it.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import ModalBasis, Pupil, ZernikeBasis
from modalinfo.ordering import fitting_error
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def setup():
    pupil = Pupil(24)
    matrix = ZernikeBasis(pupil, [2, 3, 4], orthonormalize=True).matrix
    basis = ModalBasis(matrix, pupil, labels=["KL1", "KL2", "KL3"])
    a = np.random.default_rng(19).normal(size=(1000, 3)) * np.array([3.0, 2.0, 1.0])
    return basis, a


def _log(a, extra):
    return ModalLog(np.c_[a, extra], rate=1000.0, modes=["KL1", "KL2", "KL3", "KL9"],
                    convention="labels")


def test_extra_column_zero_in_some_frames_is_refused(setup):
    basis, a = setup
    sparse = a[:, 0] * (np.arange(a.shape[0]) % 2)  # non-zero on odd frames only
    assert np.any(sparse != 0) and not np.all(sparse != 0)
    with pytest.raises(ValueError, match=r"1 mode\(s\) the basis does not represent \(KL9\)"):
        fitting_error(_log(a, sparse), basis)


def test_all_zero_extra_column_is_accepted(setup):
    basis, a = setup
    result = fitting_error(_log(a, np.zeros(a.shape[0])), basis)
    np.testing.assert_allclose(result.curve(), fitting_error(a, basis).curve(), rtol=1e-12)
