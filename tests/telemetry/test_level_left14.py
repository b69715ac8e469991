"""A step or a drift of the mean: the level rule and the quality pass (issue 27, left14-level).

References, outside the code under test:
- the F(1, B) law of ``scipy.stats.f``: on Gaussian white noise the cosine terms are
  independent N(0, sigma^2), so the rule's rejections at 5 % are binomial(0.05, draws);
- statsmodels' KPSS test (Kwiatkowski et al. 1992) on the same series: it rejects
  level stationarity of the planted step and does not on the stationary series;
- planted facts: a step of known size at a known frame (the CUSUM location of a
  single step is the step frame, to within the noise), a ramp; round 14 PART a d04:
  an AR(1) 0.9 log with a step of 6.5 marginal sd half way was reported stationary
  and clean.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo._stats import LEVEL_MIN_TERMS, level_stationarity, level_steps
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.quality import assess_quality


def ar1(rng: np.random.Generator, n: int, rho: float, m: int | None = None) -> np.ndarray:
    """Stationary AR(1) of unit marginal variance (3000 frames of burn-in)."""
    shape = (n + 3000,) if m is None else (n + 3000, m)
    e = rng.standard_normal(shape)
    return lfilter([1.0], [1.0, -rho], e, axis=0)[3000:] * math.sqrt(1.0 - rho * rho)


def test_white_noise_rejections_are_binomial_at_the_f_level():
    # 400 draws at 5 %: binomial sd 1.09 %, bound 5 % + 3 sd = 8.3 %, and >= 1.7 %
    rng = np.random.default_rng(140)
    p = np.array([level_stationarity(rng.standard_normal(512)).p_value for _ in range(400)])
    assert np.isfinite(p).all()
    assert 0.017 <= np.mean(p < 0.05) <= 0.083


def test_persistent_stationary_series_hold_the_level():
    # AR(1) 0.9, n = 2000 (judged): 300 draws at 5 %, binomial sd 1.26 %, bound 8.8 %
    rng = np.random.default_rng(141)
    p = np.array([level_stationarity(ar1(rng, 2000, 0.9)).p_value for _ in range(300)])
    assert np.mean(np.isfinite(p)) > 0.95
    assert np.mean(p < 0.05) <= 0.088


def test_too_few_correlation_times_is_not_judged():
    # AR(1) 0.99 over 500 frames: ~2.5 effective samples; a step of 5 sd is also
    # indistinguishable from persistence there: said (NaN), not guessed
    rng = np.random.default_rng(142)
    x = ar1(rng, 500, 0.99)
    t = level_stationarity(x)
    assert not t.judged and t.terms < LEVEL_MIN_TERMS
    flagged, judged = level_steps(x)
    assert flagged == [] and judged == 0


def test_a_step_is_found_where_it_was_planted_as_kpss_does():
    stattools = pytest.importorskip("statsmodels.tsa.stattools")
    rng = np.random.default_rng(143)
    x = ar1(rng, 4000, 0.9)
    clean = x.copy()
    x[1600:] += 3.0  # 3 marginal sd at 40 % of the record
    t = level_stationarity(x)
    assert t.p_value < 1e-6
    assert abs(t.frame - 1600) <= 40
    # difference of two AR(1) 0.9 means over 1600 and 2400 frames: sd 0.14, bound 3 sd
    assert t.shift == pytest.approx(3.0, abs=0.45)
    assert level_stationarity(clean).p_value > 0.01
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # KPSS's table-interpolation warning
        assert stattools.kpss(x, regression="c", nlags="auto")[1] <= 0.01
        assert stattools.kpss(clean, regression="c", nlags="auto")[1] > 0.05


def test_a_ramp_is_found():
    rng = np.random.default_rng(144)
    x = ar1(rng, 4000, 0.9) + np.linspace(0.0, 3.0, 4000)
    assert level_stationarity(x).p_value < 1e-4


def test_quality_reports_the_d04_step_with_its_frame():
    rng = np.random.default_rng(145)
    x = ar1(rng, 4000, 0.9, 3)
    x[2000:, 0] += 6.5
    rep = assess_quality(ModalLog(x, rate=1e3, modes=[2, 3, 4]))
    assert rep.stationary is False  # was True (round 14 PART a, d04)
    assert [s[0] for s in rep.level_steps] == ["Z2"]
    label, frame, shift, p = rep.level_steps[0]
    assert abs(frame - 2000) <= 20 and shift == pytest.approx(6.5, abs=0.5) and p < 1e-6
    assert "Z2 at frame" in rep.describe() and "steps or drifts" in rep.note
    assert rep.to_dict()["level_steps"].startswith("Z2 ")
    # the stationary modes alone: nothing
    calm = assess_quality(ModalLog(x[:, 1:], rate=1e3, modes=[3, 4]))
    assert calm.level_steps == () and calm.level_judged == 2 and calm.stationary is True


def test_quality_reads_bin_means_when_subsampling():
    # 20000 frames, sample_frames=2000: bins of 10 frames; the frame is found to a bin
    rng = np.random.default_rng(146)
    x = ar1(rng, 20000, 0.9, 2)
    x[13000:, 1] -= 2.0
    rep = assess_quality(x, sample_frames=2000)
    assert [s[0] for s in rep.level_steps] == ["col1"]
    assert abs(rep.level_steps[0][1] - 13000) <= 60


def test_shipped_logs_have_no_level_step():
    from pathlib import Path

    from modalinfo.io import load

    data = Path(__file__).resolve().parents[2] / "data"
    for name in ("kaos_like_open_loop.npz", "kaos_like_closed_loop.npz"):
        rep = assess_quality(load(data / name))
        assert rep.level_steps == () and rep.level_judged == rep.n_modes
