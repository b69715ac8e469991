"""A predictor trained on a reference run of other conditions is refused (audit 10,
feedback, rows rt-ref-other-rate, rt-ref-other-wind, sim-trained-other-rate).

Reference: the definition of the training set, the POL of a no-prediction run "of the
same conditions" (``run_trained``'s ``reference``): a forecaster's lags count frames, so
the least-squares weights fitted at another frame rate or wind are another model (shown
here: the two references give other weights). Before, ``run_trained(config, ...,
reference=<run at twice the time step>)`` and ``simulate(config, predictor=<trained on
it>)`` ran without a word. A reference differing only in the controller (gain, delay)
or the seed is still accepted: the POL estimates the turbulence whatever the loop does.
"""

import dataclasses

import numpy as np
import pytest

from closedloop import LoopPredictor, run_trained, simulate

from .conftest import lag_only


@pytest.fixture(scope="module")
def runs():
    cfg = lag_only()
    slow = cfg.replace(loop=dataclasses.replace(cfg.loop, time_step=2e-3,
                                                integration_time=2e-3, delay=2e-3))
    return cfg, simulate(cfg, 0.12, seed=0), slow, simulate(slow, 0.24, seed=0)


def test_other_rate_is_another_model(runs):
    _, ref, _, ref_slow = runs
    a = LoopPredictor.from_name("linear-ls").trained(ref).predictor.params_
    b = LoopPredictor.from_name("linear-ls").trained(ref_slow).predictor.params_
    assert not all(np.array_equal(a[k], b[k]) for k in a)


def test_reference_of_another_rate_refused(runs):
    cfg, _, _, ref_slow = runs
    with pytest.raises(ValueError, match=r"`loop.time_step` is not this config's"):
        run_trained(cfg, "linear-ls", 0.01, seed=0, reference=ref_slow)
    spec = LoopPredictor.from_name("linear-ls").trained(ref_slow)
    with pytest.raises(ValueError, match=r"`predictor` 'linear-ls' was trained"):
        simulate(cfg, 0.01, predictor=spec, seed=0)


def test_reference_of_another_wind_refused(runs):
    cfg, _, _, _ = runs
    # a quarter of the wind (4x was 325 m/s, beyond the 100 m/s wind rule: left26-twins)
    windy = cfg.replace(layers=tuple(dataclasses.replace(lay, wind_speed=lay.wind_speed / 4)
                                     for lay in cfg.layers))
    with pytest.raises(ValueError, match=r"`layers` is not this config's"):
        run_trained(cfg, "linear-ls", 0.01, seed=0, reference=simulate(windy, 0.12, seed=0))


def test_controller_and_seed_may_differ(runs):
    cfg, ref, _, _ = runs
    other = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=0.3, delay=2e-3))
    r = run_trained(other, "linear-ls", 0.01, seed=1, reference=ref)
    assert r.strehl.shape[0] == 10 and np.all(np.isfinite(r.strehl))


def test_control_basis_other_than_trained_on_refused(runs):
    # a predictor fitted on POL @ B1 was run on POL @ B2 of the same width without a word
    cfg, ref, _, _ = runs
    n = ref.logs["dm0.pol"].n_modes
    q, _ = np.linalg.qr(np.random.default_rng(0).standard_normal((n, n)))
    b1, b2 = np.eye(n)[:, :5], q[:, :5]
    spec = LoopPredictor.from_name("linear-ls").trained(ref, basis=b1)
    assert simulate(cfg, 0.005, predictor=spec, seed=0, control_basis=b1).strehl.shape[0] == 5
    with pytest.raises(ValueError, match="another control basis"):
        simulate(cfg, 0.005, predictor=spec, seed=0, control_basis=b2)
    with pytest.raises(ValueError, match="another control basis"):
        simulate(cfg, 0.005, predictor=LoopPredictor.from_name("linear-ls").trained(ref),
                 seed=0, control_basis=b1)
