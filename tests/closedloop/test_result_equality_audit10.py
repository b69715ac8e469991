"""A SimulationResult equals its round trips (audit 10-state, rows SimulationResult-eq-*).

Reference: round trips (``copy.deepcopy``, pickle) must compare equal and another seed's
run unequal. The result's ``logs`` hold ModalLogs, which compared by identity before
the fix, so ``r == copy.deepcopy(r)`` was False.
"""

import copy
import pickle

from closedloop import simulate

from .conftest import lag_only


def test_simulation_result_equals_its_round_trips():
    r = simulate(lag_only(), 0.02, seed=0)
    assert r == copy.deepcopy(r)
    assert r == pickle.loads(pickle.dumps(r))
    assert r != simulate(lag_only(), 0.02, seed=1)
