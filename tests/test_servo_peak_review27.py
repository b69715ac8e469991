"""``servo._peak`` refines the largest local maxima of its grid, not the smallest (review27).

Planted bug of review27 (docs/MUTATION.md, round 27) that the round-42 file let through:
the 8 local maxima refined taken from the bottom of the sort (every tested |E| had at
most 8 local maxima on the grid, so all were refined either way). Reference: a
function written by hand with 21 ripple maxima and one narrow resonance between two
grid points, whose peak numpy finds on a grid 1e-4 of a step fine around it.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.servo import _peak

NYQUIST = 0.5
STEP = NYQUIST / 4096
F0 = 1000.5 * STEP  # half-way between two grid points
WIDTH = 0.15 * STEP


def _func(f):
    f = np.asarray(f, dtype=float)
    return 0.5 + 0.1 * np.cos(2 * np.pi * 40.0 * f) + 1.0 / (1.0 + ((f - F0) / WIDTH) ** 2)


def test_a_narrow_resonance_among_many_ripples_is_refined():
    grid = np.linspace(0.0, NYQUIST, 4097)
    values = _func(grid)
    inner = values[1:-1]
    n_local = int(np.sum((inner >= values[:-2]) & (inner >= values[2:])))
    assert n_local > 8  # more local maxima than are refined
    fine = F0 + np.linspace(-STEP, STEP, 20001)
    reference = float(np.max(_func(fine)))
    assert float(np.max(values)) < 0.9 * reference  # the grid alone misses it
    assert _peak(_func, NYQUIST) == pytest.approx(reference, rel=1e-6)
