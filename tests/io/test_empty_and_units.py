"""Logs with zero modes in every format, AOT coefficient units, and sizes without dask.

References: the documented error contract of ``modalinfo.io`` (a ``LogFormatError``
naming the file; here it must also say "no modes"); the README's "Foreign logs"
promise (a unit the file does not record is marked assumed); the SI/IEC definitions
of the metre and its prefixes (1 m = 1e9 nm, 1 um = 1e-6 m) for an AOT image in
metres, microns or nanometres under any spelling; and
``dask.utils.parse_bytes`` / ``format_bytes`` (another library) for
:func:`modalinfo.common.sizes.parse_size` / ``format_size``.
"""

from __future__ import annotations

import warnings

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.common.sizes import format_size, parse_size
from modalinfo.io import LogFormatError, load


def _aot_file(path, coeffs, unit):
    """An AOT file written with aotpy alone, one loop whose coefficients carry ``unit``."""
    aotpy = pytest.importorskip("aotpy")
    tel = aotpy.MainTelescope(uid="TEL", enclosing_diameter=8.0)
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    wfs = aotpy.ShackHartmann(uid="W", source=ngs, n_valid_subapertures=6)
    dm = aotpy.DeformableMirror(uid="DM", telescope=tel, n_valid_actuators=40)
    loop = aotpy.ControlLoop(uid="L", input_sensor=wfs, commanded_corrector=dm,
                             framerate=1000.0,
                             modal_coefficients=aotpy.Image("c", coeffs, unit=unit))
    system = aotpy.AOSystem(ao_mode="SCAO", main_telescope=tel, sources=[ngs],
                            wavefront_sensors=[wfs], wavefront_correctors=[dm], loops=[loop])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system.write_to_file(str(path))
    return path


def _zero_mode_files(tmp_path):
    empty = np.zeros((10, 0))
    files = {}
    np.savez(tmp_path / "plain.npz", data=empty)
    files["npz"] = tmp_path / "plain.npz"
    np.save(tmp_path / "plain.npy", empty)
    files["npy"] = tmp_path / "plain.npy"
    with h5py.File(tmp_path / "plain.h5", "w") as fh:
        fh["data"] = empty
    files["hdf5"] = tmp_path / "plain.h5"
    fits.PrimaryHDU(empty).writeto(tmp_path / "image.fits")
    files["fits"] = tmp_path / "image.fits"
    fits.BinTableHDU.from_columns([fits.Column(name="time", format="D",
                                               array=np.arange(5.0))]).writeto(
        tmp_path / "table.fits")
    files["fits table"] = tmp_path / "table.fits"
    (tmp_path / "times.csv").write_text("time\n0\n0.001\n0.002\n")
    files["csv"] = tmp_path / "times.csv"
    files["aot"] = _aot_file(tmp_path / "empty_aot.fits", empty, "rad")
    return files


def test_zero_modes_is_one_refusal_naming_the_file_in_every_format(tmp_path):
    for kind, path in _zero_mode_files(tmp_path).items():
        for mmap in (False, True):
            with pytest.raises(LogFormatError) as info:
                load(path, mmap=mmap)
            text = str(info.value)
            assert path.name in text and "no modes" in text, (kind, text)


def test_aot_without_a_unit_is_rad_assumed_and_says_so(tmp_path):
    coeffs = np.arange(12.0).reshape(4, 3)
    log = load(_aot_file(tmp_path / "none.fits", coeffs, None))
    # no mode images either: the Noll labels are assumed too (round 10 PART b, A01)
    assert log.units == "rad" and log.metadata["assumed"] == {"units": "rad",
                                                               "modes": "Z2..Z4 (noll)"}
    stated = load(tmp_path / "none.fits", units="nm")
    assert stated.units == "nm" and "units" not in stated.metadata["assumed"]
    assert np.array_equal(stated.coeffs, coeffs)


@pytest.mark.parametrize("unit", ["rad/s", "furlong", "V", "pix"])
def test_aot_with_a_unit_that_is_not_phase_is_refused_unless_stated(tmp_path, unit):
    coeffs = np.arange(12.0).reshape(4, 3)
    path = _aot_file(tmp_path / "odd.fits", coeffs, unit)
    with pytest.raises(LogFormatError, match="is not a unit of phase") as info:
        load(path)
    assert repr(unit) in str(info.value) and "odd.fits" in str(info.value)
    log = load(path, units="waves")  # the caller states what the card got wrong
    assert log.units == "waves" and log.metadata["aot_unit"] == unit
    assert np.array_equal(log.coeffs, coeffs)


@pytest.mark.parametrize("unit, ours, factor", [
    ("rad", "rad", 1.0), ("radians", "rad", 1.0), ("NM", "nm", 1.0),
    ("microns", "um", 1.0), ("m", "nm", 1e9), ("meters", "nm", 1e9), ("waves", "waves", 1.0),
])
def test_aot_phase_and_length_units_are_read(tmp_path, unit, ours, factor):
    coeffs = np.arange(1.0, 13.0).reshape(4, 3) * 1e-7
    log = load(_aot_file(tmp_path / "u.fits", coeffs, unit))
    assert log.units == ours and log.metadata["assumed"] == {"modes": "Z2..Z4 (noll)"}
    np.testing.assert_allclose(log.coeffs, coeffs * factor, rtol=1e-15)


_METRES = {"nm": 1e-9, "um": 1e-6}  # SI: what one unit of our length units is in metres


@pytest.mark.parametrize("unit, metres", [
    ("micron", 1e-6), ("microns", 1e-6), ("micrometer", 1e-6), ("micrometres", 1e-6),
    ("um", 1e-6), ("nanometer", 1e-9), ("nanometres", 1e-9), ("nm", 1e-9),
    ("metre", 1.0), ("meters", 1.0), ("m", 1.0),
])
def test_aot_length_spellings_keep_the_physical_length(tmp_path, unit, metres):
    # every spelling of a length unit: the values read, times the SI size of the unit the
    # reader names, are the file's values times the SI size of the file's unit
    coeffs = np.arange(1.0, 13.0).reshape(4, 3)
    log = load(_aot_file(tmp_path / "u.fits", coeffs, unit))
    np.testing.assert_allclose(np.asarray(log.coeffs) * _METRES[log.units], coeffs * metres,
                               rtol=1e-12)


def test_aot_unit_contradicting_the_hint_is_refused(tmp_path):
    path = _aot_file(tmp_path / "nm.fits", np.ones((4, 3)), "nm")
    with pytest.raises(ValueError, match="contradicts"):
        load(path, units="rad")


SIZES = ["2GB", "512 MiB", "2e9", "100", "1.5k", "5 kB", "1Ki", "3 t", "2gb", "0", ".5G",
         "7.", "2 GiB", "1.5e3MB", "4TiB", " 8 mb ",
         "1.7", "2.5B", "1.0001 kB"]  # fractions of a byte: rounded down, as dask does


@pytest.mark.parametrize("text", SIZES)
def test_parse_size_reads_sizes_as_dask_does(text):
    dask_utils = pytest.importorskip("dask.utils")
    assert parse_size(text) == dask_utils.parse_bytes(text)


@pytest.mark.parametrize("n", [5, 1000, 256 * 2**20, 1.5e9, 3e12])
def test_format_size_as_dask(n):
    dask_utils = pytest.importorskip("dask.utils")
    assert format_size(n) == dask_utils.format_bytes(n)


@pytest.mark.parametrize("text", ["-2GB", "plenty", "2 GBs", "inf", "nan", "", "1e400", True,
                                  None, float("inf"), -1.0])
def test_parse_size_refuses_what_is_not_a_size(text):
    with pytest.raises(ValueError, match="memory_limit"):
        parse_size(text, "memory_limit")


def test_parse_size_needs_no_dask(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "dask", None)
    monkeypatch.setitem(sys.modules, "dask.utils", None)
    assert parse_size("2GB") == 2 * 10**9 and parse_size("1 KiB") == 1024


def test_csv_with_a_byte_order_mark_reads_its_first_name(tmp_path):
    rows = np.arange(1.0, 21.0).reshape(10, 2)
    text = "Z2,Z3\n" + "".join(f"{a!r},{b!r}\n" for a, b in rows.tolist())
    (tmp_path / "excel.csv").write_text(text, encoding="utf-8-sig")  # a spreadsheet export
    log = load(tmp_path / "excel.csv", rate=100.0)
    assert log.modes == [2, 3] and np.array_equal(log.coeffs, rows)


def test_atomic_write_refuses_a_special_file(tmp_path):
    import os
    import stat

    from modalinfo.common.files import atomic_write

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="is a FIFO, not a regular file"):
        atomic_write(fifo, lambda fh: fh.write(b"x"), overwrite=True)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
