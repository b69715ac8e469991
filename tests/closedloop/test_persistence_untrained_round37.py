"""Persistence fits nothing: no reference run, and ``--train-seed`` refused with it.

Round 37 PART b, CL01 / CL02: ``closedloop run --predictor persistence --train-seed 3``
and ``compare --predictors none,persistence --train-seed 3`` ran, their HDF5 results
bit-equal for seeds 3 and 7, because ``LoopPredictor.from_name`` gave persistence
``training=REFERENCE_POL`` (a pointless reference run), so the refusal of an unused
``--train-seed`` counted it as trained.

References: the definition of persistence, ``x_hat[n + h] = x[n]`` (mean 0, one AR
coefficient 1, no MA term, whatever the data), and the run as it was made before this
fix: a ``PersistencePredictor`` fitted on the POL of the no-prediction run (the
reference run ``run_trained`` made for it), compared bit for bit.
"""

import numpy as np
import pytest

from closedloop import LoopModel, simulate
from closedloop.cli import main
from closedloop.control.predictors import LoopPredictor, training_data
from closedloop.training import run_trained
from modalinfo.forecast import PersistencePredictor

from .conftest import small


def test_persistence_needs_no_training_and_is_ready_for_any_mode_count():
    spec = LoopPredictor.from_name("persistence")
    assert spec.training is None and not spec.needs_training and not spec.is_none
    assert repr(spec) == "LoopPredictor('persistence')"
    ready = spec.ready(5)
    assert ready.predictor.n_modes_ == 5 and spec.predictor is not ready.predictor
    params = ready.predictor.params_
    np.testing.assert_array_equal(params["mu"], np.zeros(5))
    np.testing.assert_array_equal(params["phi"], np.ones((5, 1)))
    assert params["theta"].shape == (5, 0)
    assert ready.ready(7) is ready  # fitted: kept as it is


@pytest.mark.parametrize("argv", [
    ["run", "--preset", "kaos", "--duration", "0.005", "--predictor", "persistence",
     "--train-seed", "3", "--quiet"],
    ["compare", "--preset", "kaos", "--duration", "0.005", "--predictors",
     "none,persistence", "--train-seed", "3", "--quiet"],
])
def test_train_seed_with_persistence_is_refused(argv, capsys):
    assert main(argv) == 2  # before: the runs went ahead
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    assert "--train-seed 3" in err and "persistence" in err and "trained" in err


def test_persistence_run_is_the_run_fitted_on_the_reference_bit_for_bit():
    cfg = small()
    model = LoopModel(cfg)
    reference = simulate(cfg, 0.1, seed=5, model=model, progress=False)
    before = simulate(cfg, 0.1, seed=5, model=model, progress=False,
                      predictor=PersistencePredictor().fit(training_data(reference)))
    now = run_trained(cfg, "persistence", 0.1, seed=5, model=model, progress=False)
    assert now.predictor == "persistence"
    np.testing.assert_array_equal(now.residual_variance, before.residual_variance)
    for name, log in before.logs.items():
        np.testing.assert_array_equal(now.logs[name].coeffs, log.coeffs)
