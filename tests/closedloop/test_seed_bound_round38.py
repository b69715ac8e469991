"""``simulate(seed=...)`` above what the result file can store (round 38 PART a, R72).

Reference: HDF5 (h5py) attributes hold integers of at most 64 bits; ``SimulationConfig``
already refuses ``seed`` above ``MAX_SEED`` = 2**63 - 1 for that reason. Before, the
``seed`` argument of ``simulate`` took 2**100, ran, and ``SimulationResult.save`` then
raised h5py's "Object dtype dtype('O') has no native HDF5 equivalent".
"""

from __future__ import annotations

import pytest

from closedloop import presets
from closedloop.config import MAX_SEED
from closedloop.simulation import simulate


@pytest.mark.parametrize("seed", [2**100, MAX_SEED + 1])
def test_seed_beyond_the_file_refused_before_running(seed):
    with pytest.raises(ValueError, match=r"`seed` must be at most 2\*\*63 - 1"):
        simulate(presets.kaos(), 0.02, seed=seed, progress=False)
