"""Identification of mode images as our Zernikes, and bases built from mode images.

References (outside the project): the NAOMI control modes shipped by ``aotpy``
(``aotpy/data/NAOMI/zernike_control_modes.fits``, documented by aotpy's NAOMI
translator as "Zernike modes 2 to 15" on a 256-pixel pupil), ``aotools.zernikeArray``
and ``hcipy.make_zernike_basis`` (Noll Zernikes 2-15 of two other libraries); the
exact geometric maps of the grid (transpose, flips) applied with numpy, whose effect
on Zernikes is analytic (x <-> y swaps Z2/Z3 and negates Z6...; x -> -x negates the
modes odd in x).
"""

from __future__ import annotations

import importlib.resources
import warnings

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.bases.identify import TRANSFORMS, ZernikeIdentification, identify_zernike
from modalinfo.bases.image_basis import MaskedPupil, basis_from_images, pupil_from_mask
from modalinfo.bases.indexing import noll_to_zernike


@pytest.fixture(scope="module")
def naomi_modes():
    pytest.importorskip("aotpy")
    from astropy.io import fits

    res = importlib.resources.files("aotpy.data.NAOMI") / "zernike_control_modes.fits"
    with importlib.resources.as_file(res) as path:
        return np.asarray(fits.getdata(path), dtype=np.float64)


def test_naomi_modes_are_z2_to_z15(naomi_modes):
    assert naomi_modes.shape == (14, 256, 256)
    ident = identify_zernike(naomi_modes)
    assert list(ident.noll) == list(range(2, 16))
    assert np.all(ident.correlation > 0.999)
    assert np.all(ident.second < 0.01)  # no other Zernike comes close
    assert ident.is_standard and ident.transform == "none" and ident.order == "noll"
    assert ident.n_pixels == Pupil(256).n_valid  # the support is exactly our 256-px disc


def test_naomi_basis_on_its_pupil(naomi_modes):
    basis = basis_from_images(naomi_modes, diameter=1.82)
    assert type(basis.pupil) is Pupil and basis.pupil == Pupil(256, diameter=1.82)
    ours = ZernikeBasis(Pupil(256, diameter=1.82), modes=range(2, 16))
    # same modes to the pixelation of the file (max deviation measured: ~3e-3 RMS)
    rms = np.sqrt(np.mean((basis.matrix - ours.matrix) ** 2, axis=0))
    assert np.all(rms < 0.05)
    assert np.array_equal(basis.matrix, naomi_modes[:, basis.pupil.mask].T)


@pytest.mark.parametrize(
    ("name", "noll", "sign"),
    [
        # x <-> y: Z2 <-> Z3, Z7 <-> Z8, Z9 <-> Z10 (with sign), cos 2theta negated ...
        ("transpose", [3, 2, 4, 5, 6, 8, 7, 10, 9, 11, 12, 13, 14, 15],
         [1, 1, 1, 1, -1, 1, 1, -1, -1, 1, -1, 1, 1, -1]),
        # x -> -x: the modes odd in x change sign (Z2, Z5, Z8, Z10, Z13, Z15 ...)
        ("flip-x", list(range(2, 16)), None),
    ],
)
def test_axis_changes_are_found(naomi_modes, name, noll, sign):
    moved = np.ascontiguousarray(TRANSFORMS[name](naomi_modes))
    ident = identify_zernike(moved)
    assert list(ident.noll) == noll
    if sign is None:  # flip-x: analytic parity of each mode in x
        n, m = noll_to_zernike(np.arange(2, 16))
        odd_in_x = ((m > 0) & (np.abs(m) % 2 == 1)) | ((m < 0) & (np.abs(m) % 2 == 0))
        sign = np.where(odd_in_x, -1, 1)
    assert list(ident.sign) == list(sign)
    assert not ident.is_standard
    assert ident.transform == name  # the map back to our axes is itself (an involution)
    assert list(ident.noll_after_transform) == list(range(2, 16))
    assert name in ident.summary()


def test_negated_modes_have_no_symmetry_fix(naomi_modes):
    ident = identify_zernike(-naomi_modes[:5])
    assert list(ident.noll) == [2, 3, 4, 5, 6] and np.all(ident.sign == -1)
    assert ident.transform is None  # defocus cannot be made positive by a grid symmetry
    assert "5 with opposite sign" in ident.summary()


def test_other_libraries_zernikes_match_ours():
    aotools = pytest.importorskip("aotools")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        z = aotools.zernikeArray(15, 64)[1:]  # Noll 2..15
    ident = identify_zernike(z)
    assert ident.is_standard and list(ident.noll) == list(range(2, 16))
    hcipy = pytest.importorskip("hcipy")
    grid = hcipy.make_pupil_grid(64, 1.0)
    modes = np.array([m.shaped for m in hcipy.make_zernike_basis(14, 1.0, grid, 2)])
    ident = identify_zernike(modes, mask=Pupil(64).mask)
    assert ident.is_standard and list(ident.noll) == list(range(2, 16))
    assert np.all(ident.correlation > 0.99)


def test_random_images_are_not_zernikes():
    rng = np.random.default_rng(0)
    imgs = rng.standard_normal((4, 32, 32)) * Pupil(32).mask
    ident = identify_zernike(imgs)
    assert not ident.is_zernike.any() and not ident.all_zernike
    assert ident.transform is None
    assert "no mode matches" in ident.summary()


def test_to_dict_round_trip(naomi_modes):
    ident = identify_zernike(naomi_modes[:3])
    back = ZernikeIdentification.from_dict(ident.to_dict())
    assert back.table() == ident.table().replace(
        f"{ident.correlation[0]:>8.4f}", f"{back.correlation[0]:>8.4f}")
    assert list(back.noll) == list(ident.noll) and back.transform == ident.transform


def test_annulus_and_arbitrary_masks():
    annulus = Pupil(40, diameter=2.0, obscuration=0.3)
    # an annulus is recognised (its obscuration only up to the pixel radii: same mask)
    found = pupil_from_mask(annulus.mask, 2.0)
    assert type(found) is Pupil and np.array_equal(found.mask, annulus.mask)
    assert found.obscuration == pytest.approx(0.3, abs=1 / 20)
    # padded into a larger frame: cropped back to the same pupil
    frame = np.zeros((50, 60), dtype=bool)
    frame[5:45, 12:52] = annulus.mask
    assert pupil_from_mask(frame, 2.0) == found
    spider = annulus.mask.copy()
    spider[:, 19:21] = False
    masked = pupil_from_mask(spider, 2.0)
    assert isinstance(masked, MaskedPupil) and masked.n_valid == int(spider.sum())
    zb = ZernikeBasis(annulus, modes=range(2, 7))
    images = annulus.to_image(zb.matrix.T)  # NaN outside
    images[:, ~spider] = 0.0
    basis = basis_from_images(images, diameter=2.0)
    assert basis.pupil == masked
    assert np.array_equal(basis.matrix, zb.matrix[spider[annulus.mask]])
    import pickle

    assert pickle.loads(pickle.dumps(masked)) == masked


def test_bad_input_is_named():
    with pytest.raises(ValueError, match=r"`images` must be mode images \(M, h, w\)"):
        identify_zernike(np.zeros((4, 4)))
    with pytest.raises(ValueError, match="no pupil"):
        identify_zernike(np.zeros((2, 8, 8)))
    with pytest.raises(ValueError, match="`threshold`"):
        identify_zernike(np.ones((1, 8, 8)), threshold=0.0)
    with pytest.raises(ValueError, match="`mask` must have the images' shape"):
        basis_from_images(np.ones((1, 8, 8)), mask=np.ones((4, 4), dtype=bool))


def test_a_mask_of_zeros_and_ones_is_a_mask_and_nothing_else_is():
    """Audit 9: ``np.asarray(mask, bool)`` made every nonzero value, string or object
    True: a float image with 0.5 at the edge or the strings '0' became a full square.
    Reference: the bool mask of the same pupil."""
    pupil = Pupil(16)
    assert np.array_equal(pupil_from_mask(pupil.mask.astype(np.uint8)).mask, pupil.mask)
    with pytest.raises(ValueError, match="`mask` must be boolean"):
        pupil_from_mask(np.where(pupil.mask, 1.0, 0.5))
    with pytest.raises(TypeError, match="`mask` must be a numeric array"):
        pupil_from_mask(pupil.mask.astype(int).astype(str))
