"""Leftovers 14-misc (issue 27): the orderings' memory, and the stability run's time, before work.

References, from outside the code under test: numpy's own size of the float64 array the
ordering gathers (``np.empty((M, n)).nbytes``); the calls a real run makes, counted on
``order_modes`` (how many orderings a stability run makes: its windows plus its seeds);
the machine's usable memory replaced by a stated number (monkeypatched), so that the
refusal does not depend on the machine. No timing is asserted.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.common import memory
from modalinfo.information import MutualInformation
from modalinfo.ordering import cost, order_modes, ordering_stability
from modalinfo.ordering import orderings as orderings_module
from modalinfo.ordering import stability as stability_module
from modalinfo.ordering.cost import OrderingCostWarning, least_ordering_seconds


class _StopError(Exception):
    pass


def _no_work(monkeypatch):
    # the first work: the contributions of every mode at the samples, then the estimates
    def stop(*args, **kw):
        raise _StopError("the work started")

    monkeypatch.setattr(orderings_module, "_contributions", stop)
    monkeypatch.setattr(MutualInformation, "fit", stop)


def _big():
    # 1000 modes x 200 frames x 1000 pixels: 2e5 samples (the default budget), 1.6 GB
    rng = np.random.default_rng(2)
    return rng.standard_normal((200, 1000)), rng.standard_normal((1000, 1000))


def test_the_memory_estimate_is_numpys_size_of_the_contributions():
    for m, n in ((3, 10), (1000, 200_000), (7, 12_345)):
        one = np.empty((m, n)).nbytes if m * n < 10**6 else 8 * m * n  # float64
        # and the per-sample index and sum arrays (fixes 42, S16)
        per_sample = cost.PER_SAMPLE_ARRAYS * np.empty(n).nbytes
        assert cost.ordering_memory_bytes(m, n) == one + per_sample
        # with replicates: the ordering's, the previous replicate's and the new one
        assert cost.ordering_memory_bytes(m, n, n_resamples=1) == 3 * one + per_sample


def test_an_ordering_that_cannot_fit_is_refused_before_any_work(monkeypatch):
    # before: the library gathered 1.6 GB with no check of its own (the CLI had one)
    coeffs, basis = _big()
    _no_work(monkeypatch)
    monkeypatch.setattr(memory, "usable_memory_bytes", lambda: 1.0 * 2**30)
    with pytest.raises(ValueError, match=r"1000 modes on 200000 samples .* 1\.52 GiB .*"
                                         r"1 GiB is usable; use a smaller `sample_budget`"):
        order_modes(coeffs, basis, "mi_marginal", n_resamples=0, max_seconds=None, seed=0)
    # three copies with replicates (and the per-sample arrays): 4.5 GiB against 4 GiB
    monkeypatch.setattr(memory, "usable_memory_bytes", lambda: 4.0 * 2**30)
    with pytest.raises(ValueError, match=r"4\.5 GiB .*3 copies.*`n_resamples`=0"):
        order_modes(coeffs, basis, "mi_marginal", n_resamples=2, max_seconds=None, seed=0)


def test_an_ordering_that_fits_goes_on_to_the_work(monkeypatch):
    coeffs, basis = _big()
    _no_work(monkeypatch)
    monkeypatch.setattr(memory, "usable_memory_bytes", lambda: 2.0 * 2**30)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", OrderingCostWarning)  # its time: not this test's
        with pytest.raises(_StopError):
            order_modes(coeffs, basis, "mi_marginal", n_resamples=0, max_seconds=None, seed=0)


def _stability_case():
    rng = np.random.default_rng(5)
    coeffs = rng.standard_normal((40, 4)) / np.arange(1, 5)
    basis = rng.standard_normal((50, 4))
    return coeffs, basis


def test_the_stability_run_is_judged_on_all_its_orderings(monkeypatch):
    # 4 windows of 10 frames (500 samples) and 3 seeds on the whole log (2000 samples)
    coeffs, basis = _stability_case()
    one_window, _ = least_ordering_seconds("histogram", 500, 4, 0, 1, "mi_greedy")
    one_whole, _ = least_ordering_seconds("histogram", 2000, 4, 0, 1, "mi_greedy")
    total = 4 * one_window + 3 * one_whole
    made = []
    real = stability_module.order_modes
    monkeypatch.setattr(stability_module, "order_modes",
                        lambda *a, **k: made.append(1) or real(*a, **k))
    # before: each ordering was checked alone, under its own estimate: all ran
    limit = 0.99 * total
    assert limit > max(one_window, one_whole)
    with pytest.raises(ValueError, match=r"4 windows of 10 frames .* 3 seeds .* more than "
                                         r"`max_seconds`="):
        ordering_stability(coeffs, basis, window=10, sample_budget=2000, max_seconds=limit)
    assert made == []  # refused before any ordering
    res = ordering_stability(coeffs, basis, window=10, sample_budget=2000,
                             max_seconds=1.01 * total)
    assert len(made) == 4 + 3 == len(res.window_starts) + 3


def test_the_stability_run_warns_its_estimate_once(monkeypatch):
    # before: each ordering warned on its own (7 warnings here), or none at all
    coeffs, basis = _stability_case()
    monkeypatch.setattr(cost, "NOTE_ORDERING_SECONDS", 1e-12)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        ordering_stability(coeffs, basis, window=10, sample_budget=2000)
    costs = [w for w in got if issubclass(w.category, OrderingCostWarning)]
    assert len(costs) == 1
    assert "ordering_stability('mi_greedy'" in str(costs[0].message)
    assert "a longer `window` or fewer `seeds`" in str(costs[0].message)
    assert costs[0].filename == __file__  # said at the caller's line


def test_an_ordering_warns_with_its_own_class(monkeypatch):
    coeffs, basis = _stability_case()
    monkeypatch.setattr(cost, "NOTE_ORDERING_SECONDS", 1e-12)
    with pytest.warns(OrderingCostWarning, match=r"order_modes\('mi_greedy'"):
        order_modes(coeffs, basis, "mi_greedy", sample_budget=2000, n_resamples=0, seed=0)
