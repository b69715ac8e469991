"""Round 52 PART b (issue 27): archive files as other software writes them.

docs/ADVERSARIAL.md, "Round 52 PART b, issue 27": netCDF-4 packed integers (CF
``scale_factor`` / ``add_offset``) read as the coefficients (A55, A83: 1e4 x); a pandas
``to_hdf`` frame's column names not read (A60: a frame written z11..z2 labelled Z2..Z11)
and its time column read as a mode (A93); netCDF dimensions without coordinates (zeros)
read as timestamps or frame numbers (A56, A80, A85) and a string coordinate of mode
names not read (A85); CF time units "milliseconds since ..." read as seconds (A57, A78);
HDF5's lossy scale-offset filter and FITS tile quantization read without a word (A14,
A72, A19); rows of a chunked dataset never written read as zeros (A11); a pandas table
(``format="table"``) refused by listing PyTables' index arrays (A02); a netCDF-3 file told
"a CSV must be UTF-8" (A59); a file open by an SWMR writer called "corrupt" (K32).

References, all from outside the code: the files are built with h5py / astropy in the
layouts their writers use, as inspected in the round's files (pandas 3.1 + PyTables
3.11 ``to_hdf(format="fixed")``: group attribute ``pandas_type="frame"``, datasets
``blockN_values`` (frames x columns) and ``blockN_items`` (the column names); netCDF-4
(libnetcdf through xarray 2026.9): a dimension without a coordinate is a dimension-scale
dataset of zeros whose ``NAME`` attribute starts "This is a netCDF dimension but not a
netCDF variable"; a string coordinate is a 1-D variable-length string dataset attached
as the scale; the netCDF-3 magic bytes are ``CDF\\x01`` / ``CDF\\x02`` / ``CDF\\x05``);
the CF conventions (unpacked = packed x scale_factor + add_offset, the fill value matched
on the packed integers; time units "<unit> since <epoch>"); h5py's ``scaleoffset=0`` on
floats keeps whole steps from each chunk's minimum (HDF5's D-scaling); astropy's
``CompImageHDU`` default ``quantize_level=16`` is lossy; libhdf5's chunk index (chunks
never written are not stored). Expected values are computed with numpy from the arrays written.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import load
from modalinfo.io._common import reading
from modalinfo.io.files import LogFormatError

from ._archives import M, T
from ._archives import archive_log as _log
from ._archives import pandas_fixed as _pandas_fixed
from ._archives import pandas_table as _pandas_table

_PHONY = "This is a netCDF dimension but not a netCDF variable.         0"


def test_cf_packed_integers_are_unpacked(tmp_path):
    x = _log()
    packed = np.round(x / 1e-4).astype(np.int16)
    packed[10, 2] = -32768  # a missing cell: the fill value on the packed integers
    with h5py.File(tmp_path / "p.nc", "w") as f:
        d = f.create_dataset("coeffs", data=packed)
        d.attrs["scale_factor"] = np.float64(1e-4)
        d.attrs["add_offset"] = np.float64(0.25)
        d.attrs["_FillValue"] = np.int16(-32768)
    log = load(tmp_path / "p.nc", rate=1000.0, nonfinite="interpolate")
    expected = packed * 1e-4 + 0.25
    keep = np.ones_like(packed, dtype=bool)
    keep[10, 2] = False
    np.testing.assert_array_equal(log.coeffs[keep], expected[keep])
    assert "scale_factor" in log.metadata["cf_packing"]


def test_float_scale_factor_is_applied(tmp_path):
    x = _log().astype(np.float32)
    with h5py.File(tmp_path / "f.nc", "w") as f:
        d = f.create_dataset("coeffs", data=x / np.float32(0.5))
        d.attrs["scale_factor"] = np.float32(0.5)
    log = load(tmp_path / "f.nc", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, (x / np.float32(0.5)).astype(np.float64) * 0.5)


def test_pandas_frame_column_names_are_read(tmp_path):
    x = _log()
    names = [f"z{j}" for j in range(M + 1, 1, -1)]  # z7 .. z2: reversed
    _pandas_fixed(tmp_path / "r.h5", x, names)
    log = load(tmp_path / "r.h5", rate=1000.0)
    assert log.modes == list(range(M + 1, 1, -1))
    np.testing.assert_array_equal(log.coeffs, x)


def test_pandas_frame_time_column_is_the_time_axis(tmp_path):
    x = _log()
    t = np.arange(T) / 1000.0
    _pandas_fixed(tmp_path / "t.h5", np.column_stack([x, t]),
                  [f"z{j}" for j in range(2, M + 2)] + ["time"])
    log = load(tmp_path / "t.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(2, M + 2))
    assert log.rate == pytest.approx(1000.0)


def test_pandas_table_is_refused_by_name(tmp_path):
    _pandas_table(tmp_path / "tab.h5")
    with pytest.raises(LogFormatError, match=r"pandas HDFStore table .*format='fixed'"):
        load(tmp_path / "tab.h5")


def test_netcdf_dimension_without_coordinate_is_not_the_time(tmp_path):
    x = _log()
    with h5py.File(tmp_path / "d.nc", "w") as f:
        t = f.create_dataset("time", shape=(T,), dtype="f4")  # zeros
        t.make_scale(_PHONY)
        v = f.create_dataset("coeffs", data=x)
        v.dims[0].attach_scale(t)
    log = load(tmp_path / "d.nc")  # refused before: "timestamps not strictly increasing"
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.timestamps is None


def test_netcdf_frame_dimension_without_coordinate_is_not_frame_numbers(tmp_path):
    x = _log()
    with h5py.File(tmp_path / "fz.nc", "w") as f:
        t = f.create_dataset("frame", shape=(T,), dtype="f4")
        t.make_scale(_PHONY)
        f.create_dataset("coeffs", data=x).dims[0].attach_scale(t)
    np.testing.assert_array_equal(load(tmp_path / "fz.nc", rate=1000.0).coeffs, x)


def test_netcdf_string_coordinate_names_the_modes(tmp_path):
    x = _log()
    names = [f"z{j}" for j in range(M + 1, 1, -1)]
    with h5py.File(tmp_path / "s.nc", "w") as f:
        m = f.create_dataset("mode", data=names, dtype=h5py.string_dtype())
        m.make_scale("mode")
        f.create_dataset("coeffs", data=x).dims[1].attach_scale(m)
    log = load(tmp_path / "s.nc", rate=1000.0)
    assert log.modes == list(range(M + 1, 1, -1))


@pytest.mark.parametrize("unit, factor", [("milliseconds since 2026-06-01 10:00:00", 1e-3),
                                          ("seconds since 2026-06-01T10:00:00", 1.0),
                                          ("microseconds since 1970-01-01", 1e-6)])
def test_cf_time_units_since_an_epoch(tmp_path, unit, factor):
    x = _log()
    step = 1e-3 / factor  # one frame per ms, in the file's unit
    with h5py.File(tmp_path / "c.nc", "w") as f:
        f.create_dataset("time", data=np.arange(T) * step).attrs["units"] = unit
        f.create_dataset("coeffs", data=x)
    log = load(tmp_path / "c.nc")
    assert log.rate == pytest.approx(1000.0)


def test_lossy_scaleoffset_is_said(tmp_path):
    x = _log()
    with h5py.File(tmp_path / "so.h5", "w") as f:
        f.create_dataset("coeffs", data=x, chunks=(100, M), scaleoffset=0)
    log = load(tmp_path / "so.h5", rate=1000.0)
    with h5py.File(tmp_path / "so.h5") as f:
        np.testing.assert_array_equal(log.coeffs, f["coeffs"][()])  # what the file holds
    assert "scale-offset" in log.metadata["lossy_storage"]
    assert "to within +-1 (of" in log.metadata["lossy_storage"]


def test_lossless_storage_says_nothing(tmp_path):
    # lossless filters, a GZIP_2 image with quantize_level 0, and tiles astropy could not
    # quantize (6-pixel rows of a quantize_level 16 image: stored losslessly, ZSCALE 0)
    x = _log()
    with h5py.File(tmp_path / "gz.h5", "w") as f:
        f.create_dataset("coeffs", data=x, chunks=(100, M), compression="gzip")
    fits.CompImageHDU(data=x.astype(np.float32), quantize_level=0.0,
                      compression_type="GZIP_2").writeto(tmp_path / "l.fz")
    assert "lossy_storage" not in load(tmp_path / "gz.h5", rate=1000.0).metadata
    assert "lossy_storage" not in load(tmp_path / "l.fz", rate=1000.0).metadata
    fits.CompImageHDU(data=x.astype(np.float32)).writeto(tmp_path / "six.fz")
    six = load(tmp_path / "six.fz", rate=1000.0)
    np.testing.assert_array_equal(six.coeffs, x.astype(np.float32))
    assert "lossy_storage" not in six.metadata


def test_quantized_tile_compression_is_said(tmp_path):
    x = np.repeat(_log(), 4, axis=1).astype(np.float32)  # 24-pixel rows: tiles quantize
    fits.CompImageHDU(data=x).writeto(tmp_path / "q.fits.fz")  # astropy's default: lossy
    log = load(tmp_path / "q.fits.fz", rate=1000.0)
    assert np.max(np.abs(log.coeffs - x)) > 0  # the quantization did lose digits
    assert "quantized" in log.metadata["lossy_storage"]


def test_lossy_storage_note_on_the_command_line(tmp_path, capsys):
    from modalinfo.cli import main

    with h5py.File(tmp_path / "so.h5", "w") as f:
        f.create_dataset("coeffs", data=_log(), chunks=(100, M), scaleoffset=0)
    assert main(["convert", str(tmp_path / "so.h5"), str(tmp_path / "o.npz"), "--rate",
                 "1000", "--quiet"]) == 0
    assert "lossy scale-offset filter" in capsys.readouterr().err


def test_rows_never_written_are_refused(tmp_path):
    x = _log()
    with h5py.File(tmp_path / "g.h5", "w") as f:
        d = f.create_dataset("coeffs", shape=(1000, M), maxshape=(None, M), chunks=(100, M),
                             dtype="f8")
        d[:T] = x  # rows 400..999 never written
    with pytest.raises(LogFormatError, match=r"rows 400\.\.999 .* never written"):
        load(tmp_path / "g.h5", rate=1000.0)


def test_rows_all_written_are_read(tmp_path):
    x = _log()
    with h5py.File(tmp_path / "w.h5", "w") as f:
        d = f.create_dataset("coeffs", shape=(0, M), maxshape=(None, M), chunks=(64, M),
                             dtype="f8")
        d.resize(T, axis=0)
        d[:] = x
    np.testing.assert_array_equal(load(tmp_path / "w.h5", rate=1000.0).coeffs, x)


@pytest.mark.parametrize("magic", [b"CDF\x01", b"CDF\x02", b"CDF\x05"])
def test_netcdf3_is_named(tmp_path, magic):
    path = tmp_path / "n3.nc"
    path.write_bytes(magic + bytes(60) + b"\x80\x90" * 40)
    with pytest.raises(LogFormatError, match="netCDF-3"):
        load(path)


def test_file_open_by_a_writer_is_not_corrupt(tmp_path):
    # libhdf5's message when an SWMR writer has the file open (K32), through `reading`
    path = tmp_path / "busy.h5"
    with pytest.raises(LogFormatError) as info, reading("HDF5", path):
        raise OSError("Unable to synchronously open file (file is already open for write "
                      "(may use <h5clear file> to clear file consistency flags))")
    assert "open for writing by another process" in str(info.value)
    assert "corrupt" not in str(info.value)
