"""Tests of ``ModalLog`` and ``summarize``.

References: index conventions against the published Noll (1976) / ANSI Z80.28 /
Fringe tables (e.g. Noll 5 = sin 2theta = ANSI 3; Noll 11 spherical = Fringe 9);
non-finite interpolation against ``numpy.interp`` on the good samples; the
one-pass summary against NumPy's two-pass mean/std and ``statsmodels.tsa.acf``
(lag-1 autocorrelation); the numba kernel against a slow pure-Python loop.
"""

from __future__ import annotations

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf

from modalinfo.telemetry import ModalLog, summarize
from modalinfo.telemetry._kernels import chunk_stats_update, lag1_finalize


def make(T=100, M=5, dtype=np.float64, seed=0, **kw):
    coeffs = np.random.default_rng(seed).standard_normal((T, M)).astype(dtype)
    kw.setdefault("rate", 1000.0)
    return ModalLog(coeffs, **kw)


# ----------------------------------------------------------------- construction
def test_defaults_and_properties():
    log = make(T=200, M=4)
    assert log.n_frames == 200 and log.n_modes == 4 and len(log) == 200
    assert log.modes == [2, 3, 4, 5]
    assert log.labels == ["Z2", "Z3", "Z4", "Z5"]
    assert log.rate == 1000.0
    assert log.duration == pytest.approx(0.2)
    np.testing.assert_allclose(log.times, np.arange(200) / 1000.0)
    assert log.units == "rad" and log.convention == "noll" and log.wavelength is None
    assert log.metadata == {} and log.repairs == ()
    assert not log.coeffs.flags.writeable


def test_default_modes_per_convention():
    assert make(M=3, convention="ansi").modes == [1, 2, 3]
    assert make(M=3, convention="ansi").labels == ["A1", "A2", "A3"]
    assert make(M=3, convention="fringe").labels == ["F2", "F3", "F4"]
    log = make(M=2, convention="labels", modes=["KL1", "KL2"])
    assert log.labels == ["KL1", "KL2"]


def test_float32_kept_and_no_copy():
    x = np.random.default_rng(1).standard_normal((50, 3)).astype(np.float32)
    log = ModalLog(x, rate=10.0)
    assert log.dtype == np.float32
    assert np.shares_memory(log.coeffs, x)
    assert log.to_units("waves").dtype == np.float32


def test_integer_input_becomes_float64():
    log = ModalLog(np.arange(12).reshape(6, 2), rate=1.0)
    assert log.dtype == np.float64


def test_memmap_stays_memmap(tmp_path):
    x = np.random.default_rng(2).standard_normal((64, 3))
    np.save(tmp_path / "x.npy", x)
    mm = np.load(tmp_path / "x.npy", mmap_mode="r")
    log = ModalLog(mm, rate=100.0)
    assert isinstance(log.coeffs, np.memmap)
    assert isinstance(log[10:20].coeffs, np.memmap)
    blocks = list(log.iter_chunks(10))
    assert [b.shape[0] for b in blocks] == [10] * 6 + [4]
    np.testing.assert_array_equal(np.concatenate(blocks), x)


def test_timestamps_and_rate():
    t = np.array([0.0, 0.001, 0.002, 0.0035, 0.0045])
    log = ModalLog(np.zeros((5, 2)), timestamps=t)
    assert log.rate == pytest.approx(4 / 0.0045)
    np.testing.assert_array_equal(log.times, t)
    # agreeing rate is accepted (median interval 1 ms)
    ModalLog(np.zeros((5, 2)), timestamps=t, rate=1000.0)
    with pytest.raises(ValueError, match=r"`rate` \(500.0 Hz\) disagrees with `timestamps`"):
        ModalLog(np.zeros((5, 2)), timestamps=t, rate=500.0)


def test_no_time_axis():
    log = ModalLog(np.zeros((5, 2)))
    assert log.rate is None and log.times is None and log.duration is None
    with pytest.raises(ValueError, match="`time` selection needs a time axis"):
        log.select(time=(0, 1))


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"coeffs": np.zeros(5)}, ValueError, r"`coeffs` must be 2-D .* got 1-D"),
        ({"coeffs": np.zeros((2, 2, 2))}, ValueError, r"`coeffs` must be 2-D"),
        ({"coeffs": np.zeros((0, 3))}, ValueError, r"at least one frame and one mode"),
        ({"coeffs": np.zeros((3, 0))}, ValueError, r"at least one frame and one mode"),
        ({"coeffs": np.zeros((3, 2), complex)}, TypeError, r"`coeffs` must be a real"),
        ({"coeffs": [["a", "b"]]}, TypeError, r"`coeffs` must be a real numeric"),
        ({"units": "mm"}, ValueError, r"`units` must be one of 'rad', 'nm', 'um', 'waves'"),
        ({"convention": "zemax"}, ValueError, r"`convention` must be one of"),
        ({"rate": -1.0}, ValueError, r"`rate` must be > 0.0; got -1.0"),
        ({"rate": "fast"}, TypeError, r"`rate` must be a real number"),
        ({"wavelength": 500.0}, ValueError, r"`wavelength` must be in metres"),
        ({"modes": [2, 3]}, ValueError, r"`modes` must have one entry per column .*\(3\); got 2"),
        ({"modes": [2, 3, 3]}, ValueError, r"`modes` must be unique; 3 appears"),
        ({"modes": [0, 1, 2]}, ValueError, r"`modes` must be noll indices >= 1; got 0"),
        ({"modes": ["a", "b", "c"]}, TypeError, r"`modes` must be int noll indices"),
        ({"convention": "labels"}, ValueError, r"`modes` is required when convention='labels'"),
        ({"convention": "labels", "modes": [1, 2, 3]}, TypeError, r"non-empty str labels"),
        ({"metadata": [1]}, TypeError, r"`metadata` must be a dict"),
        ({"metadata": {"x": object()}}, TypeError, r"`metadata` must be JSON-serialisable"),
        ({"metadata": {1: 2}}, TypeError, r"`metadata` keys must be str"),
        ({"metadata": {"x": float("nan")}}, ValueError, r"`metadata` must not hold NaN"),
        ({"nonfinite": "ignore"}, ValueError, r"`nonfinite` must be one of"),
        ({"timestamps": [0, 1]}, ValueError, r"`timestamps` must have shape \(4,\)"),
        ({"timestamps": [0, 1, 1, 2]}, ValueError, r"strictly increasing; duplicated at index 2"),
        ({"timestamps": [0, 2, 1, 3]}, ValueError, r"strictly increasing; decreasing at index 2"),
        ({"timestamps": [0, 1, np.nan, 3]}, ValueError, r"`timestamps` must be finite"),
    ],
)
def test_validation_errors(kwargs, exc, match):
    kwargs = dict(kwargs)
    coeffs = kwargs.pop("coeffs", np.zeros((4, 3)))
    if "timestamps" not in kwargs and "rate" not in kwargs:
        kwargs["rate"] = 10.0
    with pytest.raises(exc, match=match):
        ModalLog(coeffs, **kwargs)


def test_metadata_is_copied():
    meta = {"telescope": "LOST", "loop": "closed", "nested": {"a": [1, 2]}}
    log = make(metadata=meta)
    meta["nested"]["a"].append(3)
    assert log.metadata["nested"]["a"] == [1, 2]
    got = log.metadata
    got["telescope"] = "other"
    assert log.metadata["telescope"] == "LOST"


# ----------------------------------------------------------------- non-finite values
def test_nonfinite_raise_names_first_bad_value():
    x = np.zeros((10, 3))
    x[4, 1] = np.nan
    x[7, 2] = np.inf
    with pytest.raises(
        ValueError,
        match=r"2 NaN or infinite value\(s\) in 2 frame\(s\), first "
        r"at frame 4, column 1",
    ):
        ModalLog(x, rate=1.0)


def test_nonfinite_drop_keeps_true_times():
    x = np.arange(20.0).reshape(10, 2)
    x[3, 0] = np.nan
    x[6, 1] = -np.inf
    log = ModalLog(x, rate=100.0, nonfinite="drop")
    keep = [0, 1, 2, 4, 5, 7, 8, 9]
    np.testing.assert_array_equal(log.coeffs, np.arange(20.0).reshape(10, 2)[keep])
    np.testing.assert_allclose(log.times, np.array(keep) / 100.0)
    assert log.rate == 100.0
    assert log.repairs == ("nonfinite='drop': dropped 2 frame(s) holding 2 non-finite value(s)",)
    assert log.metadata["repairs"] == list(log.repairs)


def test_nonfinite_interpolate_matches_numpy_interp():
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.5, 1.5, 40)) * 1e-3  # ~1 kHz (below 10 Hz is warned)
    x = rng.standard_normal((40, 3))
    bad = np.zeros_like(x, dtype=bool)
    bad[[0, 5, 6, 39], 0] = True
    bad[[20], 2] = True
    y = x.copy()
    y[bad] = np.nan
    log = ModalLog(y, timestamps=t, nonfinite="interpolate")
    for j in range(3):
        good = ~bad[:, j]
        want = x[:, j].copy()
        want[~good] = np.interp(t[~good], t[good], x[good, j])
        np.testing.assert_array_equal(log.coeffs[:, j], want)
    assert "filled 5 non-finite value(s) in 5 frame(s)" in log.repairs[0]
    # the user's array is left alone
    assert np.isnan(y[0, 0])


def test_nonfinite_interpolate_all_bad_column():
    x = np.zeros((5, 2))
    x[:, 1] = np.nan
    with pytest.raises(ValueError, match=r"column 1 \(mode 3\) has no finite value"):
        ModalLog(x, rate=1.0, nonfinite="interpolate")


def test_nonfinite_drop_everything():
    with pytest.raises(ValueError, match="would leave an empty log"):
        ModalLog(np.full((3, 2), np.nan), rate=1.0, nonfinite="drop")


# ----------------------------------------------------------------- selection
def test_frame_slicing_moves_time_origin():
    log = make(T=100, rate=50.0)
    sub = log[10:30]
    assert sub.n_frames == 20
    assert sub.start_time == pytest.approx(0.2)
    np.testing.assert_allclose(sub.times, np.arange(10, 30) / 50.0)
    np.testing.assert_array_equal(sub.coeffs, log.coeffs[10:30])
    every2 = log[::2]
    assert every2.rate == 25.0
    np.testing.assert_allclose(every2.times, log.times[::2])
    with pytest.raises(TypeError, match="indexed by a frame slice"):
        log[3]
    with pytest.raises(ValueError, match="selects no frame"):
        log[50:50]
    with pytest.raises(ValueError, match="step must be positive"):
        log[::-1]


def test_time_window_half_open():
    log = make(T=100, rate=100.0, start_time=1.0)
    sub = log.select(time=(1.1, 1.2))
    np.testing.assert_allclose(sub.times, 1.0 + np.arange(10, 20) / 100.0)
    assert log.select(time=(None, 1.05)).n_frames == 5
    assert log.select(time=(1.95, None)).n_frames == 5
    with pytest.raises(ValueError, match="selects no frame"):
        log.select(time=(5.0, 6.0))
    with pytest.raises(TypeError, match=r"`time` must be a pair"):
        log.select(time=3.0)


def test_time_window_with_timestamps():
    t = np.array([0.0, 0.1, 0.25, 0.3, 0.7]) * 1e-3  # ~1 kHz (below 10 Hz is warned)
    log = ModalLog(np.arange(10.0).reshape(5, 2), timestamps=t)
    np.testing.assert_array_equal(log.select(time=(0.1e-3, 0.3e-3)).times, t[[1, 2]])


def test_select_and_drop_modes():
    log = make(M=6)  # Z2..Z7
    sub = log.select(modes=[4, "Z6", 5])
    assert sub.modes == [4, 6, 5]
    np.testing.assert_array_equal(sub.coeffs, log.coeffs[:, [2, 4, 3]])
    assert log.drop_modes([2, 3]).modes == [4, 5, 6, 7]
    assert log.without_piston_tiptilt().modes == [4, 5, 6, 7]
    with pytest.raises(ValueError, match=r"`modes` entry 11 is not a mode of this log"):
        log.select(modes=[11])
    with pytest.raises(ValueError, match="must not name a mode twice"):
        log.select(modes=[4, "Z4"])
    with pytest.raises(ValueError, match="leaves no mode"):
        log.drop_modes(log.modes)
    with pytest.raises(TypeError, match="entries must be mode indices or labels"):
        log.select(modes=[4.0])
    labelled = make(M=2, convention="labels", modes=["KL1", "KL2"])
    with pytest.raises(ValueError, match="needs Zernike modes"):
        labelled.without_piston_tiptilt()


# ----------------------------------------------------------------- conversions
def test_to_convention_published_tables():
    # Noll 2..11 -> ANSI: (n, m) pairs of Noll's table and j_ansi = (n(n+2)+m)/2
    noll = list(range(2, 12))
    ansi_of = {2: 2, 3: 1, 4: 4, 5: 3, 6: 5, 7: 7, 8: 8, 9: 6, 10: 9, 11: 12}
    fringe_of = {2: 2, 3: 3, 4: 4, 5: 6, 6: 5, 7: 8, 8: 7, 9: 11, 10: 10, 11: 9}
    x = np.random.default_rng(4).standard_normal((20, len(noll)))
    log = ModalLog(x, rate=1.0, modes=noll)
    ansi = log.to_convention("ansi")
    assert ansi.modes == sorted(ansi_of.values())
    for j, a in ansi_of.items():
        np.testing.assert_array_equal(ansi.select(modes=[a]).coeffs[:, 0], x[:, noll.index(j)])
    fringe = log.to_convention("fringe")
    assert fringe.modes == sorted(fringe_of.values())
    for j, f in fringe_of.items():
        np.testing.assert_array_equal(fringe.select(modes=[f]).coeffs[:, 0], x[:, noll.index(j)])
    back = fringe.to_convention("ansi").to_convention("noll")
    assert back.modes == noll
    np.testing.assert_array_equal(back.coeffs, x)
    assert log.to_convention("NOLL") is log
    with pytest.raises(ValueError, match="labelled .* no index"):
        make(M=1, convention="labels", modes=["KL1"]).to_convention("noll")


def test_without_piston_tiptilt_ansi():
    log = ModalLog(np.zeros((3, 5)), rate=1.0, modes=[0, 1, 2, 3, 4], convention="ansi")
    assert log.without_piston_tiptilt().modes == [3, 4]


def test_to_units_round_trip_and_wavelength_rules():
    log = make(units="rad", wavelength=600e-9)
    nm = log.to_units("nm")
    np.testing.assert_allclose(nm.coeffs, log.coeffs * 600.0 / (2 * np.pi), rtol=1e-15)
    np.testing.assert_allclose(nm.to_units("rad").coeffs, log.coeffs, rtol=1e-14)
    with pytest.raises(ValueError, match=r"`wavelength` \(5e-07 m\) differs"):
        log.to_units("nm", wavelength=500e-9)
    opd = make(units="nm")
    with pytest.raises(ValueError, match="`wavelength` \\(metres\\) is required"):
        opd.to_units("rad")
    rad = opd.to_units("rad", wavelength=500e-9)
    assert rad.wavelength == 500e-9
    np.testing.assert_allclose(rad.coeffs, opd.coeffs * 2 * np.pi / 500.0, rtol=1e-15)


def test_with_metadata():
    log = make(metadata={"a": 1}).with_metadata(loop="closed")
    assert log.metadata == {"a": 1, "loop": "closed"}


# ----------------------------------------------------------------- summary
def _slow_reference(x):
    """Pure-Python sample-by-sample Welford + pair co-moment: an independent algorithm."""
    T, M = x.shape
    state = np.zeros((8, M))
    last = np.full(M, np.nan)
    bad = np.zeros(M, dtype=np.int64)
    for t in range(T):
        for j in range(M):
            v = float(x[t, j])
            if not np.isfinite(v):
                bad[j] += 1
                last[j] = np.nan
                continue
            state[0, j] += 1
            d = v - state[1, j]
            state[1, j] += d / state[0, j]
            state[2, j] += d * (v - state[1, j])
            if np.isfinite(last[j]):
                state[3, j] += 1
                dx = last[j] - state[4, j]
                state[4, j] += dx / state[3, j]
                state[5, j] += (v - state[5, j]) / state[3, j]
                state[6, j] += dx * (v - state[5, j])
            last[j] = v
    return state, bad


def test_kernel_matches_slow_reference_with_gaps():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((57, 3))
    x[[3, 4, 30], 1] = np.nan
    x[10, 2] = np.inf
    state = np.zeros((8, 3))
    last = np.full(3, np.nan)
    bad = np.zeros(3, dtype=np.int64)
    for i0 in range(0, 57, 10):  # chunked, to exercise the carried last sample
        chunk_stats_update(np.ascontiguousarray(x[i0 : i0 + 10]), state, last, bad)
    ref_state, ref_bad = _slow_reference(x)
    np.testing.assert_allclose(state, ref_state, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(bad, ref_bad)


def test_kernel_callable_from_njit():
    from numba import njit

    @njit
    def caller(x, state, last, bad):
        chunk_stats_update(x, state, last, bad)
        out = np.empty((4, x.shape[1]))
        lag1_finalize(state, out[0], out[1], out[2], out[3])
        return out

    x = np.random.default_rng(6).standard_normal((30, 2))
    out = caller(x, np.zeros((8, 2)), np.full(2, np.nan), np.zeros(2, dtype=np.int64))
    np.testing.assert_allclose(out[0], x.mean(axis=0), rtol=1e-12)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_summarize_against_numpy_and_statsmodels(dtype):
    rng = np.random.default_rng(7)
    T = 5000
    # AR(1) columns with known structure plus a large offset (stability check)
    phi = np.array([0.0, 0.5, 0.95])
    x = np.zeros((T, 3))
    e = rng.standard_normal((T, 3))
    for t in range(1, T):
        x[t] = phi * x[t - 1] + e[t]
    x = (x + 1e4).astype(dtype)
    log = ModalLog(x, rate=1000.0)
    s = summarize(log, chunk_frames=333)
    xd = x.astype(np.float64)
    np.testing.assert_allclose(s.mean, xd.mean(axis=0), rtol=1e-13)
    np.testing.assert_allclose(s.std, xd.std(axis=0), rtol=1e-9)
    np.testing.assert_allclose(s.rms, np.sqrt((xd**2).mean(axis=0)), rtol=1e-12)
    ref = [acf(xd[:, j], nlags=1, fft=False)[1] for j in range(3)]
    np.testing.assert_allclose(s.lag1, ref, rtol=1e-9, atol=1e-12)
    assert s.count.tolist() == [T] * 3 and s.n_nonfinite.tolist() == [0, 0, 0]
    assert s.labels == ["Z2", "Z3", "Z4"] and s.units == "rad"


def test_summarize_raw_array_counts_nonfinite():
    x = np.random.default_rng(8).standard_normal((100, 2))
    x[[5, 50], 0] = np.nan
    s = summarize(x, chunk_frames=7)
    assert s.n_nonfinite.tolist() == [2, 0] and s.count.tolist() == [98, 100]
    np.testing.assert_allclose(s.mean[0], np.nanmean(x[:, 0]), rtol=1e-13)


def test_summarize_constant_and_single_frame():
    s = summarize(ModalLog(np.ones((5, 1)), rate=1.0))
    assert s.std[0] == 0 and np.isnan(s.lag1[0])
    s1 = summarize(ModalLog(np.ones((1, 1)), rate=1.0))
    assert s1.count[0] == 1 and np.isnan(s1.lag1[0])
    with pytest.raises(ValueError, match="`chunk_frames` must be an int >= 1"):
        summarize(ModalLog(np.ones((5, 1)), rate=1.0), chunk_frames=0)


def test_pickle_round_trip_stays_read_only():
    import pickle

    log = make(T=20, M=3, metadata={"loop": "open"}, units="nm", wavelength=5e-7)
    back = pickle.loads(pickle.dumps(log))
    np.testing.assert_array_equal(back.coeffs, log.coeffs)
    assert back.metadata == log.metadata and back.modes == log.modes and back.rate == log.rate
    assert not back.coeffs.flags.writeable


def test_summarize_progress_callback_counts_frames():
    seen = []
    summarize(make(T=1000, M=2), chunk_frames=300, progress=seen.append)
    assert seen == [300, 300, 300, 100]


def _mapped_rss_kib(name):
    """Resident KiB of the mappings of file ``name`` (from /proc/self/smaps)."""
    total, inside = 0, False
    with open("/proc/self/smaps") as fh:
        for line in fh:
            head = line.split()
            if head and "-" in head[0] and len(head) >= 5:  # a mapping header line
                inside = line.rstrip().endswith(name)
            elif inside and line.startswith("Rss:"):
                total += int(head[1])
    return total


@pytest.mark.skipif(not __import__("os").path.exists("/proc/self/smaps"), reason="Linux only")
def test_memmap_summary_releases_pages(tmp_path):
    """Scanning a 64 MiB read-only map must not leave it resident (madvise DONTNEED)."""
    x = np.lib.format.open_memmap(
        tmp_path / "big.npy", mode="w+", dtype=np.float64, shape=(1 << 18, 32)
    )
    x[:] = 1.0
    x.flush()
    del x
    mm = np.load(tmp_path / "big.npy", mmap_mode="r")
    log = ModalLog(mm, rate=1.0)  # finiteness scan
    s = summarize(log, chunk_frames=4096)
    assert s.mean[0] == 1.0
    resident = _mapped_rss_kib("big.npy")
    np.asarray(mm).sum()  # control: an ordinary full read leaves the map resident
    assert _mapped_rss_kib("big.npy") > 48 * 1024
    assert resident < 8 * 1024, f"{resident} KiB of the 64 MiB map stayed resident"


def test_huge_finite_values_are_not_mistaken_for_nonfinite():
    big = np.finfo(np.float64).max
    log = ModalLog(np.array([[big, big], [big, -big]]), rate=1.0)  # the sum overflows
    assert log.n_frames == 2 and log.repairs == ()


def test_mode_indices_beyond_the_exact_conversions_are_refused():
    # audit 9, centre: modes=[2**63] was accepted (label Z9223372036854775808) and failed in
    # every later conversion. Reference: Noll j has radial order n with
    # n (n + 1) / 2 < j <= (n + 1)(n + 2) / 2, so 2**58 is of order > 2**29 (refused) and
    # 2**57 of order < 2**29, which round-trips through ANSI exactly
    for j in (2**58, 2**63):
        with pytest.raises(ValueError, match=r"`modes` must be noll indices of radial order "
                                             r"<= 536870912"):
            ModalLog(np.zeros((3, 1)), rate=1.0, modes=[j])
    top = ModalLog(np.zeros((3, 2)), rate=1.0, modes=[2, 2**57])
    assert top.to_convention("ansi").to_convention("noll").modes == [2, 2**57]
