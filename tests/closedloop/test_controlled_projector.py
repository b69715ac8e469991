"""A predictor's forecast stays inside the commands the WFSs can see.

References: the algebra of a truncated-SVD reconstructor (``R G`` is idempotent and
``R G R = R``, checked here with numpy on the model's own matrices); the classic
integrator written out in the test (no predictor, persistence); and a predictor built
in the test that forecasts a fixed vector in the blind directions only, which without
the projection would be commanded and never measured. The table1-solar run is the case
that found it (the paper's ARMA lost the loop there, SR 0.000; slow tier).
"""

import numpy as np
import pytest

from closedloop import LoopModel, presets, run_trained, simulate
from closedloop.control.controller import Controller
from modalinfo.forecast import PersistencePredictor

from . import test_loop

cfg, model = test_loop.cfg, test_loop.model


def test_projector_is_the_reconstructors_projector(model):
    p = model.controlled_projector
    assert p.shape == (model.n_modes, model.n_modes)
    scale = np.abs(p).max()
    np.testing.assert_allclose(p @ p, p, atol=1e-9 * scale)
    np.testing.assert_allclose(p @ model.reconstructor, model.reconstructor,
                               atol=1e-9 * np.abs(model.reconstructor).max())
    # its rank is the number of modes the joint reconstructor keeps
    assert round(float(np.trace(p))) == model.n_controlled


class _Blind:
    """Forecasts the POL plus a fixed vector ``v`` at every horizon (fitted: nothing)."""

    def __init__(self, v, horizon=4):
        self.v, self.horizon = v, horizon

    def reset(self):
        pass

    def update(self, x):
        return np.tile(x + self.v, (self.horizon, 1))


def _blind_vector(model):
    p = model.controlled_projector
    u, s, vt = np.linalg.svd(np.eye(model.n_modes) - p)
    return u[:, 0] * 1e-3  # a direction with (I - P) v = v: P v = 0


def test_blind_forecast_is_not_commanded(model):
    loop = model.config.loop
    v = _blind_vector(model)
    np.testing.assert_allclose(model.controlled_projector @ v, 0.0, atol=1e-12)
    kw = dict(gain=loop.gain, leak=loop.leak, delay_frames=loop.delay_frames,
              integration_frames=loop.integration_frames)
    plain = Controller(model.n_modes, predictor=_Blind(v), **kw)
    kept = Controller(model.n_modes, predictor=_Blind(v),
                      projector=model.controlled_projector, **kw)
    rng = np.random.default_rng(0)
    for _ in range(50):
        m = model.reconstructor @ rng.standard_normal(model.reconstructor.shape[1])
        c_plain, _, _ = plain.step(m)
        c_kept, _, _ = kept.step(m)
    # the part of a command outside the projector's range, (I - P) c: without the
    # projection the blind forecast integrates there (g v per frame), never measured
    blind = np.eye(model.n_modes) - model.controlled_projector
    np.testing.assert_allclose(blind @ c_plain, 50 * loop.gain * v, rtol=0,
                               atol=1e-9 * np.abs(v).max())
    assert np.linalg.norm(blind @ c_kept) < 1e-9 * np.linalg.norm(c_kept)


def test_persistence_keeps_the_integrators_bits(model):
    loop = model.config.loop
    kw = dict(gain=loop.gain, leak=loop.leak, delay_frames=loop.delay_frames,
              integration_frames=loop.integration_frames)
    pers = PersistencePredictor(horizon=4)
    pers.fit(np.zeros((10, model.n_modes)))
    with_p = Controller(model.n_modes, predictor=pers, projector=model.controlled_projector,
                        **kw)
    plain = Controller(model.n_modes, **kw)
    rng = np.random.default_rng(1)
    history = np.zeros((3, model.n_modes))
    for _ in range(20):
        m = rng.standard_normal(model.n_modes)
        a, _, _ = with_p.step(m)
        b, _, _ = plain.step(m)
        np.testing.assert_array_equal(a, b)
        # and the integrator itself, c_k = (1 - leak) c_{k-1} + g m_k (to rounding: the
        # loop computes g ((m + seen) - seen))
        expect = (1.0 - loop.leak) * history[0] + loop.gain * m
        np.testing.assert_allclose(b, expect, rtol=0, atol=1e-12 * np.abs(expect).max())
        history[0] = b


def test_projector_refused_with_a_wrong_shape(model):
    loop = model.config.loop
    with pytest.raises(ValueError, match="`projector` must be a finite"):
        Controller(model.n_modes, gain=loop.gain, leak=loop.leak,
                   delay_frames=loop.delay_frames, integration_frames=loop.integration_frames,
                   projector=np.eye(3))


@pytest.mark.slow
def test_table1_solar_arma_keeps_the_loop():
    """The paper's ARMA(2,3) on table1-solar: SR 0.000 before the projection (Figure 7)."""
    config = presets.get("table1-solar")
    m = LoopModel(config)
    none = simulate(config, 0.3, seed=0, model=m, progress=False)
    arma = run_trained(config, "arma", 0.3, seed=0, model=m)
    half = none.strehl_peak.size // 2
    assert arma.strehl_peak[half:].mean() > 0.9 * none.strehl_peak[half:].mean()
