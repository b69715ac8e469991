"""The science path over an obscured (annular) pupil.

References, from outside the simulator:

- analytic: the piston-removed variance of a tilt ``a x`` over an annulus of outer radius
  ``R`` and obscuration ratio ``e`` is ``a**2 R**2 (1 + e**2) / 4`` (the second moment of
  an annulus; it is why Mahajan's annular Zernike Z2 carries ``2 / sqrt(1 + e**2)``,
  Mahajan 1981, J. Opt. Soc. Am. 71, 75);
- the Strehl ratio as the peak of the FFT PSF of the annular pupil, computed here with
  numpy from the phase map (not with the simulator's own ``fft_strehl``), against the
  extended Marechal ``exp(-sigma**2)`` of the camera's variance for a small aberration;
- the annulus's variance computed with numpy from the same phase map.
"""

from __future__ import annotations

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import FieldConfig, TelescopeConfig
from closedloop.optics.geometry import Geometry
from closedloop.optics.science import ScienceCamera


def _camera(obscuration: float, n_pixels: int = 64) -> ScienceCamera:
    base = presets.get("table1")
    cfg = base.replace(telescope=TelescopeConfig(diameter=4.0, obscuration=obscuration,
                                                 n_pixels=n_pixels),
                       field=FieldConfig(size=0.0, n_points=1))
    geometry = Geometry(cfg)
    return ScienceCamera(geometry, geometry.directions)


def _ground_window(cam: ScienceCamera) -> tuple[int, int]:
    """(row, col) of pupil pixel (0, 0) on plane 0 (a whole-pixel copy on axis)."""
    col, row = cam._shifts[0, 0]
    assert col == int(col) and row == int(row)
    return int(row), int(col)


@pytest.mark.parametrize("obscuration", [0.0, 0.3, 0.6])
def test_tilt_variance_over_the_annulus(obscuration):
    cam = _camera(obscuration)
    views = cam.plane_views()
    a = 0.05  # rad per pixel
    n = views[0].shape[1]
    views[0][:] = a * np.arange(n)[None, :]  # tilt along x (columns)
    var = cam.forward()[0]
    radius = cam.geometry.n_pixels / 2.0
    expected = a ** 2 * radius ** 2 * (1.0 + obscuration ** 2) / 4.0
    # pixelisation of a 64-pixel disc: well below 2 %; a disc used in place of the
    # annulus is 9 % (e = 0.3) or 36 % (e = 0.6) off
    assert var == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("obscuration", [0.25, 0.5])
def test_annulus_moments_and_fft_strehl(obscuration):
    cam = _camera(obscuration)
    mask = cam.geometry.pupil_mask
    n = mask.shape[0]
    rng = np.random.default_rng(3)
    views = cam.plane_views()
    views[0][:] = rng.normal(0.0, 0.15, views[0].shape)
    row, col = _ground_window(cam)
    phase = views[0][row:row + n, col:col + n].copy()
    # a large aberration inside the hole only: an unobscured computation would see it
    hole = cam.geometry.disc_and_hole()[1]
    phase[hole] += 30.0 + 5.0 * rng.normal(size=hole.sum())
    views[0][row:row + n, col:col + n] = phase
    # a large piston too (the moments must not lose it to cancellation)
    views[0][:] += 40.0
    phase += 40.0
    var = cam.forward()[0]
    assert var == pytest.approx(np.var(phase[mask]), rel=1e-9)
    assert cam.mean[0] == pytest.approx(np.mean(phase[mask]), rel=1e-12)
    # Strehl of the annular pupil by FFT (padding 4), against exp(-variance)
    big = np.zeros((4 * n, 4 * n), complex)
    big[:n, :n] = np.where(mask, np.exp(1j * phase), 0.0)
    sr_fft = (np.abs(np.fft.fft2(big)) ** 2).max() / mask.sum() ** 2
    # sigma = 0.15 rad: exp(-sigma^2) = 0.978 and the FFT peak agree to ~sigma^4
    assert np.exp(-var) == pytest.approx(sr_fft, abs=2e-3)
