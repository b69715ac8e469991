"""A constant reference among several is refused, naming it; a stack of textured ones is not.

Reference (outside the code): a constant image has no structure, so its squared
difference with any shifted window is the same number for every lag (a flat surface: no
minimum, no shift; the measured shift of a textured scene by a known integer lag is that
lag, the Fourier shift theorem's exact translation of a periodic scene, here
``numpy.roll``).

Planted bug R8-43 (docs/MUTATION.md, round 8): the check written over the whole stack
(``np.ptp(refs, axis=(0, 1, 2))``) instead of per image caught only an all-constant
stack; ``test_shifts.py`` checked one constant reference alone.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter

from closedloop.optics.shifts import measure_shifts


def _scene(seed: int) -> np.ndarray:
    return 1.0 + 0.15 * gaussian_filter(np.random.default_rng(seed).standard_normal((48, 48)),
                                        2.0, mode="wrap")


@pytest.mark.parametrize("method", ["sdf", "adf2"])
def test_one_constant_reference_in_a_stack_is_refused(method):
    scenes = [_scene(1), _scene(2)]
    images = np.stack([np.roll(s, (1, 2), axis=(0, 1))[8:40, 8:40] for s in scenes])
    refs = np.stack([s[8:40, 8:40] for s in scenes])
    found = measure_shifts(refs, images, method=method)  # x along columns: (2, 1) pixels
    np.testing.assert_array_equal(np.abs(found.integer), [[2, 1], [2, 1]])
    np.testing.assert_allclose(np.abs(found.shifts), [[2.0, 1.0]] * 2, atol=0.1)
    refs[1] = 1.0
    with pytest.raises(ValueError, match=r"`reference` image 1 is constant"):
        measure_shifts(refs, images, method=method)
