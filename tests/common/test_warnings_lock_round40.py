"""The MI convergence rule and ``ordering_stability`` install no process-wide filter.

Round 40 PART a, T23 / T25. Reference: Python's documented rule that
``warnings.catch_warnings`` is not thread-safe (it swaps the process-wide filter list and
puts back, on exit, the list it saw on entry), and the package's answer to it,
``modalinfo.common.quiet.catching_warnings`` (one process-wide lock). The convergence
rule (``information/convergence.py``, the four quarter estimates of a tied pair) and
``ordering_stability`` (``ordering/stability.py``, its orderings) used a bare
``catch_warnings``: a histogram MI of a tied pair in one thread and conditional-MI
intervals in another left ``ignore Warning`` and ``ignore BiasRuleWarning`` installed
for good (every later warning of the process lost), ``ordering_stability`` left
``ignore OrderingCostWarning``. Checked here without timing: while the quarters run,
no filter is installed and no lock held (round 40 T24: they run in ``quiet.quiet()``,
a flag of their own thread; before T24 they held the lock); ``ordering_stability`` now
changes no filter at all (a thread-local flag silences its own orderings' cost check,
and another thread's check still warns).
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


def test_convergence_quarters_change_no_filter_and_take_no_lock():
    """T23, then T24: the quarters now run in ``quiet()`` (a flag of their thread), with
    no filter and no lock (tests/information/test_quiet_quarters_round40.py)."""
    rng = np.random.default_rng(0)
    n = convergence.CONVERGENCE_MIN_SAMPLES
    x = np.round(rng.standard_normal(n) * 2)
    y = np.round(x + rng.standard_normal(n) * 2)
    seen = []
    before = list(warnings.filters)

    def estimate(xq, yq):
        seen.append((_lock_free_elsewhere(), quiet.is_quiet(), list(warnings.filters) == before))
        return 0.1

    convergence.convergence_rule(estimate, x, y, 0.1)
    assert seen and all(s == (True, True, True) for s in seen)
    assert list(warnings.filters) == before and not quiet.is_quiet()


def test_ordering_stability_changes_no_filter_and_silences_only_its_thread(monkeypatch):
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.ordering import cost

    rng = np.random.default_rng(1)
    coeffs = rng.standard_normal((1200, 6)) * np.linspace(1.0, 0.2, 6)
    basis = ZernikeBasis(Pupil(16), range(2, 8))
    before = list(warnings.filters)
    seen = []
    real = stability._orders

    def note(caught):
        # an hour's estimate: OrderingCostWarning unless the thread's run is judged
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            cost.check_ordering_seconds(3000.0, "x is estimated at 3000 s", "y", None)
        caught.append(len(got))

    def spy(*args, **kwargs):
        seen.append(list(warnings.filters) == before)  # no temporary process-wide filter
        here, other = [], []
        note(here)
        t = threading.Thread(target=note, args=(other,))
        t.start()
        t.join(30)
        seen.append((here, other))
        return real(*args, **kwargs)

    monkeypatch.setattr(stability, "_orders", spy)
    stability.ordering_stability(coeffs, basis, "variance", window=400)
    assert seen == [True, ([0], [1])]
    assert list(warnings.filters) == before
