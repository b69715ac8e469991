"""Stop 59's small items (fix53-c, issue 27): a netCDF time unit's epoch is kept.

docs/ADVERSARIAL.md, "Round 52 PART b" (Left): "seconds since 2026-11-01 05:00:00" was
read as seconds and its start date dropped. The log now keeps the date of its first
frame as ``metadata["date"]``, the key the AOT reader fills from DATE-BEG and the FITS
writer writes as DATE-OBS, and ``convert`` carries it. A "minutes since" / "hours since"
unit was not understood at all (read as seconds from the name ``time``).

References, from outside the code: the CF conventions (time units "<unit> since
<epoch>", UTC when the epoch names no zone, a ``calendar`` attribute other than
standard / gregorian / proleptic_gregorian counts days otherwise), the expected dates
computed with numpy ``datetime64`` arithmetic, the FITS card read back by astropy.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.cli import main
from modalinfo.io import load

T, M = 300, 4


def _nc(path, unit, times, calendar=None):
    with h5py.File(path, "w") as f:
        t = f.create_dataset("time", data=times)
        t.attrs["units"] = unit
        if calendar is not None:
            t.attrs["calendar"] = calendar
        f.create_dataset("coeffs", data=np.random.default_rng(53).normal(size=(T, M)))
    return path


def _iso(stamp: np.datetime64) -> str:
    return str(stamp.astype("datetime64[us]")).removesuffix(".000000")


@pytest.mark.parametrize("unit, times, first", [
    ("seconds since 2026-11-01 05:00:00", 3600.0 + np.arange(T) * 1e-3,
     np.datetime64("2026-11-01T05:00:00") + np.timedelta64(3600, "s")),
    ("milliseconds since 2026-11-01T05:00:00Z", np.arange(T, dtype=np.int64) + 250,
     np.datetime64("2026-11-01T05:00:00") + np.timedelta64(250, "ms")),
    ("microseconds since 2026-11-01 06:30:00 +01:30", np.arange(T, dtype=np.int64) * 1000,
     np.datetime64("2026-11-01T05:00:00")),
    ("seconds since 2026-11-1 5:0:0", np.arange(T) * 1e-3, np.datetime64("2026-11-01T05:00:00")),
])
def test_epoch_is_kept_as_the_first_frames_date(tmp_path, unit, times, first):
    log = load(_nc(tmp_path / "c.nc", unit, times))
    assert log.rate == pytest.approx(1000.0)
    assert log.metadata["date"] == _iso(first)


def test_minutes_since_an_epoch_are_minutes(tmp_path):
    log = load(_nc(tmp_path / "m.nc", "minutes since 2026-11-01 05:00:00",
                   np.arange(T) / 60000.0))
    assert log.rate == pytest.approx(1000.0)  # read as seconds before: 60 kHz
    assert log.metadata["date"] == "2026-11-01T05:00:00"


def test_other_calendars_keep_no_date(tmp_path):
    # a 360-day or no-leap calendar counts the days since the epoch otherwise: no date
    log = load(_nc(tmp_path / "n.nc", "seconds since 2026-11-01 05:00:00",
                   np.arange(T) * 1e-3, calendar="360_day"))
    assert log.rate == pytest.approx(1000.0)
    assert "date" not in log.metadata


@pytest.mark.parametrize("out", ["o.npz", "o.h5", "o.fits", "o.csv"])
def test_the_date_goes_through_convert(tmp_path, out):
    src = _nc(tmp_path / "c.nc", "seconds since 2026-11-01 05:00:00", np.arange(T) * 1e-3)
    assert main(["convert", str(src), str(tmp_path / out), "--quiet"]) == 0
    assert load(tmp_path / out).metadata["date"] == "2026-11-01T05:00:00"
    if out.endswith(".fits"):
        assert fits.getheader(tmp_path / out)["DATE-OBS"] == "2026-11-01T05:00:00"
