"""Integer timestamps (ns or us since 1970) keep their intervals exact in every reader.

Reference: exact integer arithmetic (Python ints) on the times written, and IEEE 754
spacing (numpy.spacing: float64 seconds near 1.76e9 step by 2.4e-7 s, so a 500 us
interval converted frame by frame reads 499.76 or 500.00 us). A 2 kHz log of int64 ns
with one 10-frame gap must read with every interval 500 us to float64 rounding of the
interval itself, jitter none (< 1e-6, ``modalinfo info``'s word), the one gap where it
is, and its exact first time in the metadata.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.information.selection import _check_simultaneous
from modalinfo.io import load
from modalinfo.telemetry import ModalLog

T0 = 1_764_000_000_123_456_789  # ns since 1970, 2025-11-24
N = 300
STEP = 500_000  # ns: 2 kHz


def _times(t0=T0, unit=1):
    k = np.r_[np.arange(100), np.arange(110, 110 + N - 100)]  # frames 100-109 dropped
    return (t0 + k.astype(np.int64) * STEP) // unit


def _coeffs():
    return np.random.default_rng(0).standard_normal((N, 2))


def _write(path, fmt, t, name="time_ns"):
    c = _coeffs()
    if fmt == "csv":
        rows = "".join(f"{int(a)},{float(x)!r},{float(y)!r}\n"
                       for a, (x, y) in zip(t, c, strict=True))
        path.write_text(f"{name},Z2,Z3\n" + rows)
    elif fmt == "npz":
        np.savez(path, coefficients=c, **{name: t})
    elif fmt == "hdf5":
        with h5py.File(path, "w") as f:
            f["coefficients"] = c
            f[name] = t
    else:
        cols = [fits.Column(name=name, format="K", array=t)]
        cols += [fits.Column(name=f"Z{j + 2}", format="D", array=c[:, j]) for j in range(2)]
        fits.BinTableHDU.from_columns(cols).writeto(path)
    return path


def test_float64_seconds_cannot_hold_the_interval():
    t = _times()
    assert np.spacing(T0 / 1e9) > 2e-7
    assert len(set(np.diff(t.astype(np.float64) / 1e9)[:99].tolist())) > 1  # "jitter"


@pytest.mark.parametrize("fmt, ext", [("csv", "csv"), ("npz", "npz"), ("hdf5", "h5"),
                                      ("fits", "fits")])
def test_every_reader_keeps_integer_intervals_exact(tmp_path, fmt, ext):
    t = _times()
    log = load(_write(tmp_path / f"ns.{ext}", fmt, t))
    exact = [(int(a) - T0) for a in t]  # Python ints: exact
    np.testing.assert_array_equal(np.round(log.timestamps * 1e9).astype(np.int64), exact)
    assert log.timestamps[0] == 0.0
    dt = np.diff(log.timestamps)
    regular = np.delete(dt, 99)
    np.testing.assert_allclose(regular, 5e-4, rtol=1e-12, atol=0)
    s = log.sampling()
    assert s.jitter < 1e-6 and s.median_rate == pytest.approx(2000.0, rel=1e-12)
    assert s.gap_after.tolist() == [99]
    assert s.gap_duration[0] == pytest.approx(11 * 5e-4, rel=1e-12)
    assert log.metadata["file_start_time_exact"] == f"{T0} ns"
    assert log.metadata["file_start_time"] == T0 / 10**9  # correctly rounded


def test_microseconds_since_1970_too(tmp_path):
    t = _times(unit=1000)  # us: 1.76e15 < 2^53, but float64 seconds step by 2.4e-7
    log = load(_write(tmp_path / "us.npz", "npz", t, "time_us"))
    np.testing.assert_allclose(np.delete(np.diff(log.timestamps), 99), 5e-4, rtol=1e-12)
    assert log.metadata["file_start_time_exact"] == f"{T0 // 1000} us"


def test_small_integer_and_float_times_are_read_as_before(tmp_path):
    t = np.arange(N, dtype=np.int64) * 500  # us from 0: float64 holds them to 1e-16
    log = load(_write(tmp_path / "small.npz", "npz", t, "time_us"))
    np.testing.assert_array_equal(log.timestamps, t.astype(np.float64) * 1e-6)
    assert "file_start_time" not in log.metadata


def test_the_constructor_refuses_integers_float64_cannot_hold():
    with pytest.raises(ValueError, match=r"`timestamps` .*> 2\^53; ns since 1970"):
        ModalLog(_coeffs(), timestamps=_times())
    with pytest.warns(UserWarning, match="below 10 Hz"):  # 1 Hz frame times (fixes 40-a)
        log = ModalLog(_coeffs(), timestamps=np.arange(N, dtype=np.int64))  # exact: accepted
    assert log.sampling().jitter == 0.0


def test_extra_logs_of_one_clock_are_compared_by_their_first_times(tmp_path):
    a = load(_write(tmp_path / "a.npz", "npz", _times()))
    same = load(_write(tmp_path / "b.npz", "npz", _times()))
    later = load(_write(tmp_path / "c.npz", "npz", _times(T0 + 5 * 10**9)))
    _check_simultaneous(a, same)
    with pytest.raises(ValueError, match="must be sampled at the frames of `data`"):
        _check_simultaneous(a, later)
