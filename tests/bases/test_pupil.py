"""Pupil sampling.

References: the pixel-centre definition (i + 0.5 - N/2) D/N written out by hand, the
aotools ``circle``-free coordinate grid of ``aotools.functions.zernike.zernike_nm``, the
disc area pi N^2 / 4 (pixel count converges to it) and the annulus area.
"""

import copy
import pickle

import numpy as np
import pytest

from modalinfo.bases import Pupil


def test_coordinates_and_axes():
    p = Pupil(8, diameter=2.0)
    step = 2.0 / 8
    assert p.x[0, 0] == pytest.approx(-1 + step / 2)
    assert p.x[0, 7] == pytest.approx(1 - step / 2)
    # x along columns (axis 1), y along rows (axis 0)
    np.testing.assert_array_equal(p.x[0], p.x[5])
    np.testing.assert_array_equal(p.y[:, 0], p.y[:, 3])
    np.testing.assert_allclose(p.y[:, 0], p.x[0])
    np.testing.assert_allclose(p.rho, np.hypot(p.x, p.y) / 1.0)
    np.testing.assert_allclose(p.theta, np.arctan2(p.y, p.x))
    assert p.pixel_area == pytest.approx(step**2)
    # theta = +pi/2 on the +y axis (row index increasing)
    assert p.theta[7, 3] > 0 and p.theta[0, 3] < 0


@pytest.mark.parametrize("n", [64, 255, 256])
def test_mask_area(n):
    p = Pupil(n)
    # pixel count of a digitised disc: pi N^2 / 4 within a perimeter's worth (~ pi N / 2)
    assert abs(p.n_valid - np.pi * n**2 / 4) < np.pi * n / 2
    assert p.mask[n // 2, n // 2]
    assert not p.mask[0, 0]
    np.testing.assert_array_equal(p.mask, p.mask[::-1, :])
    np.testing.assert_array_equal(p.mask, p.mask.T)


def test_annular_mask_and_valid_vectors():
    p = Pupil(200, diameter=4.0, obscuration=0.3)
    area = np.pi * (1 - 0.3**2) * 100**2
    assert abs(p.n_valid - area) < np.pi * 200 * 1.3 / 2
    assert not p.mask[100, 100]
    assert np.all(p.rho_valid >= 0.3) and np.all(p.rho_valid <= 1)
    np.testing.assert_array_equal(p.rho_valid, p.rho[p.mask])
    np.testing.assert_array_equal(p.theta_valid, p.theta[p.mask])
    assert p.rho_valid.shape == (p.n_valid,)


def test_matches_aotools_grid():
    # aotools.functions.zernike.zernike_nm uses the same centred pixel grid
    n = 64
    coords = (np.arange(n) - n / 2.0 + 0.5) / (n / 2.0)
    gx, gy = np.meshgrid(coords, coords)
    p = Pupil(n, diameter=2.0)
    np.testing.assert_allclose(p.x, gx, atol=1e-15)
    np.testing.assert_allclose(p.y, gy, atol=1e-15)


def test_to_image_round_trip():
    p = Pupil(32)
    v = np.arange(p.n_valid, dtype=float)
    img = p.to_image(v)
    assert img.shape == (32, 32)
    assert np.all(np.isnan(img[~p.mask]))
    np.testing.assert_array_equal(img[p.mask], v)
    stack = p.to_image(np.stack([v, 2 * v]))
    assert stack.shape == (2, 32, 32)
    np.testing.assert_array_equal(stack[1][p.mask], 2 * v)
    with pytest.raises(ValueError, match=r"`values` must have last axis of length n_valid="):
        p.to_image(np.zeros(p.n_valid + 1))


def test_immutable_and_equality():
    p = Pupil(16)
    with pytest.raises(AttributeError):
        p.n_pixels = 3
    with pytest.raises(ValueError):
        p.mask[0, 0] = True
    assert p == Pupil(16) and p != Pupil(16, obscuration=0.1)
    q = pickle.loads(pickle.dumps(Pupil(16, 2.0, 0.2)))
    assert q == Pupil(16, 2.0, 0.2)
    np.testing.assert_array_equal(q.mask, Pupil(16, 2.0, 0.2).mask)
    assert copy.deepcopy(p) == p


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"n_pixels": 4}, ValueError, r"`n_pixels` must be an int >= 8; got 4"),
        ({"n_pixels": 16.0}, TypeError, r"`n_pixels` must be an int"),
        ({"n_pixels": 16, "diameter": 0.0}, ValueError, r"`diameter` must be > 0.0"),
        ({"n_pixels": 16, "diameter": np.inf}, ValueError, r"`diameter` must be finite"),
        ({"n_pixels": 16, "obscuration": 1.0}, ValueError, r"`obscuration` must be < 1.0"),
        ({"n_pixels": 16, "obscuration": -0.1}, ValueError, r"`obscuration` must be >= 0.0"),
    ],
)
def test_bad_inputs(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        Pupil(**kwargs)


def test_a_grid_beyond_the_free_memory_is_refused_before_allocating(monkeypatch):
    # adversarial round 4, a31: Pupil(10**6) raised numpy's MemoryError (7.3 TiB grid)
    import modalinfo.bases.pupil as pupil_module

    monkeypatch.setattr(pupil_module, "free_memory_bytes", lambda: 6 * 8 * 64 * 64 - 1.0)
    with pytest.raises(ValueError, match=r"`n_pixels` = 64 needs about .* GiB"):
        Pupil(64)
    monkeypatch.setattr(pupil_module, "free_memory_bytes", lambda: 6 * 8 * 64 * 64 + 1.0)
    assert Pupil(64).n_pixels == 64


def test_an_annulus_without_pixels_and_absurd_diameters_are_refused():
    # audit 9, centre: Pupil(8, obscuration=0.99) had 0 valid pixels (ZernikeBasis gave a
    # (0, M) matrix) and diameter=1e300 raised OverflowError. Reference: the pixel-centre
    # radii (i + 0.5 - N/2) / (N/2) written out by hand: on 8 pixels the centres nearest
    # the rim are at sqrt(3.5^2 + 1.5^2) / 4 = 0.952 of the radius (8 of them), the next
    # beyond it, so an obscuration of 0.95 keeps 8 pixels and 0.99 none
    radii = np.hypot(*np.meshgrid(np.arange(8) - 3.5, np.arange(8) - 3.5)) / 4.0
    assert Pupil(8, obscuration=0.95).n_valid == int(np.sum((radii >= 0.95) & (radii <= 1)))
    assert not np.any((radii >= 0.99) & (radii <= 1))
    with pytest.raises(ValueError, match=r"`obscuration` 0.99 leaves no pixel of the 8 x 8"):
        Pupil(8, obscuration=0.99)
    for d in (1e-300, 1e300):
        with pytest.raises(ValueError, match=r"`diameter` must be in metres within 1e-06 - "
                                             r"1e\+06"):
            Pupil(16, diameter=d)
def test_diameter_beyond_any_telescope_is_refused():
    """Audit 9: diameter=1e300 overflowed the pixel area (OverflowError); the bound,
    10^6 m, is 10^4 x the 39 m ELT (a diameter in um or nm typed as m)."""
    with pytest.raises(ValueError, match=r"`diameter` must be in metres within .*; got 1e"):
        Pupil(16, diameter=1e300)
    assert Pupil(16, diameter=39.0).pixel_area == pytest.approx((39.0 / 16) ** 2)
