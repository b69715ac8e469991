"""Planted-bug review round 25 (review25, issue 27): persistence made ready without a
reference run (round 37 PART b, CL01 / CL02) and the seed bound of ``simulate`` (round
38 PART a, R72), where round 37 / 38's tests met only the loop without a control basis
and seeds above the bound.

References: the definition of persistence, ``x_hat[n + h] = x[n]`` on the values the
loop feeds it - with a ``control_basis`` of n columns, the n basis coefficients
(``_check_control_basis``' documented shape ``(n_modes, n)``), so the run equals one
with a ``PersistencePredictor`` fitted by hand on n columns; the HDF5 / int64 bound
``2**63 - 1`` (``closedloop.config.MAX_SEED``), itself a storable seed.
"""

import numpy as np

from closedloop import LoopModel, SimulationResult, simulate
from closedloop.config import MAX_SEED
from closedloop.control.predictors import LoopPredictor
from modalinfo.forecast import PersistencePredictor

from .conftest import small


def test_persistence_by_name_on_a_control_basis_is_the_hand_fitted_one():
    """R25-C1: 10 basis columns of 55 modes: persistence is readied for 10 values (its
    mode count the basis's columns, not its rows: the run was refused)."""
    cfg = small()
    model = LoopModel(cfg)
    basis = np.eye(model.n_modes)[:, :10]
    by_name = simulate(cfg, 0.01, seed=5, model=model, progress=False, control_basis=basis,
                       predictor=LoopPredictor.from_name("persistence"))
    by_hand = simulate(cfg, 0.01, seed=5, model=model, progress=False, control_basis=basis,
                       predictor=PersistencePredictor().fit(np.zeros((2, 10))))
    np.testing.assert_array_equal(by_name.residual_variance, by_hand.residual_variance)


def test_the_largest_storable_seed_runs_and_is_saved(tmp_path):
    """R25-C2: seed = 2**63 - 1, the bound itself, runs and its file stores it."""
    cfg = small()
    result = simulate(cfg, 0.005, seed=MAX_SEED, model=LoopModel(cfg), progress=False)
    assert result.seed == MAX_SEED
    result.save(tmp_path / "r.h5")
    assert SimulationResult.load(tmp_path / "r.h5").seed == MAX_SEED


def test_persistence_trained_on_a_reference_is_fitted_on_its_values():
    """R25-C3: ``trained(reference)`` of a persistence by name (what the compression
    study's RTC timing calls, with its basis) returns it fitted on the reference's
    values - every DM's modes, or the basis's n columns - not unfitted."""
    from closedloop.control.predictors import training_data

    cfg = small()
    model = LoopModel(cfg)
    reference = simulate(cfg, 0.1, seed=5, model=model, progress=False)  # past closure
    spec = LoopPredictor.from_name("persistence")
    assert spec.trained(reference).predictor.n_modes_ == training_data(reference).shape[1]
    basis = np.eye(model.n_modes)[:, :10]
    assert spec.trained(reference, basis=basis).predictor.n_modes_ == 10
    assert getattr(spec.predictor, "n_modes_", None) is None  # itself unchanged
