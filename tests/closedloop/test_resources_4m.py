"""Set-up at 4-m size: the refusal before any set-up, and the reconstructors built lazily.

References (outside the code): the estimate's own peak as the boundary of the refusal
(a limit one part in 1e6 either side of it; the estimate against measured peak RSS is
``benchmarks/bench_4m_loop.py``'s, RESULTS.md "4-m loop"); numpy's ``pinv`` with the
WFS's ``rcond`` for the least-squares reconstructor; a ``LoopModel`` that would be
built is replaced by one that fails, so "refused before the set-up" is observed.
"""

import dataclasses

import numpy as np
import pytest

from closedloop import LoopModel, presets, simulate
from closedloop import simulation as simulation_module
from closedloop.config import (
    FieldConfig,
    SimulationConfig,
)
from closedloop.resources import ResourceError, check_resources, estimate

from .conftest import shrunk


def dkist_like() -> SimulationConfig:
    """The ``dkist-scao`` preset at 1,500 K-L modes, the test's variant of bench_4m_loop.py's.

    From the preset: telescope (172 px across 4 m), layers (weights, altitudes, 10 m/s,
    L0 = 27 m, r0 = 7 cm), the 43 x 43 SH, loop, wavelengths, seed. Changed: 1,500 modes
    on the kind's default 44 x 44 actuators, winds all along +x, a noise-free SH, a 3 x 3
    science grid over 10", the default name.
    """
    base = presets.dkist_scao()
    return base.replace(
        name="custom",
        layers=tuple(dataclasses.replace(lay, wind_direction=0.0) for lay in base.layers),
        dms=(dataclasses.replace(base.dms[0], n_modes=1500, options=None),),
        wfss=(dataclasses.replace(base.wfss[0], noise=0.0),),
        field=FieldConfig(size=10.0, n_points=3))


def test_a_4m_run_is_refused_at_its_estimate_before_any_set_up(monkeypatch):
    cfg = dkist_like()
    est = estimate(cfg, 1.0)
    # the set-up counts the K-L build (n_valid^3) and the pseudo-inverse of the
    # 2,882 x 1,500 interaction matrix (rows x cols^2), seconds each
    assert est.setup_seconds > 1.0
    check_resources(cfg, 1.0, limit=est.peak_bytes * (1 + 1e-6))
    with pytest.raises(ResourceError, match=r"driven by `dms\[0\]\.n_actuators`"):
        check_resources(cfg, 1.0, limit=est.peak_bytes * (1 - 1e-6))

    def no_set_up(config):
        raise AssertionError("the set-up ran")

    monkeypatch.setattr(simulation_module, "LoopModel", no_set_up)
    with pytest.raises(ResourceError, match="more than"):
        simulate(cfg, 1.0, memory_limit=est.peak_bytes * (1 - 1e-6), progress=False)


def test_small_presets_report_no_set_up_build():
    # their SVDs take milliseconds: nothing to report (the estimate's text is unchanged)
    for name in ("table1", "kaos", "mcao3"):
        assert estimate(presets.get(name), 0.1).setup_seconds == 0.0


def _two_dm_tiny() -> SimulationConfig:
    return shrunk(presets.get("table1"), (20, 9), field_samples=3)


def test_a_joint_map_model_never_builds_the_per_wfs_reconstructors():
    model = LoopModel(_two_dm_tiny())
    assert model.reconstructor is not None
    simulate(model.config, 0.005, model=model, progress=False)
    assert all("reconstructor" not in vars(w) for w in model.wfss)
    # asked for, it is the pseudo-inverse of the WFS's interaction with its own DM,
    # weighted by the measurements' inverse noise variances: a photon-limited slope's is
    # its light share s (variance 1 / s; issue 27, left31-edge), computed by the code as
    # 1 / (1 / s), which may differ from s in the last bit: within 1e-12
    for w in model.wfss:
        root = np.sqrt(w.field_share)[:, None]
        expected = np.linalg.pinv(root * w.interaction, rcond=1e-3) * root.T
        np.testing.assert_allclose(w.reconstructor, expected, rtol=0,
                                   atol=1e-12 * np.abs(expected).max())


def test_the_gram_path_gives_the_svd_reconstructor(monkeypatch):
    # the joint MAP reconstructor through the Gram matrix (the 4-m path) against the SVD
    # (the path of every earlier preset) on the same tiny two-DM model; the singular value
    # of the whitened matrix nearest the cut is 45 % from it, so both keep the same 20 of
    # 29; the Gram's rounding is <= eps kappa^2 <= 2.2e-10 (products.gram_pinv)
    from closedloop.optics import products
    from closedloop.optics.dm import ZernikeMirror

    cfg = _two_dm_tiny()
    svd_model = LoopModel(cfg)
    svd_wfs = [w.reconstructor for w in svd_model.wfss]  # built now (lazy), by the SVD
    monkeypatch.setattr(products, "GRAM_MIN_BYTES", 0)
    monkeypatch.setattr(ZernikeMirror, "large_products", True)
    gram_model = LoopModel(cfg)
    assert gram_model.n_controlled == svd_model.n_controlled
    ref = svd_model.reconstructor
    assert np.max(np.abs(gram_model.reconstructor - ref)) <= 1e-8 * np.max(np.abs(ref))
    for r_svd, w_gram in zip(svd_wfs, gram_model.wfss, strict=True):
        assert np.max(np.abs(w_gram.reconstructor - r_svd)) <= 1e-8 * np.max(np.abs(r_svd))


@pytest.mark.slow
def test_the_kl_build_fits_in_its_estimate_at_dkist_size():
    # tracemalloc's peak of the K-L build (numpy and LAPACK workspaces through numpy)
    # against what the estimate holds for it: the transient ``dm_build`` plus the Gram
    # matrix and m2c with its cached copy (counted in ``dm_shapes``); never below, and
    # not more than 1.5x above (measured: the estimate 1.115x the peak)
    import tracemalloc

    from closedloop.config import dm_disc_diameter
    from closedloop.optics.actuator_dm import _influence
    from modalinfo.bases import _dm_kl_cache, dm_kl_modes

    cfg = dkist_like()
    est = estimate(cfg, 0.1)
    dx = cfg.telescope.diameter / cfg.telescope.n_pixels
    influence = _influence(dm_disc_diameter(cfg, 0), dx, 0, 44, 0.35, 0.05)
    influence.matrix  # noqa: B018 - built before (counted in dm_shapes)
    n, m = influence.n_valid, cfg.dms[0].n_modes
    _dm_kl_cache.clear()
    tracemalloc.start()
    try:
        dm_kl_modes(influence, dm_disc_diameter(cfg, 0), 27.0, n_modes=m)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
        _dm_kl_cache.clear()
    held = est.parts["dm_build"] + 8.0 * n * n + 2 * 8.0 * n * m
    assert peak <= held <= 1.5 * peak


def test_earlier_presets_keep_float64_products_and_svds_at_any_size():
    # the error-budget probe's ideal-sensor model of table1 has an 11.9 MB joint
    # reconstructor (3,228 + 4,872 pixels x 184 modes), above the 8 MB thresholds: with
    # Zernike mirrors it stays on the float64 product and the SVD (the golden budgets)
    from closedloop.budget import _ideal_config
    from closedloop.optics import products

    model = LoopModel(_ideal_config(presets.get("table1")))
    assert 8 * model.reconstructor.size >= products.FLOAT32_MIN_BYTES
    assert not model._products[0].single
    assert model.reconstructor is model._products[0].matrix
