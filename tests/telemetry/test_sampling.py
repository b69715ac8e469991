"""Median rate, jitter, gaps and segments of timestamps; analyses refusing gaps.

References: NumPy's median of the intervals, scipy's ``median_abs_deviation`` with
``scale="normal"`` for the jitter, the mean rate ``(T - 1) / span`` computed by hand,
gaps placed by construction, and frame slices of the log for the segments.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import median_abs_deviation

from modalinfo.telemetry import ModalLog, require_contiguous, sampling_of


def _gappy(n=4000, rate=2000.0, gap_at=1999, gap=0.1):
    t = np.arange(n) / rate
    t[gap_at + 1:] += gap
    return t


def test_gap_log_median_rate_and_gap():
    t = _gappy()
    s = sampling_of(t)
    assert s.median_rate == pytest.approx(2000.0, rel=1e-9)
    assert s.mean_rate == pytest.approx(3999 / (t[-1] - t[0]), rel=1e-12)
    assert s.mean_rate < 1910  # the mean is biased by the gap; the median is not
    assert s.n_gaps == 1 and s.gap_after.tolist() == [1999]
    assert s.gap_duration[0] == pytest.approx(0.1005)
    assert s.segments == [(0, 2000), (2000, 4000)]
    assert "after frame 1999" in s.describe_gap(0)


def test_jitter_matches_scipy_mad():
    rng = np.random.default_rng(3)
    dt = 1e-3 * (1 + 0.05 * rng.standard_normal(5000)).clip(0.8, 1.2)
    t = np.concatenate([[0.0], np.cumsum(dt)])
    s = sampling_of(t)
    assert s.uniform
    expected = median_abs_deviation(np.diff(t), scale="normal") / np.median(np.diff(t))
    assert s.jitter == pytest.approx(expected, rel=1e-9)
    assert 0.04 < s.jitter < 0.06  # the 5% clock noise put in


def test_log_segments_and_longest_segment():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((300, 3))
    t = np.arange(300) / 100.0
    t[100:] += 1.0  # gap after frame 99
    t[250:] += 1.0  # gap after frame 249
    log = ModalLog(x, timestamps=t)
    assert log.segments() == [(0, 100), (100, 250), (250, 300)]
    longest = log.longest_segment()
    np.testing.assert_array_equal(longest.coeffs, x[100:250])
    np.testing.assert_array_equal(longest.timestamps, t[100:250])
    assert longest.sampling().uniform
    assert "frames 100..249 of 300" in longest.metadata["segment"]
    uniform = ModalLog(x, rate=100.0)
    assert uniform.sampling() is None and uniform.segments() == [(0, 300)]
    assert uniform.longest_segment() is uniform
    with pytest.raises(ValueError, match=r"2 gap\(s\), the first of 1.01 s .* after frame 99"):
        require_contiguous(log, "this analysis")


def test_gap_factor_threshold():
    t = np.array([0.0, 1.0, 2.0, 3.4, 4.4, 6.0])  # intervals 1, 1, 1.4, 1, 1.6
    assert sampling_of(t).gap_after.tolist() == [4]
    assert sampling_of(t, gap_factor=1.3).gap_after.tolist() == [2, 4]
    with pytest.raises(ValueError, match="gap_factor"):
        sampling_of(t, gap_factor=1.0)


def test_forecast_and_bootstrap_refuse_gaps():
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.forecast import LinearPredictor, evaluate
    from modalinfo.ordering import order_modes

    rng = np.random.default_rng(0)
    x = np.cumsum(rng.standard_normal((600, 3)), axis=0) * 0.01
    t = np.arange(600) / 1000.0
    t[300:] += 0.05
    log = ModalLog(x, timestamps=t)
    with pytest.raises(ValueError, match=r"forecast evaluation assumes equally spaced frames"
                       r".*after frame 299.*log\.longest_segment\(\)"):
        evaluate([LinearPredictor()], log, horizons=[1])
    ev = evaluate([LinearPredictor()], log.longest_segment(), horizons=[1])
    assert ev.labels == ("Z2", "Z3", "Z4")
    basis = ZernikeBasis(Pupil(16), modes=[2, 3, 4])
    with pytest.raises(ValueError, match="block bootstrap of the MI gains"):
        order_modes(log, basis, "mi_greedy", sample_budget=2000, n_resamples=5, seed=0)
    res = order_modes(log, basis, "mi_greedy", sample_budget=2000, n_resamples=0, seed=0)
    assert sorted(res.order.tolist()) == [0, 1, 2]  # frame order does not matter here


def test_sampling_of_uses_the_timestamp_rule():
    """Audit 9: ``sampling_of`` cast its input with ``np.asarray(float)``: datetime64 in
    ms became seconds x 1000, strings were parsed, masked values used, and decreasing
    times gave a negative rate. It now shares ModalLog's timestamp rule. Reference:
    1 / interval of an exact 1 ms grid."""
    t = np.arange(50) * 1e-3
    assert sampling_of(list(t)).median_rate == pytest.approx(1000.0, rel=1e-12)
    with pytest.raises(TypeError, match="`times` must be a numeric array of seconds"):
        sampling_of(np.arange(50).astype("datetime64[ms]"))
    with pytest.raises(TypeError, match="`times` must be a numeric array of seconds"):
        sampling_of(t.astype(str))
    with pytest.raises(ValueError, match="`times` is a masked array with 1 masked"):
        sampling_of(np.ma.masked_array(t, mask=np.arange(50) == 7))
    with pytest.raises(ValueError, match="`times` must be strictly increasing; decreasing"):
        sampling_of(t[::-1])


# ---- times rounded to a sizeable part of an interval (audit 10-time) --------------------
# Reference: IEEE 754 spacing (numpy.spacing) and the times by construction: float32
# times from 1000 s at 2 kHz are 6.1e-5 s apart (12 % of the 5e-4 s interval), and the
# median of intervals of 8 or 9 spacings was 8 x 6.1e-5 s = 2048 Hz with "jitter none".

def test_float32_times_too_coarse_refused():
    t = (1000.0 + np.arange(3000) / 2000.0).astype(np.float32)
    assert np.spacing(np.float32(1001.5)) > 0.05 / 2000.0  # the premise
    with pytest.raises(ValueError, match=r"`timestamps` are too coarse.*float32.*--rate"):
        ModalLog(np.zeros((3000, 2)), timestamps=t)


def test_float64_unix_ms_read_as_seconds_too_coarse_refused():
    t = 1.7e12 + np.arange(3000) / 2000.0  # float64 spacing 2.4e-4 s: half an interval
    with pytest.raises(ValueError, match=r"too coarse.*float64"):
        ModalLog(np.zeros((3000, 2)), timestamps=t)


@pytest.mark.parametrize("start", [50.0, 200.0])
def test_rounded_float32_times_give_the_true_rate(start):
    # float32 spacing at 200 s is 1.5e-5 s (3 % of an interval): accepted, and the rate
    # must be 2000 Hz to within 2 spacings over the span, not the median's 1 spacing
    t = (start + np.arange(3000) / 2000.0).astype(np.float32)
    spacing = float(np.spacing(np.float32(t[-1])))
    s = sampling_of(t.astype(np.float64))  # widened by a reader, as the NPZ one does
    assert abs(s.median_interval - 1 / 2000.0) <= 2 * spacing / 2999
    assert s.uniform
    med = float(np.median(np.diff(t.astype(np.float64))))
    assert abs(med - 1 / 2000.0) > 10 * abs(s.median_interval - 1 / 2000.0)  # median biased
    log = ModalLog(np.zeros((3000, 1)), timestamps=t, rate=2000.0)  # agrees with the rate
    assert log.rate == 2000.0


def test_unix_epoch_times_at_10khz_give_the_true_rate():
    t = 1.7e9 + np.arange(5000) / 1e4  # float64 spacing 2.4e-7 s: 0.24 % of an interval
    assert abs(sampling_of(t).median_rate - 1e4) < 1e4 * 1e-4


# ---- a rate change below the gap threshold (audit 10-time) ------------------------------
# Reference: the time axis by construction (1500 frames at 2 kHz, then 1500 at 1980 Hz:
# no interval is a gap or short, and "jitter none; no gaps" was all info said).

def _two_clocks(r2=1980.0):
    t = np.arange(1500) / 2000.0
    return np.r_[t, t[-1] + np.arange(1, 1501) / r2]


def test_rate_change_of_one_percent_found():
    s = sampling_of(_two_clocks())
    assert s.uniform  # not a gap: not refused
    assert s.rate_low == pytest.approx(1980.0, rel=1e-9)
    assert s.rate_high == pytest.approx(2000.0, rel=1e-9)
    assert s.rate_change == pytest.approx(20.0 / 1980.0, rel=1e-9)
    assert "changes by 1%" in s.describe_irregular()


@pytest.mark.parametrize("seed", range(5))
def test_no_rate_change_in_jitter_or_rounding(seed):
    rng = np.random.default_rng(seed)
    t = np.arange(3000) / 2000.0
    for times in (t + rng.normal(0, 0.05 / 2000, t.size),  # 5 % timestamp noise
                  1.7e9 + t + rng.normal(0, 1e-6 / 2000, t.size),  # Unix epoch
                  1.7e9 + np.arange(3000) / (4000.0 + 500 * seed)):  # rounding 1e-3
        assert sampling_of(np.sort(times)).rate_change == 0.0


def test_rate_change_warned_where_frames_are_taken_as_equal():
    from modalinfo.forecast import PersistencePredictor, evaluate

    log = ModalLog(np.random.default_rng(0).standard_normal((3000, 1)),
                   timestamps=_two_clocks())
    with pytest.warns(UserWarning, match=r"changes by 1% along the log \(1980 to 2000 Hz"):
        evaluate({"p": PersistencePredictor()}, log, horizons=[1])


def test_duration_of_a_gapped_log_is_its_span():
    # Reference: the time axis by construction: two runs of 1500 frames at 2 kHz, 8 h
    # apart, span t[-1] - t[0] = 28800.7495 s, plus one frame interval (0.5 ms)
    t = np.r_[np.arange(1500), np.arange(1500)] / 2000.0
    t[1500:] += 8 * 3600.0
    log = ModalLog(np.zeros((3000, 1)), timestamps=t)
    assert log.duration == pytest.approx(28800.75, abs=1e-6)
    clean = ModalLog(np.zeros((3000, 1)), timestamps=np.arange(3000) / 2000.0)
    assert clean.duration == pytest.approx(1.5, abs=1e-12)


# ---- a stated rate against jittered timestamps (audit 10-time) --------------------------
# Reference: the true rate by construction (frames every 0.5 ms, each time with 5 %
# Gaussian noise of an interval): ModalLog refused the true 2000 Hz in 6 of 20 seeds,
# the median interval being 0.2 % off; the mean of the intervals telescopes to the span.

def test_true_rate_accepted_with_jittered_timestamps():
    t = np.arange(3000) / 2000.0
    for seed in range(20):
        noisy = np.sort(t + np.random.default_rng(seed).normal(0, 0.05 / 2000, t.size))
        assert ModalLog(np.zeros((3000, 1)), timestamps=noisy, rate=2000.0).rate == 2000.0
    with pytest.raises(ValueError, match="disagrees"):  # 0.2 % off stays refused
        ModalLog(np.zeros((3000, 1)), timestamps=t, rate=1996.0)


# ---- frames removed from a log without a time axis (audit 10-time) ----------------------
# Reference: the frames removed by construction (10 NaN frames; one 1e6 glitch frame):
# without a rate nothing marks the hole, and select_inputs, transfer_entropy_map and
# evaluate paired the frames around it as consecutive without a word.

def _removed_logs():
    from modalinfo.telemetry import apply_outlier_policy

    x = np.random.default_rng(0).standard_normal((3000, 2))
    nan = x.copy()
    nan[1000:1010] = np.nan
    glitch = x.copy()
    glitch[500] = 1e6
    return [ModalLog(nan, nonfinite="drop"), apply_outlier_policy(ModalLog(glitch), "drop")[0]]


@pytest.mark.parametrize("which", [0, 1])
def test_lagged_analyses_refuse_frames_removed_without_time_axis(which):
    from modalinfo.forecast import PersistencePredictor, evaluate
    from modalinfo.information import select_inputs, transfer_entropy_map

    log = _removed_logs()[which]
    with pytest.raises(ValueError, match="frames were removed from a log without a time"):
        select_inputs(log, 0, max_lag=2, n_surrogates=19)
    with pytest.raises(ValueError, match="bridge"):
        transfer_entropy_map(log, lags=2, n_surrogates=19)
    with pytest.raises(ValueError, match="forecast evaluation takes the frames"):
        evaluate({"p": PersistencePredictor()}, log, horizons=[1])


# ---- a block of frames exported twice (audit 10-time) -----------------------------------
# Reference: the repeat by construction (frames 1000..1099 written again after 1099);
# a frozen frame, a constant log and independent Gaussian frames repeat no block.

def test_repeated_block_found_and_nothing_else():
    from modalinfo.telemetry.sampling import repeated_blocks

    x = np.random.default_rng(0).standard_normal((3000, 3))
    assert repeated_blocks(x[np.r_[0:1100, 1000:3000]]) == [(1100, 100, 1000)]
    assert repeated_blocks(x) == []
    frozen = x.copy()
    frozen[200:230] = frozen[200]
    assert repeated_blocks(frozen) == []
    assert repeated_blocks(np.zeros((100, 3))) == []
    rounded = np.round(np.random.default_rng(1).standard_normal((20000, 2)), 1)
    assert repeated_blocks(rounded) == []  # chance equal rows, no equal run of 8
