"""A log of labelled columns (convention "labels") in the orderings and fitting errors.

Round 21 PART a (issue 27), rows l22, l23, l30, l31. Reference: numpy on the same
coefficients, taken column by column by label (the mean square of each named column for
the variance order; ``mean_t r_t^T G r_t`` with the basis's pixel Gram matrix
``G = Z^T Z / n_valid`` for dPhi(0)), and the array road (``log.coeffs`` permuted into
the basis's order with numpy, which the docs define as the basis's own coefficients).
Before the fix a labelled log's columns were taken in order whatever their labels.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import KLBasis, ModalBasis, Pupil, ZernikeBasis
from modalinfo.ordering import fitting_error, order_modes
from modalinfo.telemetry import ModalLog

# these coarse pupils serve other checks; fitting_error's note on them
# (PupilSamplingWarning) is tested in tests/ordering/test_fixes33a.py
pytestmark = pytest.mark.filterwarnings(
    "ignore::modalinfo.ordering.fitting_error.PupilSamplingWarning")


@pytest.fixture(scope="module")
def setup():
    pupil = Pupil(24)
    matrix = ZernikeBasis(pupil, [2, 3, 4], orthonormalize=True).matrix
    basis = ModalBasis(matrix, pupil, labels=["KL1", "KL2", "KL3"])
    rng = np.random.default_rng(21)
    a = rng.normal(size=(2000, 3)) * np.array([3.0, 2.0, 1.0])  # KL1 > KL2 > KL3
    return pupil, basis, a


def test_permuted_labels_are_matched_by_name(setup):
    _, basis, a = setup
    log = ModalLog(a[:, [2, 0, 1]], rate=1000.0, modes=["KL3", "KL1", "KL2"],
                   convention="labels")
    expected = [["KL1", "KL2", "KL3"][i] for i in np.argsort(-np.mean(a**2, axis=0))]
    assert list(order_modes(log, basis, "variance").labels) == expected
    gram = basis.matrix.T @ basis.matrix / basis.matrix.shape[0]
    total = float(np.mean(np.einsum("ti,ij,tj->t", a, gram, a)))
    result = fitting_error(log, basis)
    assert result.mean_total == pytest.approx(total, rel=1e-12)
    np.testing.assert_allclose(result.curve(), fitting_error(a, basis).curve(), rtol=1e-12)


def test_unrelated_labels_are_refused_naming_them(setup):
    _, basis, a = setup
    log = ModalLog(a, rate=1000.0, modes=["x", "y", "z"], convention="labels")
    with pytest.raises(ValueError, match=r"labelled \['x', 'y', 'z'\].*lacks KL1, KL2, KL3"):
        order_modes(log, basis, "variance")


def test_extra_labelled_column_is_refused_by_fitting_error(setup):
    _, basis, a = setup
    log = ModalLog(np.c_[a, a[:, 0]], rate=1000.0, modes=["KL1", "KL2", "KL3", "KL9"],
                   convention="labels")
    with pytest.raises(ValueError, match=r"1 mode\(s\) the basis does not represent \(KL9\)"):
        fitting_error(log, basis)


def test_kl_subset_log_with_its_kl_basis(setup):
    pupil, _, _ = setup
    rng = np.random.default_rng(5)
    z = rng.normal(size=(1500, 9)) * np.linspace(2.0, 0.5, 9)
    kl = KLBasis.from_data(ZernikeBasis(pupil, range(2, 11)), z)
    c = kl.coefficients_from_zernike(z)
    keep = [0, 2, 4, 7]
    sub = kl.reorder(keep)
    log = ModalLog(c[:, keep[::-1]], rate=1000.0, modes=[f"KL{k + 1}" for k in keep[::-1]],
                   convention="labels")
    assert list(order_modes(log, sub, "variance").labels) == ["KL1", "KL3", "KL5", "KL8"]
    np.testing.assert_allclose(fitting_error(log, sub).curve(),
                               fitting_error(c[:, keep], sub).curve(), rtol=1e-12)
