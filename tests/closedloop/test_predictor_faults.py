"""A predictor's unusable output stops the loop at once, or is held on request.

References: the integrator recursion written out here (a held frame keeps the previous
command, every other frame is ``c_k = c_{k-1} + g m_k``, the persistence control law);
the fault's step and mode are those the test's faulty predictor injects.
"""

import numpy as np
import pytest

from closedloop import LoopModel, simulate
from closedloop.control.controller import Controller, PredictorFault
from modalinfo.forecast import PersistencePredictor

from .conftest import small


class Faulty:
    """Persistence with a planted fault: ``kind`` at step ``at`` (mode ``mode``)."""

    def __init__(self, base, kind, at, mode=0):
        self.base, self.kind, self.at, self.mode = base, kind, at, mode
        self.horizon = base.horizon
        self.step = 0

    def reset(self):
        self.base.reset()
        self.step = 0

    def update(self, x):
        out = np.array(self.base.update(x))
        k = self.step
        self.step += 1
        if k != self.at:
            return out
        if self.kind == "inf":
            out[-1, self.mode] = -np.inf
        elif self.kind == "nan":
            out[0, self.mode] = np.nan
        elif self.kind == "vector":  # (M,) where (H, M) is expected
            return out[0]
        elif self.kind == "extra_mode":
            return np.hstack([out, out[:, :1]])
        elif self.kind == "text":
            return "forecast"
        return out


def _persistence(n_modes, horizon=2):
    return PersistencePredictor(horizon=horizon).fit(np.zeros((20, n_modes)))


@pytest.mark.parametrize(("kind", "at", "match"), [
    ("inf", 4, r"Faulty returned -inf at step 4 for mode 2 \(horizon 2\)"),
    ("nan", 0, r"Faulty returned nan at step 0 for mode 2 \(horizon 1\)"),
    ("vector", 9, r"shape \(3,\) at step 9; the loop needs exactly \(2, 3\)"),
    ("extra_mode", 1, r"shape \(2, 4\) at step 1; the loop needs exactly \(2, 3\)"),
    ("text", 3, r"returned str at step 3, not an array"),
])
def test_controller_refuses_each_fault_with_its_step(kind, at, match):
    ctl = Controller(3, gain=0.3, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                     predictor=Faulty(_persistence(3), kind, at, mode=2))
    rng = np.random.default_rng(1)
    for _ in range(at):
        ctl.step(rng.standard_normal(3))
    with pytest.raises(PredictorFault, match=match) as info:
        ctl.step(rng.standard_normal(3))
    assert info.value.step == at
    assert "on_predictor_fault='hold'" in str(info.value)


def test_hold_keeps_the_last_command_and_counts_it():
    gain = 0.3
    ctl = Controller(3, gain=gain, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                     predictor=Faulty(_persistence(3), "nan", 6, mode=1),
                     on_predictor_fault="hold")
    rng = np.random.default_rng(2)
    c = np.zeros(3)
    for k in range(12):
        m = rng.standard_normal(3)
        if k != 6:
            c = c + gain * m  # persistence: exactly the integrator
        got, _, _ = ctl.step(m)
        np.testing.assert_allclose(got, c, rtol=0, atol=1e-12)
    assert ctl.n_faults == 1
    with pytest.raises(ValueError, match="`on_predictor_fault` must be one of 'raise', 'hold'"):
        Controller(3, gain=gain, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                   on_predictor_fault="skip")


@pytest.fixture(scope="module")
def setup():
    cfg = small()
    model = LoopModel(cfg)
    return cfg, model, _persistence(model.n_modes)


def test_simulate_stops_at_the_fault_naming_the_dm_mode(setup):
    cfg, model, base = setup
    bad = Faulty(base, "inf", 7, mode=40)  # dm1's 6th mode: 35 modes on dm0
    label = model.dms[1].labels[5]
    with pytest.raises(PredictorFault, match=rf"at step 7 for mode 40 \(dm1 {label}\)"):
        simulate(cfg, 0.03, seed=3, model=model, predictor=bad, progress=False)
    vec = Faulty(base, "vector", 2)
    with pytest.raises(PredictorFault, match=rf"needs exactly \(2, {model.n_modes}\)"):
        simulate(cfg, 0.03, seed=3, model=model, predictor=vec, progress=False)


def test_simulate_hold_warns_and_keeps_finite_logs(setup):
    cfg, model, base = setup
    bad = Faulty(base, "nan", 5, mode=3)
    with pytest.warns(RuntimeWarning, match="on 1 of 30 frames; the last command was held"):
        run = simulate(cfg, 0.03, seed=3, model=model, predictor=bad, progress=False,
                       on_predictor_fault="hold")
    commands = run.logs["dm0.commands"].coeffs
    np.testing.assert_array_equal(commands[5], commands[4])
    assert np.all(np.isfinite(run.residual_variance))
