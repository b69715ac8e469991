"""Stop 59's small items (fix53-c, issue 27): a batch folder search takes every file the
readers take.

docs/ADVERSARIAL.md, "Round 52 PART b" (Left, A73): ``modalinfo batch`` skipped a
netCDF-4 ``.nc`` log and a tile-compressed FITS ``.fz`` / ``.fits.fz`` log of a folder
("their extension is not a log's") while ``info`` / ``convert`` read them.

References, from outside the code: the files are written by h5py (a netCDF-4 file is an
HDF5 file, the netCDF-4 format specification) and by astropy's ``CompImageHDU``
(fpack's tile compression); the expected coefficients are the numpy arrays written, and
the folder's own listing (``os.listdir``) says which files there are.
"""

from __future__ import annotations

import os

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.batch.manifest import collect_logs
from modalinfo.io import load, save
from modalinfo.io.files import LogFormatError


def _coeffs():
    return np.random.default_rng(53).normal(size=(200, 4)).astype(np.float32)


def _folder(tmp_path):
    x = _coeffs()
    with h5py.File(tmp_path / "a.nc", "w") as f:
        f.create_dataset("coeffs", data=x)
    fits.CompImageHDU(data=x, quantize_level=0.0, compression_type="GZIP_2").writeto(
        tmp_path / "b.fits.fz")
    fits.CompImageHDU(data=x, quantize_level=0.0, compression_type="GZIP_1").writeto(
        tmp_path / "c.fz")
    return x


def test_folder_search_lists_netcdf_and_fpacked_logs(tmp_path):
    x = _folder(tmp_path)
    skipped: list[str] = []
    entries = collect_logs(tmp_path, skipped=skipped)
    assert sorted(os.path.basename(e.path) for e in entries) == sorted(os.listdir(tmp_path))
    assert skipped == []
    for entry in entries:  # each is a log the readers take: the rows will not be errors
        np.testing.assert_array_equal(load(entry.path, rate=1000.0).coeffs, x)


def test_netcdf3_named_nc_is_still_named(tmp_path):
    # a netCDF-3 file keeps its refusal (CDF\x01 magic) though .nc now means HDF5
    path = tmp_path / "n3.nc"
    path.write_bytes(b"CDF\x01" + bytes(60) + b"\x80\x90" * 40)
    assert [os.path.basename(e.path) for e in collect_logs(tmp_path)] == ["n3.nc"]
    with pytest.raises(LogFormatError, match="netCDF-3"):
        load(path)


@pytest.mark.parametrize("name", ["o.nc", "o.fz", "o.fits.fz"])
def test_save_does_not_write_a_read_only_extension(tmp_path, name):
    # modalinfo writes neither netCDF's conventions nor fpack's tiles: a name that says so
    # would mislead ncdump / funpack
    log = load(_write_npz(tmp_path))
    with pytest.raises(ValueError, match="cannot tell the format"):
        save(log, tmp_path / name)
    assert not (tmp_path / name).exists()


def _write_npz(tmp_path):
    path = tmp_path / "src.npz"
    np.savez(path, coeffs=_coeffs(), rate=1000.0)
    return path
