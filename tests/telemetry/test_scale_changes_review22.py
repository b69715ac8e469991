"""The per-mode scale rule's law and its Bonferroni count, and the spread at a split.

Issue 27, review22 (docs/MUTATION.md, "Planted bugs, round 22"): a Bonferroni count
without the modes (Q1), a sampling constant 16 % off (Q2) and the effective values of a
mean in place of a variance's (V2) passed tests/telemetry. References (outside the code):

- the sampling law of the log mean absolute deviation of ``n`` Gaussian values: sd
  ``sqrt(var|Z|) / E|Z| / sqrt(n) = sqrt(pi / 2 - 1) / sqrt(n)`` (E|Z| = sqrt(2 / pi)),
  checked by a numpy Monte Carlo (32,000 blocks: relative standard error of the sd 0.4 %,
  the bound 3 %);
- the range of ``k`` independent standard Gaussians, ``scipy.stats.studentized_range``
  with infinite degrees of freedom; Bonferroni's cut ``alpha / J`` over the judged
  (block size, mode) pairs, counted by hand;
- Bartlett (1946): the sample variance of an AR(1) series with lag-1 ``r`` has the
  variance of ``n (1 - r^2) / (1 + r^2)`` independent values; the MAD's relative sampling
  sd ``1.1662 / sqrt(n)``; the F law of ``scipy.stats.f`` - the documented rule of
  ``spread_at_split`` computed by hand with numpy medians and ``numpy.corrcoef``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from modalinfo._stats import (
    MEANAD_REL_SD,
    SCALE_CHANGE_ALPHA,
    block_mean_deviations,
    judge_scale_changes,
    spread_at_split,
)


def test_log_mean_deviation_sd_is_the_gaussian_law():
    e = np.random.default_rng(0).standard_normal((1600, 4000))
    sc = block_mean_deviations(e, 8)  # 8 blocks of 200 values, 4000 columns
    measured = np.log(sc).std() * math.sqrt(200)
    assert measured == pytest.approx(math.sqrt(math.pi / 2 - 1), rel=0.03)
    assert MEANAD_REL_SD == pytest.approx(measured, rel=0.03)


def _table(m: int, jumps: dict[int, float], blocks: int = 8) -> dict:
    """Block scales 1 except one block of each column in ``jumps`` (its log range)."""
    sc = np.ones((blocks, m))
    for j, w in jumps.items():
        sc[3, j] = math.exp(w)
    return {blocks: sc}


EFFECTIVE = 800.0  # 100 effective innovations per block of 1/8
SPREAD = math.sqrt(math.pi / 2 - 1) / math.sqrt(EFFECTIVE / 8)


@pytest.mark.parametrize("w", [6.0, 7.0, 8.5])
def test_p_value_is_the_studentized_range_tail(w):
    found, judged = judge_scale_changes(_table(1, {0: w * SPREAD}), np.array([0]), 1600,
                                        EFFECTIVE, alpha=1.0)
    assert judged == 1 and len(found) == 1
    col, b, ratio, block, p = found[0]
    assert (col, b, block) == (0, 8, 3)
    assert ratio == pytest.approx(math.exp(w * SPREAD), rel=1e-12)
    assert p == pytest.approx(stats.studentized_range.sf(w, 8, np.inf), rel=1e-5)


@pytest.mark.parametrize("q,named", [(1e-4, False), (2e-6, True)])
def test_bonferroni_counts_every_judged_mode(q, named):
    # 50 modes judged at one block size: cut 0.1 % / 50 = 2e-5; a mode at p = 1e-4 is
    # below the per-size 0.1 % but not below the cut (ratio 1.64 / 1.78 > 1.5 both)
    m = 50
    w = stats.studentized_range.isf(q, 8, np.inf)
    found, judged = judge_scale_changes(_table(m, {7: w * SPREAD}), np.arange(m), 1600,
                                        EFFECTIVE)
    assert judged == m
    assert math.exp(w * SPREAD) > 1.5
    assert [f[0] for f in found] == ([7] if named else [])
    assert SCALE_CHANGE_ALPHA / m == pytest.approx(2e-5)


def _ar1(rng, n: int, rho: float, m: int) -> np.ndarray:
    e = rng.standard_normal((n + 2000, m))
    x = np.empty_like(e)
    x[0] = e[0]
    for t in range(1, e.shape[0]):
        x[t] = rho * x[t - 1] + math.sqrt(1 - rho * rho) * e[t]
    return x[2000:]


def test_spread_at_split_p_value_by_hand():
    # AR(1) 0.9 modes whose spread doubles at frame 3000 of 6000 (two of four modes)
    rng = np.random.default_rng(4)
    x = _ar1(rng, 6000, 0.9, 4)
    x[3000:, :2] *= 2.0
    found, judged = spread_at_split(x, 3000)
    assert judged == 4 and [v.column for v in found] == [0, 1]
    for v in found:
        sides = (x[:3000, v.column], x[3000:, v.column])
        mad = [np.median(np.abs(s - np.median(s))) for s in sides]
        nu = []
        for s in sides:
            r = min(max(np.corrcoef(s[:-1], s[1:])[0, 1], 0.0), 0.999)
            nu.append(s.size * (1 - r * r) / (1 + r * r) / (2 * 1.1662 ** 2))
        f = (mad[1] / mad[0]) ** 2
        p = min(1.0, 2 * min(stats.f.sf(f, nu[1], nu[0]), stats.f.cdf(f, nu[1], nu[0])))
        assert v.frame == 3000
        assert v.ratio == pytest.approx(mad[1] / mad[0], rel=1e-12)
        assert v.p_value == pytest.approx(p, rel=0.02)
