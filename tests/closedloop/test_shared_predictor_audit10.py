"""A fitted predictor given to several runs at once (audit 10-state, row thr-sim-shared-pred).

References: serial runs, each with its own freshly fitted predictor (the same fit: same
samples, same bits), and a second predictor fitted and fed alike for the caller's own
stream. Before the fix runs in three threads sharing one predictor interleaved its
``update`` calls (Strehl ratios off the serial ones without a word), and ``simulate``
left the caller's online stream advanced.
"""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from closedloop import simulate
from modalinfo.forecast import ARMAPredictor

from .conftest import lag_only

# the simulator's pseudo-open-loop modes are smooth: Yule-Walker's AR(2) fits them 2.0-2.3x
# worse than least squares in sample (4.5-4.9x out of sample over 1 s), which ``fit`` now
# says (fixes 41-b); this file tests the threads, not the fit
pytestmark = pytest.mark.filterwarnings("ignore:ARMAPredictor.fit. the Yule-Walker fit")


@pytest.fixture(scope="module")
def pol():
    return simulate(lag_only(), 0.2, seed=0).logs["dm0.pol"].coeffs


def _fitted(pol):
    return ARMAPredictor(order=(2, 0), horizon=2).fit(pol)


def test_runs_sharing_one_predictor_match_serial_runs(pol):
    cfg = lag_only()
    serial = [simulate(cfg, 0.05, seed=s, predictor=_fitted(pol)).strehl for s in range(3)]
    shared = _fitted(pol)
    with ThreadPoolExecutor(3) as pool:
        threaded = list(pool.map(lambda s: simulate(cfg, 0.05, seed=s, predictor=shared).strehl,
                                 range(3)))
    for a, b in zip(serial, threaded, strict=True):
        assert np.array_equal(a, b)


def test_a_run_leaves_the_callers_stream(pol):
    p, untouched = _fitted(pol), _fitted(pol)
    for q in (p, untouched):
        q.reset()
        for frame in pol[:10]:
            q.update(frame)
    simulate(lag_only(), 0.05, seed=1, predictor=p)
    for frame in pol[10:30]:
        assert np.array_equal(p.update(frame), untouched.update(frame))
