"""Controlling a subspace of the modes, the orderings of Figure 6, and the latency model.

References: linear algebra (an integrator is equivariant under an orthogonal change of
basis, so every ordering controlling all modes is the same loop, and ``B = I`` is the
plain loop); scikit-learn's PCA (the data K-L ordering's modes are its components); the
theoretical K-L of ``modalinfo.bases.KLBasis``; and arithmetic for the latency model.
"""

import numpy as np
import pytest

from closedloop import LoopModel, presets, simulate
from closedloop.studies.compression import (
    ORDERINGS,
    LatencyModel,
    compression_study,
    control_orderings,
    rtc_compute_time,
)

DURATION = 0.1


@pytest.fixture(scope="module")
def kaos():
    cfg = presets.get("kaos")
    return cfg, LoopModel(cfg)


@pytest.fixture(scope="module")
def reference(kaos):
    cfg, model = kaos
    return simulate(cfg, DURATION, model=model, progress=False)


@pytest.fixture(scope="module")
def bases(reference):
    return control_orderings(reference, sample_budget=20_000)


def test_identity_basis_is_the_plain_loop(kaos, reference):
    cfg, model = kaos
    r = simulate(cfg, DURATION, model=model, progress=False, control_basis=np.eye(27))
    assert np.array_equal(r.strehl, reference.strehl)
    assert np.array_equal(r.logs["dm0.commands"].coeffs, reference.logs["dm0.commands"].coeffs)
    np.testing.assert_allclose(r.logs["dm0.pol"].coeffs, reference.logs["dm0.pol"].coeffs,
                               rtol=0, atol=1e-12)


def test_every_ordering_with_all_modes_is_the_same_loop(kaos, reference, bases):
    cfg, model = kaos
    for name, b in bases.items():
        r = simulate(cfg, DURATION, model=model, progress=False, control_basis=b)
        np.testing.assert_allclose(r.strehl, reference.strehl, rtol=1e-9, err_msg=name)


def test_uncontrolled_modes_are_left_alone(kaos, reference):
    cfg, model = kaos
    r = simulate(cfg, DURATION, model=model, progress=False, control_basis=np.eye(27)[:, :5])
    cmd = np.asarray(r.logs["dm0.commands"].coeffs)
    assert np.all(cmd[:, 5:] == 0.0) and np.any(cmd[:, :5] != 0.0)
    # an uncontrolled mode's residual is its open-loop turbulence: POL = residual there
    np.testing.assert_array_equal(r.logs["dm0.pol"].coeffs[:, 5:],
                                  r.logs["dm0.residual"].coeffs[:, 5:])
    # fewer corrected modes: lower Strehl after the closure
    k = reference.closure_index + 20
    assert r.strehl_peak[k:].mean() < reference.strehl_peak[k:].mean()


@pytest.mark.parametrize(("basis", "match"), [
    (np.ones((27, 2)), "orthonormal"),
    (np.eye(26), "shape"),
    (np.full((27, 1), np.nan), "finite"),
])
def test_bad_control_basis(kaos, basis, match):
    cfg, model = kaos
    with pytest.raises(ValueError, match="control_basis") as info:
        simulate(cfg, 0.01, model=model, progress=False, control_basis=basis)
    assert match in str(info.value)


def test_orderings_are_orthogonal_changes_of_basis(bases):
    assert set(bases) == set(ORDERINGS)
    for name, b in bases.items():
        np.testing.assert_allclose(b.T @ b, np.eye(27), atol=1e-10, err_msg=name)
    np.testing.assert_array_equal(bases["zernike"], np.eye(27))
    # MI orders are permutations of their basis's columns
    perm = np.argmax(np.abs(bases["zernike-mi"]), axis=0)
    assert sorted(perm) == list(range(27))
    overlap = np.abs(bases["kl"].T @ bases["kl-mi"])
    np.testing.assert_allclose(np.sort(overlap.max(axis=0)), np.ones(27), atol=1e-10)


def test_pca_ordering_matches_scikit_learn(reference, bases):
    from sklearn.decomposition import PCA

    from closedloop.control.predictors import training_start

    pol = np.asarray(reference.logs["dm0.pol"].coeffs)[training_start(reference):]
    # our PCA is uncentred (second moments, as modalinfo's data K-L); centre explicitly
    # to compare with scikit-learn on the same matrix
    pca = PCA().fit(np.vstack([pol, -pol]))
    for k in range(5):
        assert abs(abs(pca.components_[k] @ bases["pca"][:, k]) - 1.0) < 1e-8


def test_theoretical_kl_ordering_is_modalinfos_kl(reference, bases):
    from modalinfo.bases import KLBasis, Pupil

    cfg = reference.config
    kl = KLBasis.from_turbulence(Pupil(48, diameter=0.7), 27, outer_scale=20.0,
                                 zernike_modes=list(range(2, 29)))
    np.testing.assert_allclose(np.abs(bases["kl"]), np.abs(np.asarray(kl.zernike_from_kl)),
                               atol=1e-12)
    assert cfg.layers[0].outer_scale == 20.0


def test_latency_model_rounds_to_the_internal_step():
    lat = LatencyModel(readout=0.5e-3, oversampling=8)
    assert lat.delay(10e-6, 0.5e-3) == 0.5e-3            # < half a step: no change
    assert lat.delay(40e-6, 0.5e-3) == pytest.approx(0.5625e-3)
    assert LatencyModel(readout=0.5e-3, rtc_speed=4.0).delay(240e-6, 0.5e-3) == \
        pytest.approx(0.5625e-3)


def test_rtc_compute_time_is_a_time(kaos, bases):
    cfg, model = kaos
    t = rtc_compute_time(model, bases["zernike"][:, :5], repeats=50, batches=2)
    assert 0.0 < t < 0.1


def test_compression_study_structure(kaos):
    cfg, model = kaos
    study = compression_study(cfg, n_values=[4, 27], duration=0.1, model=model,
                              orderings=("zernike", "pca"), predictor="linear-ls")
    for lat in (False, True):
        for name in ("none", "linear-ls"):
            # with every mode the orderings span one space: one shared run
            a = study.strehl_peak[(lat, "zernike", name)]
            b = study.strehl_peak[(lat, "pca", name)]
            assert a[-1] == b[-1] and np.all(np.isfinite(a))
    # the latency runs equal the fixed runs wherever the modelled delay did not change
    for name in ("none", "linear-ls"):
        same = study.delay[name] == cfg.loop.delay
        for o in ("zernike", "pca"):
            np.testing.assert_array_equal(study.strehl_peak[(True, o, name)][same],
                                          study.strehl_peak[(False, o, name)][same])
    n, sr = study.optimum("pca", "none", latency=False)
    assert n in (4, 27) and sr == np.max(study.strehl_peak[(False, "pca", "none")])
    with pytest.raises(ValueError, match="n_values"):
        compression_study(cfg, n_values=[0, 27], duration=0.05, model=model)
    with pytest.raises(ValueError, match="predictor"):
        compression_study(cfg, n_values=[27], duration=0.05, model=model, predictor="none")
