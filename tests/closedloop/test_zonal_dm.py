"""The zonal ("ideal") DM's interaction is sparse, equal to the dense poke matrix.

Reference: the dense interaction matrix built independently, column by column, by
poking one pixel of the DM's disc at a time and measuring it through the sensor's own
measurement path (``WavefrontSensor.forward``, the product the loop uses), which is what
the former ``block.toarray()`` held. Memory: ``tracemalloc`` around the set-up of an
80-pixel model, against the ``8 n_disc**2`` bytes a dense block would take.
"""

import tracemalloc

import numpy as np
import pytest
from scipy import sparse

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.simulation import LoopModel, simulate


def _zonal(n_pixels: int, wfs_kind: str = "ideal", fov: float = 4.0,
           samples: int = 2) -> SimulationConfig:
    return SimulationConfig(
        name="zonal",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=n_pixels),
        layers=(LayerConfig(altitude=0.0, d_over_r0=10.0, wind_speed=5.0),
                LayerConfig(altitude=5000.0, d_over_r0=3.0, wind_speed=10.0)),
        dms=(DMConfig(altitude=0.0, kind="ideal"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=fov, kind=wfs_kind, n_subapertures=4,
                        field_samples=samples),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.0, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1))


def _poked(model: LoopModel) -> np.ndarray:
    """Dense interaction matrix: one measurement per unit pixel of the DM's disc."""
    wfs, dm = model.wfss[0], model.dms[0]
    g = model.geometry
    cols = []
    for pix in dm.pixels:
        maps = [np.zeros((p.n, p.n)) for p in g.planes]
        maps[dm.plane].reshape(-1)[pix] = 1.0
        cols.append(wfs.forward(maps))
    return np.array(cols).T


@pytest.mark.parametrize("wfs_kind", ["ideal", "shack_hartmann"])
def test_zonal_interaction_is_sparse_and_equals_the_poke_matrix(wfs_kind):
    model = LoopModel(_zonal(12, wfs_kind))
    wfs = model.wfss[0]
    assert sparse.issparse(wfs.interaction)
    dense = _poked(model)
    assert wfs.interaction.shape == dense.shape
    # one nonzero input per column: the sparse product adds the same terms, so the values
    # agree to the last bits of a few additions
    np.testing.assert_allclose(wfs.interaction.toarray(), dense, rtol=1e-14, atol=1e-14)
    if wfs_kind == "shack_hartmann":
        np.testing.assert_allclose(wfs.reconstructor, np.linalg.pinv(dense, rcond=1e-3),
                                   rtol=1e-9, atol=1e-9 * np.abs(wfs.reconstructor).max())
    else:
        assert wfs.reconstructor is None


def test_zonal_loop_runs_and_corrects_the_ground_layer():
    # the ideal zonal DM takes the field-averaged phase of its sensor: on a one-sample field
    # and a static ground layer at gain 1 the residual on axis vanishes after one frame
    cfg = _zonal(16, "ideal", fov=0.0, samples=1).replace(
        layers=(LayerConfig(altitude=0.0, d_over_r0=10.0, wind_speed=0.0),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.0, gain=1.0))
    r = simulate(cfg, 4e-3, seed=3, progress=False)
    assert r.residual_variance[0, 0] > 1.0
    assert r.residual_variance[-1, 0] < 1e-20


def test_zonal_model_at_80_pixels_does_not_allocate_a_dense_block():
    cfg = _zonal(80, "ideal", fov=4.0, samples=2)
    tracemalloc.start()
    try:
        model = LoopModel(cfg)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    n_disc = model.dms[0].pixels.size
    dense_bytes = 8 * n_disc * model.wfss[0].n_measurements
    assert dense_bytes > 150e6  # the block a dense matrix would be (~200 MB)
    assert peak < 0.1 * dense_bytes
