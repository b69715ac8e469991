"""Percentile bounds are exceeded as often as their level states (leftovers 12-est, issue 27).

Reference (outside the code): the order-statistic law of exchangeable draws. Of R
replicates and one new draw from the same continuous law, the new one falls below the
j-th smallest replicate with probability exactly j / (R + 1) (Davison & Hinkley 1997,
sec. 5.2.3); for a uniform parent, below ``(1 - f) X_(j) + f X_(j+1)`` with probability
``(j + f) / (R + 1)`` (E X_(j) = j / (R + 1)). The bound at the (1 - L) / 2 quantile is
therefore exceeded with probability (1 - L) / 2 when it is the order statistic of rank
``(1 - L) / 2 (R + 1)`` (type-6, Weibull plotting positions; Hyndman & Fan 1996). numpy's
default linear quantile (type 7) takes rank ``1 + (1 - L) / 2 (R - 1)``: at R = 40 and
L = 0.95 rank 1.975, exceeded with probability 1.975 / 41 = 0.048 per side, which is
what mutual_information_ci's percentile / basic intervals and order_modes' bounds did
before. The Monte Carlo rate over 40,000 trials has sd sqrt(p (1 - p) / 40000) =
0.0008 at p = 0.025; the assertion allows 4 sd.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import mutual_information_ci
from modalinfo.information.resampling import percentile_bounds
from modalinfo.ordering import orderings

TRIALS = 40_000


def _exact_exceedance(r: int, level: float) -> float:
    """Probability that a new uniform draw falls below the type-6 lower bound of R."""
    rank = (1.0 - level) / 2.0 * (r + 1)
    j = min(max(math.floor(rank), 1), r - 1)
    f = min(max(rank - j, 0.0), 1.0)
    return (j + f) / (r + 1)


@pytest.mark.parametrize(("r", "level"), [(40, 0.95), (39, 0.95), (20, 0.9), (100, 0.9)])
def test_exceedance_of_each_bound_is_the_order_statistic_probability(r, level):
    rng = np.random.default_rng(1234 + r)
    reps = rng.random((r, TRIALS))
    new = rng.random(TRIALS)
    low, high = percentile_bounds(reps, level, axis=0)
    p = _exact_exceedance(r, level)
    assert p == pytest.approx((1.0 - level) / 2.0, abs=1e-12)  # the level itself
    sd = math.sqrt(p * (1 - p) / TRIALS)
    assert abs(np.mean(new < low) - p) < 4 * sd
    assert abs(np.mean(new > high) - p) < 4 * sd  # mirror: 1 - U is uniform too


def test_the_bounds_of_39_replicates_at_95_percent_are_their_extremes():
    reps = np.random.default_rng(5).standard_normal(39)
    low, high = percentile_bounds(reps, 0.95)
    assert float(low) == pytest.approx(reps.min(), rel=1e-12)
    assert float(high) == pytest.approx(reps.max(), rel=1e-12)


@pytest.mark.parametrize("interval", ["percentile", "basic"])
def test_mutual_information_ci_uses_the_order_statistics(interval):
    rng = np.random.default_rng(6)
    x = rng.standard_normal(400)
    y = 0.6 * x + 0.8 * rng.standard_normal(400)
    res = mutual_information_ci(x, y, method="gaussian", n_resamples=79, bootstrap="iid",
                                interval=interval, seed=1, confidence_level=0.95)
    d = np.sort(res.bootstrap_distribution)
    lo, hi = d[1], d[-2]  # ranks 0.025 * 80 = 2 and 78 of 79
    if interval == "basic":
        lo, hi = 2 * res.estimate - hi, 2 * res.estimate - lo
    assert res.low == pytest.approx(lo, abs=1e-15) and res.high == pytest.approx(hi, abs=1e-15)


def test_order_modes_bounds_are_the_order_statistics(monkeypatch):
    r, modes = 39, 4
    rng = np.random.default_rng(7)
    boot = [rng.standard_normal((r, modes)) for _ in range(3)]
    monkeypatch.setattr(orderings, "_bootstrap", lambda *a, **k: tuple(boot))
    a = rng.standard_normal((300, modes))
    matrix = np.linalg.qr(rng.standard_normal((50, modes)))[0] * math.sqrt(50)
    res = orderings.order_modes(a, matrix, "mi_marginal", estimator="gaussian", seed=0,
                                n_resamples=r, block_length=1, confidence_level=0.95)
    for name, b in zip(("mi", "gain", "margin"), boot, strict=True):
        # rank 0.025 * 40 = 1 to rounding (1e-16 of the next order statistic)
        np.testing.assert_allclose(getattr(res, f"{name}_low"), b.min(axis=0), rtol=1e-12)
        np.testing.assert_allclose(getattr(res, f"{name}_high"), b.max(axis=0), rtol=1e-12)
