"""The geometric Shack-Hartmann slope: the centred mean gradient over each subaperture.

References, computed in the test and independent of the WFS's sparse operators:
- analytic: the mean of the gradient of ``a x^2 + b x y + c y^2 + d x + e y`` over a
  square centred on ``(x_c, y_c)`` is its gradient at the centre, ``(2 a x_c + b y_c + d,
  b x_c + 2 c y_c + e)``; for a plane, its coefficients. On a grid the x-slope is the
  mean x-derivative of the phase taken linear in x between pixel centres and constant
  across each pixel row (and the same with x and y exchanged), which equals these for a
  plane always, and for a quadratic where the subaperture's edges sit symmetrically on
  the pixel grid (edges on pixel centres or half-way between them);
- a direct numerical integral (fundamental theorem of calculus and scipy.integrate.quad):
  the mean over ``[x0, x1] x [y0, y1]`` of that x-derivative is
  ``(1 / (px py)) int_{y0}^{y1} (phi(x1, y) - phi(x0, y)) dy``, ``phi(x, y)`` numpy's
  linear interpolation along x of the pixel row nearest to y, for any phase, on any
  grid alignment (and the same with x and y exchanged).
Tolerance 1e-12 of the largest slope: float rounding only (sums of a few hundred terms).
"""

import numpy as np
import pytest
from scipy.integrate import quad

from closedloop.simulation import LoopModel

from .test_physics import _single


def _sensor(n_pixels, n_sub):
    cfg = _single(n_pixels=n_pixels, n_sub=n_sub, wfs_kind="shack_hartmann", n_modes=9)
    model = LoopModel(cfg)
    assert len(model.geometry.planes) == 1  # ground layer, ground DM, ground WFS
    return model.geometry, model.wfss[0]


def _subapertures(geometry, wfs):
    """Edges ``(x0, x1, y0, y1)`` [m] of each valid subaperture, and which are fully lit.

    Fully lit: the square grown by one pixel (the support of its pixel-pair weights)
    lies inside the pupil disc, so every pair the window uses carries light.
    """
    n_sub = geometry.config.wfss[0].n_subapertures
    d = geometry.diameter  # a ground WFS senses the pupil itself
    pitch = d / n_sub
    assert wfs.pitch == pytest.approx(pitch)
    rows, cols = np.divmod(wfs.valid_subapertures, n_sub)
    x0 = -d / 2 + cols * pitch
    y0 = -d / 2 + rows * pitch
    edges = np.column_stack([x0, x0 + pitch, y0, y0 + pitch])
    dx = geometry.dx
    corner = np.maximum(np.abs(x0 - dx), np.abs(x0 + pitch + dx)) ** 2 + np.maximum(
        np.abs(y0 - dx), np.abs(y0 + pitch + dx)) ** 2
    full = corner <= (d / 2) ** 2
    return edges, full


def _slopes(geometry, wfs, f):
    coords = geometry.plane_coords(0)
    yy, xx = np.meshgrid(coords, coords, indexing="ij")
    phase = f(xx, yy)
    s = wfs.forward([phase])
    n = wfs.n_valid_subapertures
    return phase, s[:n], s[n:]


@pytest.mark.parametrize("n_pixels,n_sub", [(32, 8), (32, 7), (35, 7), (30, 4)])
def test_plane_gives_its_gradient_in_every_subaperture(n_pixels, n_sub):
    # a plane's interpolant is the plane: every pixel pair measures its gradient exactly,
    # so even partly lit subapertures do
    geometry, wfs = _sensor(n_pixels, n_sub)
    _, sx, sy = _slopes(geometry, wfs, lambda x, y: 1.7 * x - 0.6 * y + 3.0)
    np.testing.assert_allclose(sx, 1.7, rtol=0, atol=1e-12 * 1.7)
    np.testing.assert_allclose(sy, -0.6, rtol=0, atol=1e-12 * 1.7)


@pytest.mark.parametrize("n_pixels,n_sub", [(32, 8), (35, 7), (30, 5), (30, 6)])
def test_quadratic_gives_the_gradient_at_the_subaperture_centre(n_pixels, n_sub):
    # edges symmetric on the grid: 32/8 and 30/6 put them half-way between pixel
    # centres, 35/7 and 30/5 too (odd and even pitch in pixels); the old window (pairs
    # on an edge all in the right-hand subaperture) was off by a x dx here
    a, b, c, d, e = 0.9, -1.3, 0.4, 0.7, -0.2
    geometry, wfs = _sensor(n_pixels, n_sub)
    _, sx, sy = _slopes(geometry, wfs,
                        lambda x, y: a * x**2 + b * x * y + c * y**2 + d * x + e * y)
    edges, full = _subapertures(geometry, wfs)
    assert full.sum() >= 4
    xc = 0.5 * (edges[:, 0] + edges[:, 1])
    yc = 0.5 * (edges[:, 2] + edges[:, 3])
    ex = 2 * a * xc + b * yc + d
    ey = b * xc + 2 * c * yc + e
    scale = np.max(np.abs(np.concatenate([ex, ey])))
    np.testing.assert_allclose(sx[full], ex[full], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(sy[full], ey[full], rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("n_pixels,n_sub", [(32, 8), (32, 7), (35, 6)])
def test_random_phase_against_the_integral_of_the_interpolant(n_pixels, n_sub):
    # any phase, any alignment (32/7 and 35/6: edges at arbitrary fractions of a pixel)
    geometry, wfs = _sensor(n_pixels, n_sub)
    rng = np.random.default_rng(5)
    coords = geometry.plane_coords(0)
    table = rng.standard_normal((coords.size, coords.size))
    phase, sx, sy = _slopes(geometry, wfs, lambda x, y: table)
    dx = geometry.dx
    edges, full = _subapertures(geometry, wfs)
    assert full.sum() >= 4

    def line_mean(fixed, lo, hi, along_y):
        # integral over [lo, hi] of the phase on the line x = fixed (along_y) or
        # y = fixed: linear between pixel centres along the line's normal, the nearest
        # pixel along the line (piecewise constant: breakpoints at the pixel edges)
        pts = coords[:-1] + dx / 2
        pts = pts[(pts > lo) & (pts < hi)]

        def f(t):
            k = int(np.argmin(np.abs(coords - t)))
            line = phase[k, :] if along_y else phase[:, k]
            return float(np.interp(fixed, coords, line))

        return quad(f, lo, hi, points=pts, limit=200, epsabs=1e-14, epsrel=1e-14)[0]

    for k in np.flatnonzero(full):
        x0, x1, y0, y1 = edges[k]
        area = (x1 - x0) * (y1 - y0)
        ref_x = (line_mean(x1, y0, y1, True) - line_mean(x0, y0, y1, True)) / area
        ref_y = (line_mean(y1, x0, x1, False) - line_mean(y0, x0, x1, False)) / area
        scale = np.max(np.abs(np.concatenate([sx, sy])))
        assert abs(sx[k] - ref_x) <= 1e-12 * scale
        assert abs(sy[k] - ref_y) <= 1e-12 * scale
