"""The MI convergence rule and ``ordering_stability`` catch warnings under the lock.

Round 40 PART a, T23 / T25. Reference: Python's documented rule that
``warnings.catch_warnings`` is not thread-safe (it swaps the process-wide filter list and
puts back, on exit, the list it saw on entry), and the package's answer to it,
``modalinfo.common.quiet.catching_warnings`` (one process-wide lock). The convergence
rule (``information/convergence.py``, the four quarter estimates of a tied pair) and
``ordering_stability`` (``ordering/stability.py``, its orderings) used a bare
``catch_warnings``: a histogram MI of a tied pair in one thread and conditional-MI
intervals in another left ``ignore Warning`` and ``ignore BiasRuleWarning`` installed
for good (every later warning of the process lost), ``ordering_stability`` left
``ignore OrderingCostWarning``. Checked here without timing: while each block runs, its
thread holds the lock (another thread cannot take it), and a block of another thread
started meanwhile leaves the filters as they were.
"""

import threading
import warnings

import numpy as np

from modalinfo.common import quiet
from modalinfo.information import convergence
from modalinfo.ordering import stability


def _lock_free_elsewhere() -> bool:
    """Whether a thread other than the caller can take the package's warnings lock now."""
    got = []

    def probe():
        ok = quiet._LOCK.acquire(blocking=False)
        if ok:
            quiet._LOCK.release()
        got.append(ok)

    t = threading.Thread(target=probe)
    t.start()
    t.join(30)
    return got[0]


def test_convergence_quarters_hold_the_warnings_lock():
    rng = np.random.default_rng(0)
    n = convergence.CONVERGENCE_MIN_SAMPLES
    x = np.round(rng.standard_normal(n) * 2)
    y = np.round(x + rng.standard_normal(n) * 2)
    seen = []

    def estimate(xq, yq):
        seen.append(_lock_free_elsewhere())
        return 0.1

    before = list(warnings.filters)
    convergence.convergence_rule(estimate, x, y, 0.1)
    assert seen and not any(seen)  # the quarters ran with the lock held
    assert list(warnings.filters) == before


def test_ordering_stability_holds_the_warnings_lock(monkeypatch):
    from modalinfo.bases import Pupil, ZernikeBasis

    rng = np.random.default_rng(1)
    coeffs = rng.standard_normal((1200, 6)) * np.linspace(1.0, 0.2, 6)
    basis = ZernikeBasis(Pupil(16), range(2, 8))
    seen = []
    real = stability._orders

    def spy(*args, **kwargs):
        seen.append(_lock_free_elsewhere())
        return real(*args, **kwargs)

    monkeypatch.setattr(stability, "_orders", spy)
    before = list(warnings.filters)
    stability.ordering_stability(coeffs, basis, "variance", window=400)
    assert seen == [False]
    assert list(warnings.filters) == before
