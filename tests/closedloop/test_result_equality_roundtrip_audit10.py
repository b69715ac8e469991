"""A SimulationResult saved and loaded compares equal to the run (audit 10, feedback, row
cl-save-load-eq).

Reference: the round trip ``SimulationResult.load(result.save(path))``, whose arrays and
logs are checked bit for bit here with numpy. Before, ``==`` was False because the logs
compared by identity.
"""

import numpy as np

from closedloop import SimulationResult, simulate

from .conftest import lag_only


def test_saved_and_loaded_run_is_equal(tmp_path):
    run = simulate(lag_only(), 0.01, seed=0)
    back = SimulationResult.load(run.save(tmp_path / "r.h5"))
    for key, log in run.logs.items():
        assert np.array_equal(back.logs[key].coeffs, log.coeffs)
    assert np.array_equal(back.strehl, run.strehl)
    assert back == run
