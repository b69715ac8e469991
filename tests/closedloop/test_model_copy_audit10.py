"""A shallow copy of a LoopModel takes turns with the original (audit 10-state).

Reference: serial runs, each with a model of its own. ``copy.copy`` shares the model's
work arrays (the science planes); before the fix it had a lock of its own, so a run of
the copy and one of the original in two threads wrote the same planes at once (row
copy-loopmodel-threads: Strehl ratios off the serial ones without a word).
"""

import copy
import pickle
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from closedloop import LoopModel, simulate

from .conftest import lag_only


def test_original_and_shallow_copy_in_two_threads_match_serial_runs():
    cfg = lag_only()
    serial = [simulate(cfg, 0.03, seed=s).strehl for s in range(2)]
    model = LoopModel(cfg)
    twin = copy.copy(model)
    with ThreadPoolExecutor(2) as pool:
        for _ in range(3):
            runs = list(pool.map(lambda a: simulate(cfg, 0.03, seed=a[0], model=a[1]).strehl,
                                 [(0, model), (1, twin)]))
            for a, b in zip(serial, runs, strict=True):
                assert np.array_equal(a, b)


def test_deep_copies_and_pickles_run_alone():
    cfg = lag_only()
    model = LoopModel(cfg)
    for other in (copy.deepcopy(model), pickle.loads(pickle.dumps(model))):
        assert np.array_equal(simulate(cfg, 0.02, seed=4, model=other).strehl,
                              simulate(cfg, 0.02, seed=4).strehl)
