"""The selection's surrogates are built on the documented parts (review34, round 34).

``selection._greedy_search`` (fix51-a) tests each next candidate against rotations of its
residual on the inputs already chosen, keeping its fit: the linear least-squares fit plus,
at each row, a least-squares line through its residual over the row's 20 nearest other
rows of the chosen inputs (fix51-d; neighbours in the maximum norm, on normal scores for
a rank-based estimator, on unit-s.d. values otherwise; the line on unit-s.d. values,
fix52-c). References, outside the package: numpy's
``lstsq`` fit, brute-force maximum-
norm neighbours on ``scipy.special.ndtri(scipy.stats.rankdata / (n + 1))`` scores or on
values over their s.d., ``numpy.roll``. The "estimator" is the test's own recording
statistic (``|corr(y, x)|``), so every candidate the search hands it is seen; one
candidate is chosen first (``tanh`` of the target's driver), then the second step's
surrogates of the other two are compared. Seeded data (n = 300, a heavy-tailed candidate 0
so that scores and values pick different neighbours): deterministic.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information.selection import _greedy_search

from .test_map_surrogate_parts_review34 import _local_line, _near


@pytest.mark.parametrize("rank_based", [True, False])
def test_the_second_steps_surrogates_are_fit_plus_rotated_local_residual(rank_based):
    rng = np.random.default_rng(34)
    n = 300
    c0 = np.sinh(2.0 * rng.standard_normal(n))
    C = np.column_stack([c0, np.tanh(c0) + 0.3 * rng.standard_normal(n),
                         rng.standard_normal(n)])
    y = np.arcsinh(c0) + 0.1 * rng.standard_normal(n)
    calls = []

    def est(yy, x, z):
        calls.append((x[:, 0].copy(), z.shape[1]))
        return abs(float(np.corrcoef(yy[:, 0], x[:, 0])[0, 1]))

    cu = (C - C.mean(axis=0)) / np.linalg.norm(C - C.mean(axis=0), axis=0)
    shifts = np.array([41, 97, 150, 203])
    picked, _, _ = _greedy_search(y, C, cu, np.ones(3, bool), method="histogram", est=est,
                                  factor=1.0, alpha=0.5, n_surrogates=shifts.size,
                                  max_inputs=2, shift0=None,
                                  rng=np.random.default_rng(0), shifts=shifts,
                                  rank_based=rank_based)
    second = [x for x, dz in calls if dz == 1]
    assert second, "the search stopped before its second step"
    first = picked[0][0]  # the input chosen first (an input, not an intermediate)
    z = C[:, [first]]
    near = _near(z, rank_based)
    a = np.column_stack([np.ones(n), z])
    want = []
    for j in sorted({0, 1, 2} - {first}):
        cj = C[:, j : j + 1]
        lin = a @ np.linalg.lstsq(a, cj, rcond=None)[0]
        local = _local_line(cj - lin, z, near)
        fit, resid = lin + local, cj - lin - local
        want += [(fit + np.roll(resid, int(s), axis=0))[:, 0] for s in shifts]
    got = second[2:]  # the two candidates' gains come first
    assert len(got) == len(want)
    # normal equations against lstsq on near-collinear neighbours: 2e-9 measured
    for w in want:  # the order of the calls is the search's: match each surrogate
        assert min(np.max(np.abs(g - w)) for g in got) < 1e-7


def test_the_third_steps_surrogates_condition_on_both_chosen_inputs():
    # two inputs chosen: the neighbours are those of the pair (maximum norm on unit-s.d.
    # values: continuous, so no tied distance, which the scores' grid can make)
    rng = np.random.default_rng(35)
    n = 300
    a0, a1 = rng.standard_normal(n), np.sinh(1.5 * rng.standard_normal(n))
    C = np.column_stack([a0, a1, a0 * a1 + 0.5 * rng.standard_normal(n),
                         rng.standard_normal(n)])
    y = a0 + np.arcsinh(a1) + 0.1 * rng.standard_normal(n)
    calls = []

    def est(yy, x, z):
        calls.append((x[:, 0].copy(), z.shape[1]))
        return abs(float(np.corrcoef(yy[:, 0], x[:, 0])[0, 1])) + 0.1 * z.shape[1]

    cu = (C - C.mean(axis=0)) / np.linalg.norm(C - C.mean(axis=0), axis=0)
    shifts = np.array([41, 97, 150])
    picked, _, _ = _greedy_search(y, C, cu, np.ones(4, bool), method="histogram", est=est,
                                  factor=1.0, alpha=0.5, n_surrogates=shifts.size,
                                  max_inputs=3, shift0=None, rng=np.random.default_rng(0),
                                  shifts=shifts, rank_based=False)
    third = [x for x, dz in calls if dz == 2]
    assert len(picked) >= 2 and third, "the search stopped before its third step"
    chosen = [picked[0][0], picked[1][0]]
    z = C[:, chosen]
    near = _near(z, False)
    a = np.column_stack([np.ones(n), z])
    want = []
    rest = sorted(set(range(4)) - set(chosen))
    for j in rest:
        cj = C[:, j : j + 1]
        lin = a @ np.linalg.lstsq(a, cj, rcond=None)[0]
        local = _local_line(cj - lin, z, near)
        want += [(lin + local + np.roll(cj - lin - local, int(s), axis=0))[:, 0]
                 for s in shifts]
    got = third[len(rest):]
    assert len(got) == len(want)
    for w in want:
        assert min(np.max(np.abs(g - w)) for g in got) < 1e-7
