"""InfluenceFunctions shared by threads and handed to callers (audit 10-state).

References (outside the code): the influence functions written out pixel by pixel
(``coupling ** (r**2 / pitch**2)`` on the square support, as in test_influence.py), whose
sum weighted by the commands is each surface; the serial call for the threaded ones.
"""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from modalinfo.bases import InfluenceFunctions, Pupil

from .conftest import dense_influence


def test_threads_sharing_one_mirror_get_their_own_surfaces():
    # the kernel releases the GIL: scratch grids held by the object mixed the commands of
    # concurrent calls (row thr-influence-surface)
    f = InfluenceFunctions(Pupil(32), 9)
    dense = dense_influence(f)
    commands = [np.random.default_rng(s).standard_normal(f.n_valid) for s in range(32)]
    with ThreadPoolExecutor(4) as pool:
        for _ in range(5):
            surfaces = list(pool.map(f.surface, commands))
            for c, s in zip(commands, surfaces, strict=True):
                np.testing.assert_allclose(s, dense @ c, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("name", ["valid_index", "valid", "factor", "positions",
                                  "valid_positions", "illumination", "centres", "coords"])
def test_public_arrays_are_read_only(name):
    # writing into valid_index or factor changed every later surface (row ret-influence)
    f = InfluenceFunctions(Pupil(16), 5)
    with pytest.raises(ValueError, match="read-only"):
        getattr(f, name)[...] = 0
    c = np.random.default_rng(0).standard_normal(f.n_valid)
    np.testing.assert_allclose(f.surface(c), dense_influence(f) @ c, rtol=1e-12, atol=1e-12)
