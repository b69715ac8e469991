"""One predictor-in-the-loop concept: names checked once, training as the paper does it,
and the name the user gave kept in the result.

References: the paper's recipe written out here by hand (a fresh
:func:`modalinfo.forecast.presets.make_predictor` fitted on
:func:`closedloop.control.predictors.training_data` of the no-prediction run, then
:func:`closedloop.simulate`), compared bit for bit with :func:`closedloop.run_trained`;
the forecasts of a hand-fitted predictor against :meth:`LoopPredictor.trained`'s; the
list of names against :data:`modalinfo.forecast.presets.PRESETS` (the one list); and,
for the command line, the calls actually made, counted by wrapping the validator and
the forecaster's ``update``.
"""

import dataclasses

import h5py
import numpy as np
import pytest

from closedloop import ORACLE, SimulationResult, run_trained, simulate
from closedloop.cli import main
from closedloop.config import save_config
from closedloop.control.predictors import NAMES, NO_PREDICTION, LoopPredictor, training_data
from modalinfo.forecast import ARMAPredictor
from modalinfo.forecast.presets import PRESETS, make_predictor

from . import test_loop

# the fixtures of the loop tests: their small MCAO and its no-prediction run (0.15 s, seed 5)
cfg, model, reference = test_loop.cfg, test_loop.model, test_loop.reference

DURATION = 0.2  # ARMA with AIC orders needs up to 160 training frames after 15 ms


def test_names_are_the_forecast_presets_plus_three():
    assert NAMES == ("none", "persistence", "oracle", *PRESETS)
    assert LoopPredictor.from_name("none") is NO_PREDICTION
    assert LoopPredictor.from_name("oracle") is ORACLE
    assert ORACLE.oracle and ORACLE.predictor is None and not ORACLE.needs_training
    assert NO_PREDICTION.is_none and not ORACLE.is_none
    arma = LoopPredictor.from_name("arma-aic")
    assert arma.name == "arma-aic" and arma.needs_training
    assert isinstance(arma.predictor, ARMAPredictor) and arma.predictor.order == "aic"
    # a fresh forecaster each time (never shared between runs)
    first, second = LoopPredictor.from_name("arma"), LoopPredictor.from_name("arma")
    assert first.predictor is not second.predictor
    for bad in ("kalman", "ARMA", "", None, 3):
        with pytest.raises(ValueError, match="`predictor` must be one of none, persistence"):
            LoopPredictor.from_name(bad)
    with pytest.raises(dataclasses.FrozenInstanceError):
        ORACLE.name = "x"


def test_trained_is_the_hand_fit_and_leaves_the_spec_alone(reference):
    spec = LoopPredictor.from_name("arma")
    trained = spec.trained(reference)
    hand = make_predictor("arma").fit(training_data(reference))
    history = training_data(reference)[-40:]
    np.testing.assert_array_equal(trained.predictor.predict(history), hand.predict(history))
    assert trained.name == "arma" and not trained.needs_training
    assert spec.needs_training and not hasattr(spec.predictor, "params_")  # unchanged
    assert ORACLE.trained(reference) is ORACLE
    # projected training data: the fit on POL @ B
    basis = np.eye(reference.logs["dm0.pol"].n_modes + reference.logs["dm1.pol"].n_modes)[:, :6]
    projected = spec.trained(reference, basis=basis).predictor
    hand_b = make_predictor("arma").fit(training_data(reference) @ basis)
    np.testing.assert_array_equal(projected.predict(history @ basis),
                                  hand_b.predict(history @ basis))


def test_run_trained_is_the_papers_recipe(cfg, model, reference):
    by_hand = make_predictor("linear-ls").fit(training_data(reference))
    expected = simulate(cfg, 0.15, seed=5, model=model, predictor=by_hand, progress=False)
    got = run_trained(cfg, "linear-ls", 0.15, seed=5, reference=reference, model=model,
                      progress=False)
    np.testing.assert_array_equal(got.residual_variance, expected.residual_variance)
    np.testing.assert_array_equal(got.logs["dm0.commands"].coeffs,
                                  expected.logs["dm0.commands"].coeffs)
    assert got.predictor == "linear-ls" and expected.predictor == "LinearPredictor"
    # without a reference it runs the same no-prediction run itself
    again = run_trained(cfg, "linear-ls", 0.15, seed=5, model=model, progress=False)
    np.testing.assert_array_equal(again.residual_variance, expected.residual_variance)
    # "none" is the plain run
    plain = run_trained(cfg, "none", 0.15, seed=5, model=model, progress=False)
    np.testing.assert_array_equal(plain.residual_variance, reference.residual_variance)
    assert plain.predictor == "none"


def test_simulate_reads_predictor_once_and_refuses_names(cfg, model):
    with pytest.raises(ValueError, match=r"got the name 'arma'.*run_trained"):
        simulate(cfg, 0.05, model=model, predictor="arma", progress=False)
    with pytest.raises(ValueError, match="'arma' is not trained"):
        simulate(cfg, 0.05, model=model, predictor=LoopPredictor.from_name("arma"),
                 progress=False)
    with pytest.raises(TypeError, match="reset\\(\\) and update"):
        simulate(cfg, 0.05, model=model, predictor=object(), progress=False)
    # the string "oracle" still works, with a DeprecationWarning (here refused after it,
    # cheaply, by the open-loop rule)
    open_cfg = cfg.replace(loop=dataclasses.replace(cfg.loop, closed=False))
    with pytest.warns(DeprecationWarning, match="closedloop.ORACLE"), \
            pytest.raises(ValueError, match="must be None in open loop.*got 'oracle'"):
        simulate(open_cfg, 0.05, predictor="oracle", progress=False)


def test_cli_walk_of_a_name_to_the_loop_and_back(cfg, tmp_path, monkeypatch, capsys):
    """``closedloop run --predictor arma-aic``: one validation, the forecaster asked at
    every frame of the run, and ``arma-aic`` in the printed line and the saved file."""
    config_file = tmp_path / "small.toml"
    save_config(cfg, config_file)
    validations = []
    from_name = LoopPredictor.from_name.__func__

    def counting_from_name(klass, name):
        validations.append(name)
        return from_name(klass, name)

    monkeypatch.setattr(LoopPredictor, "from_name", classmethod(counting_from_name))
    forecasters = []
    update = ARMAPredictor.update

    def recording_update(self, x):
        forecasters.append(id(self))
        return update(self, x)

    monkeypatch.setattr(ARMAPredictor, "update", recording_update)
    out = tmp_path / "run.h5"
    assert main(["run", "--config", str(config_file), "--duration", str(DURATION), "--seed",
                 "3", "--predictor", "arma-aic", "--out", str(out), "--quiet"]) == 0
    assert validations == ["arma-aic"]  # checked once, on the way in
    n_frames = round(DURATION / cfg.loop.time_step)
    assert len(forecasters) == n_frames and len(set(forecasters)) == 1  # one fitted ARMA
    assert capsys.readouterr().out.startswith("arma-aic: SR peak")
    assert SimulationResult.load(out).predictor == "arma-aic"
    with h5py.File(out, "r") as f:
        assert f.attrs["predictor"] == "arma-aic"
