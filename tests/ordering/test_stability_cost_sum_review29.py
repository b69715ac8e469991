"""``ordering_stability``'s refusal states the windows' and the seeds' estimate in all (review29).

Round 29 K2 (modalinfo/ordering/stability.py:368): its docstring promises "one window's
ordering ... times the windows, plus the whole log's times the seeds"; planted to print
the windows' estimate alone (the refusal still judged the sum), it passed every test,
whose estimates rounded to 0 s either way. Here 20 seeds on the whole log weigh ten
times the 2 windows. Reference: the arithmetic the message states, its own counts (read
back from its text) put through ``cost.least_ordering_seconds`` and summed by hand.
"""

import re

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import cost, ordering_stability
from modalinfo.telemetry import ModalLog


def test_the_estimate_printed_is_windows_plus_seeds():
    basis = ZernikeBasis(Pupil(16), range(2, 42))
    log = ModalLog(np.random.default_rng(0).normal(size=(4000, 40)), rate=1000.0)
    with pytest.raises(ValueError, match="more than `max_seconds`") as exc:
        ordering_stability(log, basis, method="mi_marginal", window=2000,
                           seeds=tuple(range(20)), max_seconds=1e-9)
    text = str(exc.value)
    found = re.search(r"of (\d+) modes: (\d+) windows of \d+ frames \((\d+) samples per "
                      r"estimate\) and (\d+) seeds on the whole log \((\d+) samples\), at "
                      r"least (\d+) MI estimates, is estimated at (\d+) s of CPU", text)
    modes, n_windows, n_w, n_seeds, n_all, calls, shown = map(int, found.groups())
    assert (modes, n_windows, n_seeds) == (40, 2, 20)
    s_w, c_w = cost.least_ordering_seconds("histogram", n_w, modes, 0, n_windows,
                                           "mi_marginal", "auto")
    s_s, c_s = cost.least_ordering_seconds("histogram", n_all, modes, 0, n_seeds,
                                           "mi_marginal", "auto")
    assert calls == c_w + c_s
    assert shown == round(s_w + s_s) and round(s_w) != round(s_w + s_s)
