"""Runs sharing one LoopModel take turns (adversarial round 9, row c-thr-shared-model).

Reference: the serial runs. Two threads running one model at once wrote the same science
planes, and a 256-pixel loop's Strehl ratios came out up to 0.015 off without a word; a
run now holds its model (``LoopModel.running``). The test stops run A inside its callback
and starts run B on the same model: B must not reach its first frame until A ends (before
the fix it did at once), and both must equal the serial runs bit for bit. A run started
from a callback of a run of the same model is refused (it would wait for itself).
"""

import threading

import numpy as np
import pytest

from closedloop import LoopModel, simulate

from .conftest import lag_only


def test_a_second_run_waits_for_the_first_and_both_are_right():
    cfg = lag_only()
    model = LoopModel(cfg)
    serial = [simulate(cfg, 0.01, seed=s).strehl for s in (0, 1)]
    a_inside, a_go, b_started = threading.Event(), threading.Event(), threading.Event()
    out = {}

    def hold(k):
        if k == 2:
            a_inside.set()
            a_go.wait(30)

    def run_a():
        out["a"] = simulate(cfg, 0.01, seed=0, model=model, callback=hold).strehl

    def run_b():
        out["b"] = simulate(cfg, 0.01, seed=1, model=model,
                            callback=lambda k: b_started.set()).strehl

    ta = threading.Thread(target=run_a)
    ta.start()
    assert a_inside.wait(30)
    tb = threading.Thread(target=run_b)
    tb.start()
    overlapped = b_started.wait(1.0)  # a working lock never lets B in: no timing on pass
    a_go.set()
    ta.join(60)
    tb.join(60)
    assert not overlapped
    assert np.array_equal(out["a"], serial[0]) and np.array_equal(out["b"], serial[1])


def test_a_run_from_a_callback_of_the_same_model_is_refused():
    cfg = lag_only()
    model = LoopModel(cfg)

    def nested(k):
        if k == 1:
            simulate(cfg, 0.005, seed=0, model=model)

    with pytest.raises(ValueError, match="`model` is in use"):
        simulate(cfg, 0.01, seed=0, model=model, callback=nested)
    # and the model is free again
    assert np.array_equal(simulate(cfg, 0.01, seed=0, model=model).strehl,
                          simulate(cfg, 0.01, seed=0).strehl)
