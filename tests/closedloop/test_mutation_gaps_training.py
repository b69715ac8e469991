"""closedloop.training.run_trained: the paper's recipe, call by call, without a loop.

Gaps found by mutation testing (docs/MUTATION.md, "kinds.py, resources.py, predictors.py,
training.py"). ``simulate`` and ``LoopModel`` are replaced by recorders: the reference
run they return holds an exact AR(2) POL written in the test, so the predictor the
final run receives is known by an analytic law (``linear-ls`` fits ``(a, b) = (1.5,
-0.7)``). References, from outside the code: the recipe of the module docstring and
``run_trained``'s (train on the no-prediction run of the same config and duration, the
same atmosphere unless ``train_seed`` names another, a given reference reused unless
``train_seed`` differs from the run's seed; ``seed`` None is the config's; the run gets
``budget_every`` and ``control_basis``, both runs ``memory_limit``, ``progress`` and the
one model), written out here as the expected calls.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from closedloop import training
from closedloop.control.predictors import NO_PREDICTION, ORACLE, LoopPredictor


def _ar2_pol(n: int = 80, modes: int = 2) -> np.ndarray:
    x = np.zeros((n, modes))
    x[0], x[1] = np.arange(1.0, modes + 1), -np.arange(modes, 0.0, -1)
    for k in range(2, n):
        x[k] = 1.5 * x[k - 1] - 0.7 * x[k - 2]
    return x


class _Recorder:
    """Stands in for ``simulate`` and ``LoopModel``; every call is kept."""

    def __init__(self):
        self.runs, self.models = [], []

    def model(self, config):
        made = SimpleNamespace(config=config)
        self.models.append(made)
        return made

    def simulate(self, config, duration, **kwargs):
        self.runs.append((config, duration, kwargs))
        return SimpleNamespace(
            tag=f"run{len(self.runs)}", predictor="none",
            config=SimpleNamespace(dms=(0,)),
            logs={"dm0.pol": SimpleNamespace(coeffs=_ar2_pol())},
            times=np.array([k / 1000 for k in range(80)]), closure_index=0,
            averaging_start=0, diverged=False, loop_status="closed")


@pytest.fixture
def rec(monkeypatch):
    r = _Recorder()
    monkeypatch.setattr(training, "simulate", r.simulate)
    monkeypatch.setattr(training, "LoopModel", r.model)
    return r


CONFIG = SimpleNamespace(seed=7, name="cfg")


def _final(rec):
    config, duration, kwargs = rec.runs[-1]
    assert config is CONFIG and duration == 0.25
    return kwargs


def test_a_name_is_trained_on_the_same_seed_s_reference_then_run(rec):
    basis = np.array([[1.0], [2.0]])  # the predictor sees one mode, POL @ basis
    got = training.run_trained(CONFIG, "linear-ls", 0.25, progress=False, budget_every=5,
                               memory_limit=3e9, control_basis=basis)
    assert len(rec.models) == 1 and rec.models[0].config is CONFIG
    assert len(rec.runs) == 2
    config, duration, ref_kwargs = rec.runs[0]
    assert config is CONFIG and duration == 0.25
    assert ref_kwargs == {"seed": 7, "model": rec.models[0], "progress": False,
                          "memory_limit": 3e9}
    kwargs = _final(rec)
    spec = kwargs.pop("predictor")
    assert kwargs == {"seed": 7, "model": rec.models[0], "progress": False,
                      "budget_every": 5, "memory_limit": 3e9, "control_basis": basis}
    assert isinstance(spec, LoopPredictor) and spec.name == "linear-ls"
    assert not spec.needs_training
    assert spec.predictor.coef_.shape == (1, 2)  # one projected mode
    np.testing.assert_allclose(spec.predictor.coef_, [[1.5, -0.7]], atol=1e-8)
    assert got.tag == "run2"


def test_the_seed_and_the_training_seed(rec):
    training.run_trained(CONFIG, "linear-ls", 0.25, seed=3)
    assert rec.runs[0][2]["seed"] == 3 and _final(rec)["seed"] == 3
    rec.runs.clear()
    training.run_trained(CONFIG, "linear-ls", 0.25, seed=3, train_seed=11)
    assert rec.runs[0][2]["seed"] == 11 and _final(rec)["seed"] == 3
    rec.runs.clear()
    training.run_trained(CONFIG, "linear-ls", 0.25, train_seed=11)
    assert rec.runs[0][2]["seed"] == 11 and _final(rec)["seed"] == 7


def test_a_given_reference_is_reused_unless_the_training_seed_differs(rec):
    reference = _Recorder().simulate(CONFIG, 0.25)
    reference.logs["dm0.pol"].coeffs = 2.0 * _ar2_pol()  # the same law, other values
    model = SimpleNamespace(config=CONFIG)
    training.run_trained(CONFIG, "linear-ls", 0.25, reference=reference, model=model)
    assert len(rec.runs) == 1 and not rec.models  # no reference run, no new model
    assert _final(rec)["model"] is model
    np.testing.assert_allclose(_final(rec)["predictor"].predictor.coef_,
                               np.tile([1.5, -0.7], (2, 1)), atol=1e-8)
    rec.runs.clear()
    training.run_trained(CONFIG, "linear-ls", 0.25, reference=reference, train_seed=7)
    assert len(rec.runs) == 1  # train_seed == seed: the reference is that run
    rec.runs.clear()
    training.run_trained(CONFIG, "linear-ls", 0.25, reference=reference, train_seed=8)
    assert len(rec.runs) == 2 and rec.runs[0][2]["seed"] == 8


@pytest.mark.parametrize("spec", ["none", "oracle", NO_PREDICTION, ORACLE])
def test_nothing_to_train_runs_once_with_the_spec(rec, spec):
    training.run_trained(CONFIG, spec, 0.25)
    assert len(rec.runs) == 1
    kwargs = _final(rec)
    want = spec if isinstance(spec, LoopPredictor) else LoopPredictor.from_name(spec)
    assert kwargs["predictor"] is want
    assert kwargs == {"predictor": want, "seed": 7, "model": rec.models[0],
                      "progress": None, "budget_every": None, "memory_limit": None,
                      "control_basis": None}


def test_an_untrained_spec_given_as_such_is_trained(rec):
    spec = LoopPredictor.from_name("linear-ls")
    training.run_trained(CONFIG, spec, 0.25)
    assert len(rec.runs) == 2 and _final(rec)["predictor"].name == "linear-ls"
    assert spec.needs_training  # unchanged


def test_an_unknown_name_is_refused_before_any_run(rec):
    with pytest.raises(ValueError, match=r"^`predictor` must be one of none, persistence"):
        training.run_trained(CONFIG, "kalman", 0.25)
    assert not rec.runs and not rec.models
