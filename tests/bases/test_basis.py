"""ModalBasis operations.

References: numpy.linalg.lstsq (least-squares projection), the orthonormal-basis identity
project(phase) = matrix.T @ phase / n_valid, and exact round trips synthesize/project.
"""

import numpy as np
import pytest

from modalinfo.bases import ModalBasis, Pupil, ZernikeBasis


@pytest.fixture(scope="module")
def pupil():
    return Pupil(48)


def test_project_is_least_squares(pupil):
    rng = np.random.default_rng(3)
    basis = ModalBasis(rng.normal(size=(pupil.n_valid, 7)), pupil)
    phase = rng.normal(size=(5, pupil.n_valid))
    expected = np.linalg.lstsq(basis.matrix, phase.T, rcond=None)[0].T
    np.testing.assert_allclose(basis.project(phase), expected, atol=1e-12)
    np.testing.assert_allclose(basis.project(phase[0]), expected[0], atol=1e-12)
    assert basis.labels == [f"mode{k}" for k in range(1, 8)]


def test_orthonormal_projection_equals_inner_product(pupil):
    zb = ZernikeBasis(pupil, 21, orthonormalize=True)
    phase = np.random.default_rng(0).normal(size=(4, pupil.n_valid))
    np.testing.assert_allclose(zb.project(phase), phase @ zb.matrix / pupil.n_valid,
                               atol=1e-12)


def test_synthesize_project_round_trip(pupil):
    zb = ZernikeBasis(pupil, range(2, 29))
    coeffs = np.random.default_rng(1).normal(size=(6, 27))
    phase = zb.synthesize(coeffs)
    assert phase.shape == (6, pupil.n_valid)
    np.testing.assert_allclose(phase, coeffs @ zb.matrix.T)
    np.testing.assert_allclose(zb.project(phase), coeffs, atol=1e-11)
    assert zb.synthesize(coeffs[0]).shape == (pupil.n_valid,)


def test_rank_deficient_falls_back_to_minimum_norm(pupil):
    zb = ZernikeBasis(pupil, 6)
    m = np.column_stack([zb.matrix, zb.matrix[:, 1]])  # duplicated tip
    basis = ModalBasis(m, pupil)
    phase = zb.matrix[:, 1] * 2.0
    expected = np.linalg.lstsq(m, phase, rcond=None)[0]
    np.testing.assert_allclose(basis.project(phase), expected, atol=1e-9)


def test_reorder_and_gram(pupil):
    zb = ZernikeBasis(pupil, range(2, 12))
    order = [3, 0, 9, 1, 2, 4, 5, 6, 7, 8]
    r = zb.reorder(order)
    assert type(r) is ZernikeBasis
    np.testing.assert_array_equal(r.matrix, zb.matrix[:, order])
    assert r.labels == [zb.labels[k] for k in order]
    np.testing.assert_allclose(r.gram(), zb.gram()[np.ix_(order, order)])
    phase = zb.synthesize(np.arange(10.0))
    np.testing.assert_allclose(r.project(phase), np.arange(10.0)[order], atol=1e-10)
    assert zb.labels[0] == "Z2"  # original untouched
    with pytest.raises(ValueError, match=r"`order` must not repeat a column index"):
        zb.reorder([0, 0])
    with pytest.raises(ValueError, match=r"`order` entries must be in \[0, 9\]; got min 0, max 10"):
        zb.reorder([0, 10])
    with pytest.raises(TypeError, match="`order` must hold integer column indices"):
        zb.reorder([0.0, 1.0])


def test_matrix_read_only(pupil):
    zb = ZernikeBasis(pupil, 4)
    with pytest.raises(ValueError):
        zb.matrix[0, 0] = 1.0


def test_bad_inputs(pupil):
    zb = ZernikeBasis(pupil, 5)
    with pytest.raises(ValueError, match=r"`coeffs` must have last axis of length n_modes=5"):
        zb.synthesize(np.zeros(4))
    with pytest.raises(ValueError, match=r"`coeffs` must be finite; got 1 NaN"):
        zb.synthesize([0.0, np.nan, 0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"`coeffs` must be 1-D or 2-D"):
        zb.synthesize(np.zeros((2, 2, 5)))
    other = Pupil(40)
    with pytest.raises(ValueError, match=rf"`phase` must have last axis of length n_valid="
                       rf"{pupil.n_valid}.*got shape \({other.n_valid},\)"):
        zb.project(np.zeros(other.n_valid))
    with pytest.raises(ValueError, match=r"`phase` must be finite"):
        zb.project(np.full(pupil.n_valid, np.inf))
    with pytest.raises(ValueError, match=r"`matrix` must have n_valid=\d+ rows"):
        ModalBasis(np.zeros((10, 2)), pupil)
    with pytest.raises(ValueError, match=r"`labels` must have one entry per column \(2\); got 1"):
        ModalBasis(np.zeros((pupil.n_valid, 2)), pupil, ["a"])
    with pytest.raises(TypeError, match=r"`labels` must be a sequence of str"):
        ModalBasis(np.zeros((pupil.n_valid, 2)), pupil, "ab")
    with pytest.raises(TypeError, match=r"`pupil` must be a modalinfo.bases.Pupil"):
        ModalBasis(np.zeros((10, 2)), None)
    with pytest.raises(ValueError, match=r"`matrix` must be finite"):
        ModalBasis(np.full((pupil.n_valid, 1), np.nan), pupil)
