"""``quality._grid_share``: the chance of a tie from a mode's grid step and density.

Reference: the docstring's law, chance ~ step * sum_k p_k^2 / w with ``p_k`` the exact
probability of bin ``k`` of width ``w`` (scipy.stats.norm for a Gaussian mode; the levels'
own frequencies for a DAC mode), ``w = max(step, sigma_MAD / 4)`` with scipy's
``median_abs_deviation(scale="normal")``; for fine bins ``sum p_k^2 / w -> int f^2 =
1 / (2 sqrt(pi) sigma)``. Stop 56 (stop 55's note: review 31b had no direct test of it).
"""

import math

import numpy as np
import pytest
from scipy import stats

from modalinfo.telemetry.quality import _grid_share


def _gaussian_reference(x: np.ndarray, step: float) -> float:
    w = max(step, stats.median_abs_deviation(x, scale="normal") / 4.0)
    k = np.arange(math.floor(-10.0 / w), math.ceil(10.0 / w) + 1)
    p = np.diff(stats.norm.cdf(np.append(k, k[-1] + 1) * w))
    return step * float(np.sum(p * p)) / w


@pytest.mark.parametrize("step", [1e-9, 1e-6, 1e-3])
def test_gaussian_mode_chance_follows_density(step):
    x = np.random.default_rng(56).standard_normal(200_000)
    got = _grid_share(x, step, np.dtype(np.float64))
    ref = _gaussian_reference(x, step)
    # sampling s.e. of a collision share in ~60 occupied bins at n = 2e5: < 1 %
    assert got == pytest.approx(ref, rel=0.03)
    # and the continuum law int f^2 = 1 / (2 sqrt(pi)) within the bins' curvature (w ~ 0.25)
    assert got == pytest.approx(step / (2.0 * math.sqrt(math.pi)), rel=0.05)


def test_dac_levels_chance_is_their_collision_probability():
    rng = np.random.default_rng(7)
    levels = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    prob = np.array([0.1, 0.2, 0.4, 0.2, 0.1])
    x = rng.choice(levels, size=100_000, p=prob)
    freq = np.array([(x == v).mean() for v in levels])
    got = _grid_share(x, 1.0, np.dtype(np.float64))
    assert got == pytest.approx(float(np.sum(freq * freq)), rel=1e-3)
    assert got == pytest.approx(float(np.sum(prob * prob)), abs=0.01)


def test_no_finite_pair_or_no_grid_is_certain_tie():
    assert _grid_share(np.array([1.0]), 1e-3, np.dtype(np.float64)) == 1.0
    assert _grid_share(np.array([1.0, np.nan]), 1e-3, np.dtype(np.float64)) == 1.0
    assert _grid_share(np.arange(10.0), math.inf, np.dtype(np.float64)) == 1.0
