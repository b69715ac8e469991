"""The package's warning-catching blocks follow each other (round 9, t-thr-*-filters).

Reference: Python's documented rule that ``warnings.catch_warnings`` is not thread-safe
(it swaps the process-wide filter list). Four threads computing BCa intervals left
"ignore DegenerateDataWarning" installed for good, four fitting neural nets "always
ConvergenceWarning". Now such blocks hold one lock: a BCa interval started while the lock
is held does not finish until it is released (a working lock never lets it through, so
the 1 s wait only bounds a failure), and concurrent intervals leave the filters as they
were.
"""

import threading
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from modalinfo.common.quiet import catching_warnings
from modalinfo.information import mutual_information_ci


def _bca(seed: int):
    rng = np.random.default_rng(seed)
    x, y = rng.multivariate_normal([0, 0], [[1, 0.6], [0.6, 1]], 300).T
    return mutual_information_ci(x, y, interval="bca", bootstrap="iid", n_resamples=40,
                                 seed=seed)


def test_blocks_take_turns_and_filters_survive_threads():
    _bca(0)  # compile and import first
    done = threading.Event()
    with catching_warnings():
        t = threading.Thread(target=lambda: (_bca(1), done.set()))
        t.start()
        overlapped = done.wait(1.0)
    t.join(60)
    assert not overlapped and done.is_set()
    before = list(warnings.filters)
    with ThreadPoolExecutor(4) as pool:
        list(pool.map(lambda i: [_bca(i) for _ in range(3)], range(4)))
    assert list(warnings.filters) == before
