"""Round 28 PART b: time columns whose unit the file states, or that cannot be a frame clock.

References (outside the code): numpy's own unit conversion of datetime64 / timedelta64
(``np.timedelta64(500, "us")`` is 500,000 ns, so a 2 kHz log has intervals of exactly
5e-4 s and a rate of 2000 Hz); the float64 spacing of day numbers (``np.spacing(61009.0)``
is 7.3e-12 d = 0.63 us, ``np.spacing(2461009.5)`` 4.7e-10 d = 40 us), which cannot carry
a 0.5 ms frame clock, so a time column in days must be refused, not read as a mode; the
FITS standard's TUNITn keyword (a stated unit not read must not be taken as seconds); the
HDF5 format's recorded end of file (a file cut short after reading cannot be reopened for
its checksum: the error must name the file).
"""

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

N, FS = 400, 2000.0


def _coeffs():
    rng = np.random.default_rng(28)
    return rng.normal(0.0, 0.1, (N, 3))


def test_timedelta64_time_read_in_its_unit(tmp_path):
    path = tmp_path / "td.npz"
    np.savez(path, coefficients=_coeffs(), time=np.arange(N) * np.timedelta64(500, "us"))
    log = load(path)
    np.testing.assert_allclose(np.diff(log.timestamps), 1.0 / FS, rtol=1e-12)
    assert log.n_modes == 3


def test_datetime64_time_read_relative_and_start_kept(tmp_path):
    path = tmp_path / "dt.npz"
    start = np.datetime64("2026-11-30T06:00:00", "ns")
    times = start + np.arange(N) * np.timedelta64(500_000, "ns")
    np.savez(path, coefficients=_coeffs(), time=times)
    log = load(path)
    np.testing.assert_allclose(np.diff(log.timestamps), 1.0 / FS, rtol=1e-12)
    assert "2026-11-30T06:00:00" in str(log.metadata.get("file_start_date"))


@pytest.mark.parametrize("name", ["mjd", "jd", "time [d]"])
def test_day_time_column_refused_not_read_as_a_mode(tmp_path, name):
    x = _coeffs()
    days = 61009.25 + np.arange(N) / FS / 86400.0
    if name == "jd":
        days = days + 2400000.5
    path = tmp_path / "days.csv"
    header = ",".join([name, "Z2", "Z3", "Z4"])
    np.savetxt(path, np.column_stack([days, x]), delimiter=",", header=header, comments="",
               fmt="%.17g")
    with pytest.raises(LogFormatError, match="days"):
        load(path)


def test_float_epoch_seconds_say_their_intervals_are_quantised(tmp_path):
    # GPS seconds near 1.45e9 s: np.spacing is 2.4e-7 s, 4.8e-4 of a 0.5 ms interval,
    # so the stored intervals are 499.96 or 500.20 us (numpy's own float64 rounding)
    times = 1448517618.0 + np.arange(N) / FS
    assert len(np.unique(np.diff(times))) > 1  # the reference: quantised in the file
    path = tmp_path / "gps.npz"
    np.savez(path, coefficients=_coeffs(), time=times)
    note = str(load(path).metadata.get("time_axis", ""))
    assert "quantised by 2.38e-07 s" in note


def test_float_seconds_from_the_start_need_no_note(tmp_path):
    path = tmp_path / "rel.npz"
    np.savez(path, coefficients=_coeffs(), time=np.arange(N) / FS)
    assert "time_axis" not in load(path).metadata


def test_fits_time_column_with_a_unit_not_read_is_refused(tmp_path):
    # FITS standard: TUNITn states the column's unit; 'yr' is a time unit modalinfo does
    # not read, so the column must not be taken as seconds (it was: 2000 Hz reported)
    from astropy.io import fits

    x = _coeffs()
    cols = [fits.Column(name="TIME", format="D", array=np.arange(N) / FS, unit="yr")]
    cols += [fits.Column(name=f"Z{j + 2}", format="D", array=x[:, j]) for j in range(3)]
    path = tmp_path / "yr.fits"
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(cols)]).writeto(path)
    with pytest.raises(LogFormatError, match="TUNIT 'yr'"):
        load(path)


def test_hdf5_truncated_after_reading_names_the_file(tmp_path):
    # Reference: the HDF5 format records the file's end (stored_eof); a file cut short
    # after it was read cannot be opened for its checksum: one error naming the file
    from modalinfo.io import integrity_check, save
    from modalinfo.telemetry.log import ModalLog

    path = tmp_path / "cut.h5"
    save(ModalLog(_coeffs(), rate=FS, modes=[2, 3, 4]), path)
    log = load(path)
    with open(path, "r+b") as fh:
        fh.truncate(path.stat().st_size // 2)
    with pytest.raises(LogFormatError, match="cut.h5"):
        integrity_check(path, log)


@pytest.mark.parametrize("suffix", [".npz", ".h5"])
def test_day_array_beside_seconds_is_not_the_time_axis(tmp_path, suffix):
    # guard of the day refusal: a file carrying both `time` (s) and `mjd` reads `time`
    import h5py

    path = tmp_path / f"both{suffix}"
    times = np.arange(N) / FS
    arrays = {"coefficients": _coeffs(), "time": times, "mjd": 61009.25 + times / 86400.0}
    if suffix == ".npz":
        np.savez(path, **arrays)
    else:
        with h5py.File(path, "w") as f:
            for key, value in arrays.items():
                f[key] = value
    log = load(path)
    np.testing.assert_allclose(np.diff(log.timestamps), 1.0 / FS, rtol=1e-9)
    assert log.n_modes == 3
