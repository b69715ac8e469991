"""The seed of the run a predictor was trained on is in the result's record.

Round 39 PART b, C17 / C18: ``closedloop run --predictor linear --train-seed 3 --out r.h5``
kept the training atmosphere only inside the command line typed (``provenance["command"]``),
while ``--train-seed``'s own refusal says "(it is stored in the result)"; ``closedloop
info r.h5`` printed "seed 0, predictor linear", and a result of ``run_trained(...,
train_seed=3)`` from Python recorded no trace of it at all.

Reference: the reference run itself (``closedloop.simulate`` with the training seed,
fitted by hand with ``LoopPredictor.trained``): the recorded ``train_seed`` names the run
whose fit gives the same result bit for bit.
"""

import numpy as np

from closedloop import LoopModel, simulate
from closedloop.cli import main
from closedloop.control.predictors import LoopPredictor
from closedloop.result import SimulationResult
from closedloop.training import run_trained

from .conftest import small


def test_train_seed_is_recorded_and_names_the_reference_run(tmp_path, capsys):
    cfg = small()
    model = LoopModel(cfg)
    result = run_trained(cfg, "linear", 0.1, seed=5, train_seed=3, model=model,
                         progress=False)
    assert result.seed == 5 and result.provenance["train_seed"] == 3
    reference = simulate(cfg, 0.1, seed=3, model=model, progress=False)
    by_hand = simulate(cfg, 0.1, seed=5, model=model, progress=False,
                       predictor=LoopPredictor.from_name("linear").trained(reference))
    np.testing.assert_array_equal(result.residual_variance, by_hand.residual_variance)
    # the default: the same atmosphere, as in the paper
    same = run_trained(cfg, "linear", 0.1, seed=5, model=model, progress=False)
    assert same.provenance["train_seed"] == 5
    # nothing trained: no training seed claimed
    assert "train_seed" not in run_trained(cfg, "none", 0.1, seed=5, model=model,
                                           progress=False).provenance
    path = tmp_path / "r.h5"
    result.save(path)
    assert SimulationResult.load(path).provenance["train_seed"] == 3
    assert main(["info", str(path)]) == 0
    assert "seed 5, predictor linear (trained on seed 3)" in capsys.readouterr().out
