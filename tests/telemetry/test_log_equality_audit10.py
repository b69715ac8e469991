"""A ModalLog equals its copies and round trips (audit 10-state, rows SimulationResult-eq-*).

References: round trips (pickle, ``copy.deepcopy``, an NPZ file written and read back)
must give an equal log, and a log differing in one coefficient, the rate or a mode must
compare unequal; Python's data model for ``==`` with foreign types (False, no error) and
for hashing (objects equal by value whose data may change are unhashable). Before the
fix a log compared by identity, so ``SimulationResult`` (whose ``logs`` hold ModalLogs)
was unequal to its own deep copy and pickle.
"""

import copy
import pickle

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def log():
    return ModalLog(np.random.default_rng(2).standard_normal((50, 3)), rate=100.0,
                    modes=[2, 3, 4], metadata={"site": "x"})


def test_round_trips_are_equal(log, tmp_path):
    assert log == pickle.loads(pickle.dumps(log))
    assert log == copy.deepcopy(log)
    assert log == copy.copy(log)
    save(log, tmp_path / "a.npz")
    assert load(tmp_path / "a.npz") == log
    assert not (log != copy.deepcopy(log))


def test_different_logs_are_unequal(log):
    c = np.array(log.coeffs)
    c[7, 1] = np.nextafter(c[7, 1], np.inf)  # one ulp in one value
    assert log != ModalLog(c, rate=100.0, modes=[2, 3, 4], metadata={"site": "x"})
    assert log != ModalLog(log.coeffs, rate=101.0, modes=[2, 3, 4], metadata={"site": "x"})
    assert log != ModalLog(log.coeffs, rate=100.0, modes=[2, 3, 5], metadata={"site": "x"})
    assert log != ModalLog(log.coeffs, rate=100.0, modes=[2, 3, 4])
    assert (log == 3) is False and (log == None) is False  # noqa: E711


def test_unhashable(log):
    with pytest.raises(TypeError, match="unhashable"):
        hash(log)

