"""One KSG cost model for the selection's estimate and the orderings' lower bound.

References: the measured CPU times of the module notes of modalinfo.information.ksg and
modalinfo.ordering.cost (a pair at n = 1e4: 0.045-0.08 s; the orderings' MI 6.4 us per
sample at 1e4, 13.7 us at 4e5), and the law they were fitted to, written out here:
0.6 ms + 0.5e-6 n log2(n) (1 + n / 2e6) s per pair estimate (round 12; 1.25e-6 n log2(n) before), a
lower bound of 0.2e-6 n log2(n) (0.4e-6 before round 12). Both entry
points (``select_inputs``'s ``max_seconds`` and ``modalinfo reorder``'s hour) are
checked on both sides of their limits.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import pytest

from modalinfo.cli import CommandError
from modalinfo.cli.cmd_reorder import check_mi_time
from modalinfo.information.ksg import ksg_cost, ksg_seconds_per_sample
from modalinfo.information.selection import first_step_seconds, select_inputs
from modalinfo.ordering.cost import (
    MAX_ORDERING_SECONDS,
    MI_SECONDS_PER_CALL,
    MI_SECONDS_PER_SAMPLE,
)


@pytest.mark.parametrize("n", [10, 10_000, 400_000, 1_000_000])
def test_one_law_two_bounds(n):
    law = 0.5e-6 * math.log2(n) * (1 + n / 2e6)
    assert ksg_seconds_per_sample(n, 2) == pytest.approx(law, rel=1e-12)
    assert ksg_cost(n, 2)[0] == pytest.approx(6e-4 + n * law, rel=1e-12)
    assert MI_SECONDS_PER_SAMPLE["ksg"](n) == pytest.approx(0.2e-6 * math.log2(n), rel=1e-12)
    assert first_step_seconds("ksg", n, 3, 19) == pytest.approx(3 * 20 * (6e-4 + n * law),
                                                                rel=1e-12)


def test_lower_bound_below_and_estimate_near_the_measured_times():
    least = MI_SECONDS_PER_SAMPLE["ksg"]
    assert least(10_000) < 6.4e-6 and least(400_000) < 13.7e-6 and least(10**6) < 25e-6
    # the estimate: within a factor of 2 of a pair's 0.045-0.08 s at 1e4 (module notes)
    assert 0.08 / 2 < ksg_cost(10_000, 2)[0] < 0.045 * 2


class _Log:
    n_frames, n_modes = 400, 3


def _args(resamples):
    return argparse.Namespace(estimator="ksg", budget=1_000_000, frame=None,
                              pupil_pixels=64, resamples=resamples)


def test_reorder_refuses_at_the_same_hour():
    # 400 frames x 3216 pixels >= 1e6: n = 1e6 per estimate; calls = the greedy's
    # 3 + 2 (every mode left at each step) plus 2 M - 2 per bootstrap replicate (round
    # 10 PART b, B13; 2 M - 3 until leftovers 13-cost): 5 + 4 r for M = 3; each estimate
    # also costs the per-call term and the score's screens (0.25 ms + 1.5 ns n), and the
    # ordering and each replicate gather the 3 modes at the samples (1.5 ns each)
    per_call = MI_SECONDS_PER_CALL["ksg"] + 0.2e-6 * math.log2(1e6) * 1e6 + 2.5e-4 + 1.5e-3
    gather = 3 * 1e6 * 1.5e-9
    resamples_ok = int((MAX_ORDERING_SECONDS - 5 * per_call - gather) // (4 * per_call
                                                                           + gather))
    check_mi_time(_args(resamples_ok), _Log())
    with pytest.raises(CommandError, match="would take at least"):
        check_mi_time(_args(resamples_ok + 1), _Log())


def test_select_refuses_at_the_same_estimate(monkeypatch):
    from modalinfo.information import selection

    class RanError(Exception):
        pass

    def no_search(*args, **kwargs):
        raise RanError

    monkeypatch.setattr(selection, "_greedy_search", no_search)
    data = np.random.default_rng(0).standard_normal((400, 18))
    n = 400 - 3  # rows of 3 lags
    estimate = 54 * 200 * (6e-4 + 0.5e-6 * n * math.log2(n) * (1 + n / 2e6))
    with pytest.raises(ValueError, match="method='ksg' would take about"):
        select_inputs(data, target=0, max_lag=3, method="ksg", intervals=False,
                      max_seconds=estimate * 0.99)
    with pytest.raises(RanError):
        select_inputs(data, target=0, max_lag=3, method="ksg", intervals=False,
                      max_seconds=estimate * 1.01)
