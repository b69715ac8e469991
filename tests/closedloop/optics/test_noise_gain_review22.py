"""The correlating SH's noise table is read at the shifts it was tabulated for (review 22).

Issue 27, review22 (docs/MUTATION.md, "Planted bugs, round 22"). ``_noise_gain`` reads
``CorrelatingShackHartmann.noise_factor``, documented as the variance ratio at the
fractional shift ``((ix, iy) + 1/2) / NOISE_TABLE_STEPS - 1/2`` pixels (row ``iy``,
column ``ix``), interpolated bilinearly and periodically (period one pixel). References
(outside the code under test): that documented grid, and
``scipy.interpolate.RegularGridInterpolator`` (linear) on the table padded by one cell
each side with its periodic neighbours; the rms factor is the square root of the
interpolated variance ratio. A planted half-cell offset of the grid (review 22, C2)
passed every test of the sensor.
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from closedloop.optics.correlating_sensor import NOISE_TABLE_STEPS, _noise_gain

STEPS = NOISE_TABLE_STEPS
CENTRES = (np.arange(STEPS) + 0.5) / STEPS - 0.5


def _table(seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(1.0, 7.0, (STEPS, STEPS, 2))


def test_the_gain_at_each_cell_centre_is_that_cells_ratio():
    table = _table()
    iy, ix = np.meshgrid(np.arange(STEPS), np.arange(STEPS), indexing="ij")
    iy, ix = iy.ravel(), ix.ravel()
    # whole pixels added: only the fractional shift matters
    px = CENTRES[ix] + np.tile([0, 1, -2, 3], ix.size // 4)
    py = CENTRES[iy] - np.tile([0, 2, -1, 1], iy.size // 4)
    got = _noise_gain(table, px, py)
    np.testing.assert_allclose(got, np.sqrt(table[iy, ix]), rtol=1e-12)


def test_the_gain_between_centres_is_the_periodic_bilinear_interpolation():
    table = _table(1)
    padded = np.pad(table, ((1, 1), (1, 1), (0, 0)), mode="wrap")
    grid = np.r_[CENTRES[0] - 1.0 / STEPS, CENTRES, CENTRES[-1] + 1.0 / STEPS]
    rng = np.random.default_rng(2)
    px, py = rng.uniform(-0.5, 0.5, 200), rng.uniform(-0.5, 0.5, 200)
    for axis in (0, 1):
        ref = RegularGridInterpolator((grid, grid), padded[..., axis])(np.column_stack([py, px]))
        np.testing.assert_allclose(_noise_gain(table, px, py)[:, axis], np.sqrt(ref),
                                   rtol=1e-12)
