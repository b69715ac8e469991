"""The least-time rule counts the exhaustive search up to and including 64 modes.

Round 10 of planted bugs (review10). Reference, from outside
:mod:`modalinfo.ordering.cost`: the ``score`` calls a real ``order_modes(...,
"mi_greedy", search="auto")`` makes, counted by wrapping the estimator. At 64 modes
(``_EXHAUSTIVE_MAX_MODES``, documented "up to 64 modes") the search is exhaustive, so
the rule's count must be ``M (M + 1) / 2 - 1`` and the run may add only the swapped
rivals (at most ``M - 2``). Planted bug R10-C2 (the edge ``m <= 64`` moved to
``m < 64``) escaped tests/ordering/test_least_time_structure.py, which orders 6 and 20
modes: at 64 the rule counted the screened search's 246 estimates for ~2080 made.
"""

from __future__ import annotations

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.ordering.cost import least_ordering_calls
from modalinfo.telemetry.synthetic.spectra import Layer, open_loop_log

from .conftest import CountingMI


def test_sixty_four_modes_are_searched_exhaustively_and_counted_so():
    m = 64
    modes = range(2, m + 2)
    log = open_loop_log(modes, n_frames=30, rate=1000.0, diameter=4.0,
                        layers=[Layer(r0=0.1, wind_speed=10.0)], seed=10)
    est = CountingMI()
    order_modes(log, ZernikeBasis(Pupil(20), modes=modes), "mi_greedy", estimator=est,
                sample_budget=300, seed=0, n_resamples=0, search="auto")
    least = least_ordering_calls(m, "mi_greedy", "auto")
    assert least == m * (m + 1) // 2 - 1 == 2079
    assert 0 <= est.calls - least <= m - 2  # beyond: the swapped rivals at most
