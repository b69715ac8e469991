"""``closedloop.theory``: the Kolmogorov structure function and the shifted-difference law.

References (computed in the test):
- Fried (1966): ``D(r) = 2 [(24/5) Gamma(6/5)]^(5/6) (r / r0)^(5/3)`` = 6.8839 (r/r0)^(5/3),
  the constant from ``math.gamma``;
- the expected piston-removed variance over a sampled pupil P of ``Delta(x) = phi(x) -
  phi(x - s)``, derived here from the covariance of increments: ``E var_P Delta =
  (1 / (2 N^2)) sum_{x, y in P} D_Delta(x - y)`` with ``D_Delta(r) = E[(Delta(x) -
  Delta(y))^2] = 2 D(r) + 2 D(s) - D(r + s) - D(r - s)``, summed directly over every
  pair of pupil pixels (no FFT, no autocorrelation), on pupils that are not symmetric
  (so an x/y or sign mix-up shows);
- two limits: no shift gives 0; a shift much longer than the pupil gives nearly twice
  the piston-removed variance of the phase ``(1 / (2 N^2)) sum D(x - y)`` (two nearly
  independent screens), which is Noll's 1.0324 (D / r0)^(5/3) for a disc.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from closedloop import theory

FRIED = 2.0 * ((24.0 / 5.0) * math.gamma(6.0 / 5.0)) ** (5.0 / 6.0)


def _d(r, r0):
    return FRIED * (np.abs(r) / r0) ** (5.0 / 3.0)


def _direct(mask, dx, shift, r0):
    iy, ix = np.nonzero(mask)
    x, y = ix * dx, iy * dx
    rx = x[:, None] - x[None, :]
    ry = y[:, None] - y[None, :]
    sx, sy = shift
    d_delta = (2.0 * _d(np.hypot(rx, ry), r0) + 2.0 * _d(math.hypot(sx, sy), r0)
               - _d(np.hypot(rx + sx, ry + sy), r0) - _d(np.hypot(rx - sx, ry - sy), r0))
    return float(d_delta.sum()) / (2.0 * x.size ** 2)


def test_structure_function_constant():
    assert theory.KOLMOGOROV_D_CONSTANT == pytest.approx(FRIED, rel=1e-14)
    assert theory.structure_function(0.3, 0.1) == pytest.approx(_d(0.3, 0.1), rel=1e-14)
    assert theory.structure_function(-0.3, 0.1) == pytest.approx(_d(0.3, 0.1), rel=1e-14)


def _masks():
    n = 14
    yy, xx = np.mgrid[0:n, 0:n]
    disc = np.hypot(xx - 6.5, yy - 6.5) <= 6.5
    # an off-centre ellipse cut by a line: no symmetry to hide a mix-up of axes or signs
    odd = (((xx - 7.0) / 6.5) ** 2 + ((yy - 6.0) / 4.5) ** 2 <= 1.0) & (xx + 0.5 * yy > 4)
    return {"disc": disc, "odd": odd}


@pytest.mark.parametrize("name", ["disc", "odd"])
@pytest.mark.parametrize("shift", [(0.05, 0.0), (0.0, 0.13), (0.21, -0.08), (-0.4, 0.9)])
def test_shifted_difference_variance_is_the_pair_sum(name, shift):
    mask = _masks()[name]
    dx, r0 = 0.1, 0.15
    got = theory.shifted_difference_variance(mask, dx, shift, r0)
    assert got == pytest.approx(_direct(mask, dx, shift, r0), rel=1e-9)


def test_limits():
    mask = _masks()["disc"]
    dx, r0 = 0.1, 0.15
    assert theory.shifted_difference_variance(mask, dx, (0.0, 0.0), r0) == pytest.approx(
        0.0, abs=1e-9)
    iy, ix = np.nonzero(mask)
    r = np.hypot(ix[:, None] - ix[None, :], iy[:, None] - iy[None, :]) * dx
    piston_removed = float(_d(r, r0).sum()) / (2.0 * ix.size ** 2)
    # the sampled disc is within a few % of Noll's continuous 1.0324 (D/r0)^(5/3) for the
    # disc of the same area (the pixel count)
    diameter = math.sqrt(4.0 * ix.size / math.pi) * dx
    assert piston_removed == pytest.approx(1.0324 * (diameter / r0) ** (5 / 3), rel=0.05)
    # the cross term falls only as (D / s)^(1/3): 0.956 of the limit at s = 2000 D
    far = theory.shifted_difference_variance(mask, dx, (2000.0 * diameter, 0.0), r0)
    assert 0.92 * 2.0 * piston_removed < far < 2.0 * piston_removed


@pytest.mark.parametrize(("mask", "dx", "shift", "match"), [
    # an (8, 16) mask wrapped around its 2 x 8 padding: 0.279 rad^2 where the same pupil
    # on a square grid gives 0.2895 (audit 9); refused, not a number 3.5 % off
    (np.ones((8, 16), bool), 0.1, (0.1, 0.0), r"`mask` must be a square \(N, N\) pupil"),
    (np.zeros((8, 8), bool), 0.1, (0.1, 0.0), r"with at least one pixel; got .* 0 pixels"),
    (np.ones((8, 8), bool), 0.0, (0.1, 0.0), r"`dx` must be > 0"),
    (np.ones((8, 8), bool), 0.1, (0.1, 0.0, 0.2), r"`shift` must have shape \(2\)"),
    (np.ones((8, 8), bool), 0.1, (np.nan, 0.0), r"`shift` must be finite"),
])
def test_shifted_difference_variance_refuses_what_has_no_answer(mask, dx, shift, match):
    with pytest.raises(ValueError, match=match):
        theory.shifted_difference_variance(mask, dx, shift, 0.5)


def test_a_rectangular_pupil_on_a_square_grid_keeps_the_transpose_symmetry():
    # the law is symmetric under x <-> y: the 8 x 16 half of a 16 x 16 grid shifted along
    # x equals the 16 x 8 half shifted along y (and both the pair sum of the first test)
    wide = np.zeros((16, 16), bool)
    wide[:8, :] = True
    a = theory.shifted_difference_variance(wide, 0.1, (0.1, 0.0), 0.5)
    b = theory.shifted_difference_variance(wide.T, 0.1, (0.0, 0.1), 0.5)
    assert a == pytest.approx(b, rel=1e-12)
    assert a == pytest.approx(_direct(wide, 0.1, (0.1, 0.0), 0.5), rel=1e-9)
