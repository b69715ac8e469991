"""Tests of the log-quality pass and the outlier policy (``modalinfo.telemetry.quality``).

References, all from outside the code: planted glitches and stuck runs at known frames
(found exactly); SciPy's normal quantiles (``scipy.stats.norm``) for the MAD constant and
the Bonferroni threshold, and ``scipy.stats.median_abs_deviation(scale="normal")`` /
``numpy.median`` for the robust centre and scale; the Gaussian tail probability with a
binomial tolerance (plus the MAD's known sampling error, Rousseeuw & Croux 1993) for the
false-alarm count of a clean Gaussian log; the definition of each policy applied by hand
with NumPy (``clip``: a white mode's prediction from its past is its mean); and a
save/load round trip for the recorded metadata.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog, apply_outlier_policy, assess_quality
from modalinfo.telemetry.quality import (
    MAD_TO_SIGMA,
    OUTLIER_POLICIES,
    gaussian_false_alarm,
    gaussian_threshold,
)

T, M = 4000, 27
GLITCH_FRAME = 1234  # every mode + 100 sigma
SPIKE = (77, 0)  # one mode of one frame + 100 sigma (not a glitched frame)
STUCK = {5: (500, 12), 9: (250, 10), 20: (3992, 8)}  # mode: (first frame, run length)
SHORT_RUN = (14, 900, 7)  # mode, first frame, length: one below the stuck rule (8)


def _planted() -> np.ndarray:
    x = np.random.default_rng(20261128).standard_normal((T, M))
    x[GLITCH_FRAME] += 100.0
    x[SPIKE] += 100.0
    for j, (i, n) in STUCK.items():
        x[i:i + n, j] = x[i, j]
    j, i, n = SHORT_RUN
    x[i:i + n, j] = x[i, j]
    return x


@pytest.fixture(scope="module")
def planted():
    return _planted()


def _stuck_frames() -> np.ndarray:
    return np.unique(np.concatenate([np.arange(i, i + n) for i, n in STUCK.values()]))


def test_constants_match_scipy():
    assert MAD_TO_SIGMA == pytest.approx(1.0 / stats.norm.ppf(0.75), rel=1e-12)
    for n in (1, 108_000, 270_000_000):
        assert gaussian_threshold(n, 0.01) == pytest.approx(stats.norm.isf(0.005 / n), rel=1e-9)
    assert gaussian_false_alarm(3.0) == pytest.approx(2 * stats.norm.sf(3.0), rel=1e-12)


@pytest.mark.parametrize("chunk", [None, 256])  # 256: runs and the stride cross blocks
def test_planted_glitch_and_stuck_runs_found_exactly(planted, chunk):
    r = assess_quality(ModalLog(planted, rate=1000.0), chunk_frames=chunk)
    assert r.glitch_frames.tolist() == [GLITCH_FRAME]
    assert r.outlier_frames.tolist() == sorted([SPIKE[0], GLITCH_FRAME])
    expected_out = np.ones(M, dtype=int)
    expected_out[SPIKE[1]] += 1
    np.testing.assert_array_equal(r.outliers, expected_out)
    expected_stuck = np.zeros(M, dtype=int)
    for j, (_, n) in STUCK.items():
        expected_stuck[j] = n
    np.testing.assert_array_equal(r.stuck, expected_stuck)
    np.testing.assert_array_equal(r.stuck_frames, _stuck_frames())
    expected_flagged = np.union1d(_stuck_frames(), [SPIKE[0], GLITCH_FRAME])
    np.testing.assert_array_equal(r.flagged_frames, expected_flagged)
    assert r.nonfinite.sum() == 0 and not r.approximate
    assert "1 glitched frame(s)" in r.describe() and str(GLITCH_FRAME) in r.describe()


def test_robust_centre_and_scale_match_scipy(planted):
    r = assess_quality(planted)
    np.testing.assert_allclose(r.median, np.median(planted, axis=0), rtol=0, atol=1e-12)
    ref = stats.median_abs_deviation(planted, axis=0, scale="normal")
    np.testing.assert_allclose(r.sigma, ref, rtol=1e-12)


def test_memmap_float32_same_flags(planted, tmp_path):
    path = tmp_path / "x.npy"
    np.save(path, planted.astype(np.float32))
    mm = np.load(path, mmap_mode="r")
    r = assess_quality(mm, chunk_frames=300)
    assert r.glitch_frames.tolist() == [GLITCH_FRAME]
    np.testing.assert_array_equal(r.stuck_frames, _stuck_frames())


def test_clean_gaussian_false_alarms_within_binomial_bound():
    x = np.random.default_rng(7).standard_normal((T, M))
    n = T * M
    # default rule: P(any false flag) <= 1 %; bound the count at the 1e-6 binomial quantile
    r = assess_quality(x)
    p = r.false_alarm
    assert p == pytest.approx(2 * stats.norm.sf(stats.norm.isf(0.005 / n)), rel=1e-9)
    assert r.outliers.sum() <= stats.binom.ppf(1 - 1e-6, n, p)
    assert r.glitch_frames.size == 0 and r.stuck.sum() == 0
    # k = 3: about 292 expected flags, a test of the 1.4826 scaling (10 % off gives ~105
    # or ~560). Spread: binomial, plus the MAD's sampling error (relative sd 1.166 /
    # sqrt(T) per mode; Rousseeuw & Croux 1993) times d(count)/d(scale) = 2 phi(k) k T.
    k = 3.0
    p3 = 2 * stats.norm.sf(k)
    sd_binom = math.sqrt(n * p3 * (1 - p3))
    sd_mad = math.sqrt(M) * T * 2 * stats.norm.pdf(k) * k * 1.166 / math.sqrt(T)
    r3 = assess_quality(x, k=k)
    assert r3.alpha is None and r3.false_alarm == pytest.approx(p3)
    assert abs(r3.outliers.sum() - n * p3) < 5 * math.hypot(sd_binom, sd_mad)


def test_subsample_median_is_the_strided_rows():
    x = np.random.default_rng(3).standard_normal((20_000, 4)) * [1.0, 2.0, 0.5, 3.0]
    r = assess_quality(x, sample_frames=2000, chunk_frames=777)
    assert r.approximate and r.sample_frames == 2000
    np.testing.assert_allclose(r.median, np.median(x[::10], axis=0), atol=1e-12)
    np.testing.assert_allclose(
        r.sigma, stats.median_abs_deviation(x[::10], axis=0, scale="normal"), rtol=1e-12)


def test_nonfinite_constant_and_zero_mad_modes():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((1000, 4))
    x[:, 1] = 2.5  # constant: neither stuck nor outliers
    x[:700, 2] = 0.0  # MAD 0: the mean-deviation scale takes over
    x[[10, 20], 3] = np.nan
    x[30, 3] = np.inf
    r = assess_quality(x)
    np.testing.assert_array_equal(r.nonfinite, [0, 0, 0, 3])
    np.testing.assert_array_equal(r.nonfinite_frames, [10, 20, 30])
    assert r.constant.tolist() == [False, True, False, False]
    assert r.stuck[1] == 0 and r.outliers[1] == 0
    dev = np.abs(x[:, 2] - np.median(x[:, 2]))
    assert r.sigma[2] == pytest.approx(math.sqrt(math.pi / 2) * dev.mean(), rel=1e-12)
    assert r.stuck[2] == 700  # a run of 700 equal values is stuck


def test_a_mode_without_a_finite_value_is_not_tested():
    # no finite value: nothing to centre, scale or find stuck (stuck_runs 0: not tested)
    x = np.random.default_rng(6).standard_normal((500, 3))
    x[:, 1] = np.nan
    r = assess_quality(x)
    assert r.nonfinite.tolist() == [0, 500, 0]
    assert r.stuck_runs.tolist() == [8, 0, 8] and r.outliers[1] == r.stuck[1] == 0


def _policy_log(planted):
    return ModalLog(planted, rate=1000.0, metadata={"site": "test"})


def test_policy_warn_keeps_data(planted):
    log, r = apply_outlier_policy(_policy_log(planted), "warn")
    np.testing.assert_array_equal(log.coeffs, planted)
    record = log.metadata["outliers"][-1]
    assert record["policy"] == "warn" and record["flagged_frames"] == r.n_flagged
    assert log.metadata["site"] == "test"


def test_policy_clip_replaces_outliers_only(planted):
    # white modes: the best prediction of a value from its past is the mode's mean, so
    # each outlier is replaced by about its median (AR(4) coefficients of white noise
    # are O(1 / sqrt(T)) = 0.016: a prediction within ~0.03 sigma of it; 0.2 allowed)
    log, r = apply_outlier_policy(_policy_log(planted), "clip")
    med = np.median(planted, axis=0)
    sig = stats.median_abs_deviation(planted, axis=0, scale="normal")
    np.testing.assert_array_less(np.abs(log.coeffs[GLITCH_FRAME] - med), 0.2 * sig)
    assert abs(log.coeffs[SPIKE] - med[SPIKE[1]]) < 0.2 * sig[SPIKE[1]]
    untouched = np.ones(planted.shape, dtype=bool)
    untouched[GLITCH_FRAME] = False
    untouched[SPIKE] = False
    np.testing.assert_array_equal(log.coeffs[untouched], planted[untouched])
    again = assess_quality(log)
    assert again.outliers.sum() == 0 and again.stuck.sum() == r.stuck.sum()
    assert "clipped 28 outlier value(s)" in log.metadata["outliers"][-1]["action"]


def test_policy_drop_removes_flagged_frames(planted):
    log, r = apply_outlier_policy(_policy_log(planted), "drop")
    keep = np.ones(T, dtype=bool)
    keep[np.union1d(_stuck_frames(), [SPIKE[0], GLITCH_FRAME])] = False
    np.testing.assert_array_equal(log.coeffs, planted[keep])
    np.testing.assert_allclose(log.timestamps, np.arange(T)[keep] / 1000.0, rtol=0, atol=0)
    assert log.sampling().n_gaps > 0  # the removal shows as gaps
    assert assess_quality(log).clean
    with pytest.raises(ValueError, match="time-series"):
        apply_outlier_policy(_policy_log(planted), "drop", time_series=True)


def test_policy_raise(planted):
    with pytest.raises(ValueError, match=r"'raise'.*glitched frame"):
        apply_outlier_policy(_policy_log(planted), "raise")
    clean = ModalLog(np.random.default_rng(1).standard_normal((500, 3)))
    out, r = apply_outlier_policy(clean, "raise")
    assert r.clean and out is clean  # a clean log passes through, metadata unchanged


def test_recorded_policy_travels_through_save(planted, tmp_path):
    log, _ = apply_outlier_policy(_policy_log(planted), "clip")
    back = load(save(log, tmp_path / "clipped.npz"))
    assert back.metadata["outliers"] == log.metadata["outliers"]
    np.testing.assert_array_equal(back.coeffs, log.coeffs)


@pytest.mark.parametrize("kwargs, match", [
    ({"k": 0.0}, "`k`"), ({"k": float("nan")}, "`k`"), ({"stuck_run": 1}, "`stuck_run`"),
    ({"alpha": 1.5}, "`alpha`"), ({"sample_frames": 0}, "`sample_frames`"),
])
def test_bad_options_named(kwargs, match):
    with pytest.raises((ValueError, TypeError), match=match):
        assess_quality(np.zeros((10, 2)) + np.arange(10)[:, None], **kwargs)


def test_bad_policy_named():
    log = ModalLog(np.random.default_rng(0).standard_normal((50, 2)))
    with pytest.raises(ValueError, match="`policy`"):
        apply_outlier_policy(log, "ignore")
    with pytest.raises(TypeError, match="`log`"):
        apply_outlier_policy(np.zeros((5, 2)), "warn")
    assert OUTLIER_POLICIES == ("warn", "clip", "drop", "raise")


def test_quantised_log_repeats_are_not_stuck_but_a_long_run_is():
    # AR(1) modes written with a 0.5 sigma resolution: equal consecutive values are
    # common (q ~ 0.3-0.5), and chance runs of 8+ occur; the stuck rule lengthens per
    # mode to 1 + log(alpha / (T M)) / log(q) and still finds a planted 200-frame run
    rng = np.random.default_rng(9)
    e = rng.standard_normal((T, 6)) * math.sqrt(1 - 0.95**2)
    x = np.zeros((T, 6))
    for t in range(1, T):
        x[t] = 0.95 * x[t - 1] + e[t]
    x = np.round(x * 2) / 2
    eq = x[1:] == x[:-1]
    lengths = [len(r) for j in range(6) for r in "".join("1" if v else "0" for v in eq[:, j])
               .split("0") if r]
    assert max(lengths) + 1 >= 8  # the fixed 8-value rule would flag chance runs here
    r = assess_quality(x)
    q = eq.mean(axis=0)
    need = np.maximum(8, np.ceil(1 + np.log(0.01 / (T * 6)) / np.log(q)))
    np.testing.assert_array_equal(r.stuck_runs, need)
    assert r.stuck.sum() == 0
    y = x.copy()
    y[1000:1200, 2] = 7.0  # a long run at a value the mode never takes (saturation)
    r = assess_quality(y)
    np.testing.assert_array_equal(r.stuck_frames, np.arange(1000, 1200))
    assert r.stuck.tolist() == [0, 0, 200, 0, 0, 0]


@pytest.mark.parametrize("sign", [1.0, -1.0])  # -1: the glitches fall below the median
def test_clip_float32_log_leaves_no_outlier(planted, sign):
    log = ModalLog((sign * planted).astype(np.float32), rate=1000.0)
    clipped, r = apply_outlier_policy(log, "clip")
    assert clipped.dtype == np.float32 and r.outliers.sum() == 28
    assert assess_quality(clipped, k=r.k).outliers.sum() == 0
    changed = clipped.coeffs != log.coeffs
    assert changed.sum() == 28 and changed[GLITCH_FRAME].all() and changed[SPIKE]


def test_glitched_frame_rule_is_at_least_frame_modes():
    # the rule's definition: outliers in >= frame_modes modes. Frame 100 holds spikes in
    # exactly 3 modes (glitched at the default min(M, 3)), frame 200 in 2 (not glitched)
    x = np.random.default_rng(11).standard_normal((2000, 6))
    x[100, [0, 2, 4]] += 100.0
    x[200, [1, 3]] += 100.0
    r = assess_quality(x)
    assert r.outlier_frames.tolist() == [100, 200]
    assert r.glitch_frames.tolist() == [100]
    assert assess_quality(x, frame_modes=2).glitch_frames.tolist() == [100, 200]


def test_subsample_never_exceeds_sample_frames_when_it_does_not_divide():
    # 20,500 frames at sample_frames = 2000: the stride is ceil(20500 / 2000) = 11, so the
    # subsample is x[::11] (1864 rows <= 2000); a floored stride (10) would take 2050 rows
    x = np.random.default_rng(4).standard_normal((20_500, 3)) * [1.0, 2.0, 0.5]
    r = assess_quality(x, sample_frames=2000, chunk_frames=999)
    assert r.sample_frames == x[::11].shape[0] <= 2000
    np.testing.assert_allclose(r.median, np.median(x[::11], axis=0), atol=1e-12)
    np.testing.assert_allclose(
        r.sigma, stats.median_abs_deviation(x[::11], axis=0, scale="normal"), rtol=1e-12)


def test_drop_of_the_first_frame_starts_the_log_at_the_first_kept_frame():
    # frame 0 glitched in every mode: after 'drop' the first frame is frame 1, at 1 / rate
    x = np.random.default_rng(12).standard_normal((1000, 5))
    x[0] += 100.0
    log, r = apply_outlier_policy(ModalLog(x, rate=500.0, start_time=2.0), "drop")
    assert r.flagged_frames.tolist() == [0]
    assert log.start_time == log.times[0] == log.timestamps[0] == 2.0 + 1 / 500.0
    np.testing.assert_allclose(log.times, 2.0 + np.arange(1, 1000) / 500.0, rtol=0, atol=0)


def test_quantised_mode_minimum_run_is_the_documented_law():
    # 11 frames of one mode with 5 equal consecutive pairs of 10: q = 0.5, and the minimum
    # stuck run is ceil(1 + ln(alpha / (T M)) / ln q) = ceil(11.1) = 12 (module docstring),
    # q counted here with numpy over the T - 1 consecutive pairs
    x = np.array([0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 4.0, 4.0, 5.0])[:, None]
    q = np.mean(x[1:, 0] == x[:-1, 0])
    assert q == 0.5
    r = assess_quality(x, alpha=0.01)
    assert r.stuck_runs.tolist() == [math.ceil(1 + math.log(0.01 / 11) / math.log(q))] == [12]


def test_a_subsample_too_small_for_a_mad_is_refused():
    # audit 9, centre: sample_frames=1 gave a MAD of 0, so a 100-sigma glitch at frame 10
    # was never flagged; the smallest subsample accepted (100 frames, MAD relative error
    # ~1.17 / sqrt(100) = 12 %, Rousseeuw & Croux 1993) finds it
    x = np.random.default_rng(21).standard_normal((1000, 5))
    x[10, 1] = 100.0
    for bad in (1, 2, 99):
        with pytest.raises(ValueError, match=r"`sample_frames` must be an int >= 100"):
            assess_quality(x, sample_frames=bad)
    assert assess_quality(x, sample_frames=100).outlier_frames.tolist() == [10]


def test_frame_modes_above_the_number_of_modes_is_refused():
    # audit 9, centre: frame_modes=6 on a 5-mode log made "glitched frame" unreachable;
    # frame 10 out in all 5 modes is glitched at frame_modes = 5 (= M)
    x = np.random.default_rng(22).standard_normal((500, 5))
    x[10] += 100.0
    with pytest.raises(ValueError, match=r"`frame_modes` must be an int <= 5; got 6"):
        assess_quality(x, frame_modes=6)
    assert assess_quality(x, frame_modes=5).glitch_frames.tolist() == [10]


def test_a_report_of_another_log_is_refused():
    # audit 9, centre: the report of a 3-mode log was applied to a 4-mode log (and a
    # clean log's report left a planted 100-sigma value unclipped); the report of the
    # log itself replaces it by its prediction: about the median of the white mode
    # (within 0.2 sigma, numpy median and MAD by hand; before leftovers 12-est: med + k sigma)
    x = np.random.default_rng(23).standard_normal((1000, 4))
    y = x.copy()
    y[10, 0] = 100.0
    log = ModalLog(y, rate=100.0, modes=[2, 3, 4, 5])
    with pytest.raises(ValueError, match=r"`report` must be the assessment of this log"):
        apply_outlier_policy(log, "clip", report=assess_quality(x[:, :3]))
    with pytest.raises(ValueError, match=r"and options \['k'\]"):
        apply_outlier_policy(log, "clip", report=assess_quality(log), k=5.0)
    out, r = apply_outlier_policy(log, "clip", report=assess_quality(log))
    med = np.median(y[:, 0])
    sigma = MAD_TO_SIGMA * np.median(np.abs(y[:, 0] - med))
    assert abs(out.coeffs[10, 0] - med) < 0.2 * sigma and r.outliers.sum() == 1
def test_alpha_is_checked_when_k_is_given():
    """Audit 9: with ``k`` given, ``alpha=None`` passed and failed later with a bare
    TypeError on quantised (tied) data, where alpha sets the stuck-run length."""
    tied = np.round(np.random.default_rng(0).standard_normal((200, 2)) * 5)
    with pytest.raises(TypeError, match="`alpha` must be a real number; got None"):
        assess_quality(tied, k=5.0, alpha=None)
    with pytest.raises(ValueError, match="`stuck_run` must be an int <="):
        assess_quality(tied, stuck_run=2**70)


def test_a_report_of_another_log_of_the_same_shape_is_refused(tmp_path):
    # issue 27 leftovers: a clean log's report of the same shape and labels was applied to
    # a log with a planted 100-sigma value (left unclipped). The fingerprint is a BLAKE2b
    # digest (hashlib, by hand here) of the data bytes; a save/load round trip keeps it
    import hashlib

    from modalinfo.telemetry.quality import data_fingerprint

    x = np.random.default_rng(23).standard_normal((1000, 4))
    y = x.copy()
    y[10, 0] = 100.0
    h = hashlib.blake2b(f"{x.shape}|{x.dtype.str}|".encode(), digest_size=16)
    h.update(x.tobytes())
    assert assess_quality(x, chunk_frames=7).fingerprint == "array:" + h.hexdigest()
    log = ModalLog(y, rate=100.0, modes=[2, 3, 4, 5])
    clean = ModalLog(x, rate=100.0, modes=[2, 3, 4, 5])
    for other in (clean, x, ModalLog(y, rate=50.0, modes=[2, 3, 4, 5])):  # data; time axis
        with pytest.raises(ValueError, match=r"^`report` must be the assessment of this log; "
                                             r"got a report of another log of the same shape"):
            apply_outlier_policy(log, "clip", report=assess_quality(other))
    save(log, tmp_path / "y.npz")
    again = load(tmp_path / "y.npz")
    report = assess_quality(again, chunk_frames=3)
    assert report.fingerprint == data_fingerprint(log) == assess_quality(log).fingerprint
    out, _ = apply_outlier_policy(log, "clip", report=report)
    assert out.coeffs[10, 0] < 10.0  # clipped to median + k sigma (k < 10 here)
    # an array's report still applies to the log holding those values
    apply_outlier_policy(log, "clip", report=assess_quality(y))


def test_a_report_of_a_memory_mapped_log_is_checked_without_reading_it_again(
        tmp_path, monkeypatch):
    # issue 27 leftovers: apply_outlier_policy(report=...) re-read a memory-mapped log to
    # fingerprint it (a second full pass over the file). Rows read are counted through a
    # wrapper of the block iterator every pass uses; a read-only map keeps its fingerprint,
    # a log of a caller's writable array is hashed again (its data may have changed)
    import modalinfo.telemetry.quality as quality

    read = []
    blocks = quality.row_blocks

    def counting(arr, rows):
        for block in blocks(arr, rows):
            read.append(block.shape[0])
            yield block

    monkeypatch.setattr(quality, "row_blocks", counting)
    x = np.random.default_rng(27).standard_normal((3000, 4))
    x[10, 0] = 100.0
    np.save(tmp_path / "x.npy", x)
    log = load(tmp_path / "x.npy", mmap=True)
    assert isinstance(log.coeffs, np.memmap)
    report = assess_quality(log)
    read.clear()
    apply_outlier_policy(log, "warn", report=report)
    assert sum(read) == 0  # before: 3000 (one more pass over the file)
    out, _ = apply_outlier_policy(log, "clip", report=report)
    assert sum(read) == 3000  # the clipping's own pass only
    assert out.coeffs[10, 0] < 10.0 and out.coeffs[11, 0] == x[11, 0]
    # another map of the same shape: refused, having been read once
    y = x.copy()
    y[10, 0] = 0.0
    np.save(tmp_path / "y.npy", y)
    with pytest.raises(ValueError, match="got a report of another log of the same shape"):
        apply_outlier_policy(load(tmp_path / "y.npy", mmap=True), "clip", report=report)
    # a log viewing a caller's array: hashed again, and refused once the array changed
    z = x.copy()
    mine = ModalLog(z)
    report = assess_quality(mine)
    read.clear()
    apply_outlier_policy(mine, "warn", report=report)
    assert sum(read) == 3000
    z[10, 0] = 0.0
    with pytest.raises(ValueError, match="got a report of another log of the same shape"):
        apply_outlier_policy(mine, "clip", report=report)
