"""The Shack-Hartmann's memory estimate bounds what its per-plane assembly really holds.

Reference: the assembled operators themselves (their CSR arrays' bytes, measured on the
built sensors of ``presets.est_mcao_variant(16)``), not the estimate's own formula: a
plane's assembly holds at least that plane's final operator, so the estimate's
``held_entries`` (16 bytes each) must not be below the largest one, and the whole build
(``build_entries``) not below all of them. The bits of the per-plane assembly are
checked by the golden numbers (``tests/test_golden.py``).
"""

from __future__ import annotations

import pytest

from closedloop import presets
from closedloop.kinds import mirror_kind, sensor_kind
from closedloop.optics.geometry import Geometry


@pytest.fixture(scope="module")
def built():
    config = presets.est_mcao_variant(16)
    geometry = Geometry(config)
    dms = [mirror_kind(d.kind).build(geometry, i) for i, d in enumerate(config.dms)]
    return config, geometry, [sensor_kind(w.kind).build(geometry, j, dms[w.dm])
                              for j, w in enumerate(config.wfss)]


def test_the_estimate_holds_one_plane_and_bounds_the_built_operators(built):
    config, geometry, wfss = built
    n_planes = len(geometry.planes)
    for j, wfs in enumerate(wfss):
        cost = sensor_kind(config.wfss[j].kind).estimate(config, j, n_planes, geometry.dx)
        assert cost.held_entries == pytest.approx(cost.build_entries / n_planes, rel=1e-12)
        sizes = [op.data.nbytes + op.indices.nbytes + op.indptr.nbytes
                 for op in wfs.operators]
        assert 16.0 * cost.held_entries >= max(sizes)
        assert 16.0 * cost.build_entries >= sum(sizes)
