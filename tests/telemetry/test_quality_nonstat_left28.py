"""The quality pass sees short seeing episodes, one-mode scale changes and a loop opening.

Issue 27, left28-nonstat (adversarial round 28 PART a N04 / N09 / N13 / N14, PART b N01).

References (outside the code under test):
- the tail of the range of ``k`` independent Gaussians, ``scipy.stats.studentized_range``
  with infinite degrees of freedom (Harter 1960's tables);
- planted non-stationarity with known truth, on stationary AR(1) logs of unit marginal
  variance built by ``scipy.signal.lfilter`` (burnt in): a seeing change x2.5 in scale
  ((15 / 5)^(5/6)) over a known 5 % of the frames, two modes exchanging AR(1) 0.99 / 0.9
  spectra at equal variance at a known frame (a wind-direction change), a loop opened at
  a known frame (rms x10, AR(1) 0.9 -> 0.999: round 28 PART b's generator), and a mean
  offset alone (spread unchanged by construction);
- stationary seeded logs, where the rules must stay silent: their false-alarm rates are
  measured in docs/ADVERSARIAL.md ("Leftovers 28-nonstat"); here a seeded handful, with
  the bound each assertion rests on stated.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, assess_quality


def _ar1(rng: np.random.Generator, t: int, rho: float, m: int) -> np.ndarray:
    """Stationary AR(1) columns of unit marginal variance (burnt in 3000 frames)."""
    e = rng.standard_normal((t + 3000, m))
    return lfilter([math.sqrt(1.0 - rho * rho)], [1.0, -rho], e, axis=0)[-t:]


@pytest.mark.parametrize("k", [8, 16, 32])
@pytest.mark.parametrize("w", [1.2, 3.0, 5.0, 6.5, 8.0])
def test_range_tail_is_scipys_studentized_range(k, w):
    from modalinfo._stats import range_sf

    ref = stats.studentized_range.sf(w, k, np.inf)
    assert range_sf(w, k) == pytest.approx(ref, rel=1e-6)


SCALE = 3.0 ** (5.0 / 6.0)  # r0 5 -> 15 cm: x2.5 in the modes' scale


@pytest.mark.parametrize("where", [slice(19000, 20000), slice(0, 1000), slice(9500, 10500)])
def test_a_seeing_episode_over_5_percent_is_seen(where):
    # round 28 PART a: stationary=True and 27-34 values called outliers before
    x = _ar1(np.random.default_rng(5), 20000, 0.95, 6)
    x[where] *= SCALE
    r = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 8))))
    assert r.stationary is False
    assert [s[0] for s in r.scale_steps] == [f"Z{j}" for j in range(2, 8)]
    for _, start, stop, ratio, _ in r.scale_steps:
        assert start < where.stop and stop > where.start  # the block overlaps the episode
        assert 1.5 < ratio < 1.1 * SCALE
    assert "the innovations' scale changes in 6 mode(s)" in r.note


def test_a_wind_direction_change_on_two_modes_is_seen():
    # Z2 and Z3 exchange AR(1) 0.99 / 0.9 spectra at frame 10,000 (equal variance): the
    # median over the 6 modes stayed 1.09 and stationary=True (round 28 PART a, N09)
    rng = np.random.default_rng(5)
    x = _ar1(rng, 20000, 0.95, 6)
    slow, fast = _ar1(rng, 20000, 0.99, 2), _ar1(rng, 20000, 0.9, 2)
    x[:, 0] = np.r_[slow[:10000, 0], fast[10000:, 0]]
    x[:, 1] = np.r_[fast[:10000, 1], slow[10000:, 1]]
    r = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 8))))
    assert r.scale_ratio < 1.5  # the median rule alone would not see it
    assert r.stationary is False
    assert [s[0] for s in r.scale_steps] == ["Z2", "Z3"]
    # innovations sd sqrt(1 - 0.9^2) / sqrt(1 - 0.99^2) = 3.09 for the same variance
    assert all(2.5 < s[3] < 4.0 for s in r.scale_steps)


@pytest.mark.parametrize("rho,t,m", [(0.995, 2500, 10)])
def test_stationary_logs_stay_silent(rho, t, m):
    # the cell of left28-shift's firing test (about 310 effective innovations
    # per block of 1/8): at a family-wise 0.1 % per log the expected count over 12 logs
    # is 0.012 (P(>= 1) 1.2 %); measured over 200 seeds per cell: docs/ADVERSARIAL.md
    rng = np.random.default_rng(int(rho * 1e4) + t)
    fired = sum(bool(assess_quality(_ar1(rng, t, rho, m)).scale_steps) for _ in range(12))
    assert fired == 0


def _loop_opening(seed: int = 5) -> np.ndarray:
    """Round 28 PART b's loopopen.npz: AR(1) 0.9, rms 0.05, then 0.999, rms 0.5 (8000 x 6)."""
    rng = np.random.default_rng(seed)

    def ar1(n, phi, sig):
        e = rng.normal(0, sig * np.sqrt(1 - phi ** 2), (n, 6))
        x = np.zeros((n, 6))
        x[0] = rng.normal(0, sig, 6)
        for i in range(1, n):
            x[i] = phi * x[i - 1] + e[i]
        return x

    return np.vstack([ar1(4000, 0.9, 0.05), ar1(4000, 0.999, 0.5)])


def test_a_loop_opening_names_the_spread_step_in_every_mode():
    # before: "the mean steps or drifts in 2 mode(s)" only (round 28 PART b, N01)
    r = assess_quality(ModalLog(_loop_opening(), rate=2000.0, modes=list(range(2, 8))))
    assert r.stationary is False and r.level_steps
    named = {label: (frame, ratio) for label, frame, ratio, _ in r.variance_steps}
    assert sorted(named) == [f"Z{j}" for j in range(2, 8)]
    for frame, ratio in named.values():
        assert abs(frame - 4000) < 200  # at the opening
        assert ratio > 3.0  # x10 in rms; the open half spans 4 correlation times
    assert "the spread steps or drifts in 6 mode(s)" in r.note


def test_a_mean_offset_alone_names_no_spread_step():
    # two nights joined with an offset of 3 sd: the level rule names it, the spread on
    # each side is the same (by construction), so no spread step may be named
    x = _ar1(np.random.default_rng(17), 8000, 0.99, 6)
    x[4000:] += 3.0
    r = assess_quality(x)
    assert r.level_steps and r.stationary is False
    assert r.variance_steps == ()
