"""Mutation round 36 (review36): the first frame's date from a CF time unit (fix53-c).

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"): integer minutes and
nanoseconds since an epoch, an epoch's fraction of a second, and float values in a unit
other than the second from a first value other than 0 were never read.

References (outside the code): the CF conventions ("<unit> since <epoch>", UTC without a
zone) and numpy ``datetime64`` arithmetic for the expected dates.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo.io import load

T, M = 300, 4


def _nc(path, unit, times):
    with h5py.File(path, "w") as f:
        f.create_dataset("time", data=times).attrs["units"] = unit
        f.create_dataset("coeffs", data=np.random.default_rng(36).normal(size=(T, M)))
    return path


def _iso(stamp: np.datetime64) -> str:
    return str(stamp.astype("datetime64[us]")).removesuffix(".000000")


EPOCH = np.datetime64("2026-11-01T05:00:00")


@pytest.mark.parametrize("unit, times, first, rate", [
    ("minutes since 2026-11-01 05:00:00", 90 + np.arange(T, dtype=np.int64),
     EPOCH + np.timedelta64(90, "m"), 1.0 / 60.0),
    ("nanoseconds since 2026-11-01 05:00:00", 7_000_000 + np.arange(T, dtype=np.int64)
     * 1_000_000, EPOCH + np.timedelta64(7, "ms"), 1000.0),
    ("hours since 2026-11-01 05:00:00", 2.5 + np.arange(T) / 3.6e6,
     EPOCH + np.timedelta64(150, "m"), 1000.0),
    ("seconds since 2026-11-01 05:00:00.25", np.arange(T) * 1e-3,
     EPOCH + np.timedelta64(250, "ms"), 1000.0),
])
def test_the_first_frames_date(tmp_path, unit, times, first, rate):
    if rate < 10.0:  # a minute apart: the slow-clock warning, then the log as given
        with pytest.warns(UserWarning, match="frame rate of 0.0167 Hz"):
            log = load(_nc(tmp_path / "c.nc", unit, times))
    else:
        log = load(_nc(tmp_path / "c.nc", unit, times))
    assert log.rate == pytest.approx(rate, rel=1e-6)
    assert log.metadata["date"] == _iso(first)
