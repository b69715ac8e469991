"""Every writer refuses to replace a file unasked, and writes atomically.

Reference: the documented contract of the writers (``overwrite=False`` raises
``FileExistsError`` and leaves the file byte-for-byte unchanged; ``overwrite=True``
replaces it; a crash while writing leaves the previous file intact and no temporary
file), checked for each format through its own writer and through ``save``; the
content read back with the independent libraries (astropy, h5py, numpy).
"""

from __future__ import annotations

import os

import h5py
import numpy as np
import pytest
from astropy.io import fits

import modalinfo.io as mio
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

X = np.random.default_rng(3).standard_normal((40, 3))
WRITERS = {"npz": mio.write_npz, "csv": mio.write_csv, "fits": mio.write_fits,
           "h5": mio.write_hdf5}


def _read_independently(path, ext):
    if ext == "fits":
        with fits.open(path) as hdul:
            return np.array(hdul[0].data, dtype=float)
    if ext == "h5":
        with h5py.File(path, "r") as f:
            return f["coefficients"][...]
    return load(path).coeffs


@pytest.mark.parametrize("ext", WRITERS)
def test_writer_refuses_to_overwrite_then_replaces_when_asked(tmp_path, ext):
    write = WRITERS[ext]
    path = tmp_path / f"a.{ext}"
    write(ModalLog(X, rate=10.0), path)
    before = path.read_bytes()
    with pytest.raises(FileExistsError, match=rf"a\.{ext}' exists; pass overwrite=True"):
        write(ModalLog(X + 1, rate=10.0), path)
    assert path.read_bytes() == before
    with pytest.raises(FileExistsError):
        save(ModalLog(X + 1, rate=10.0), path)
    assert path.read_bytes() == before
    write(ModalLog(X + 1, rate=10.0), path, overwrite=True)
    np.testing.assert_allclose(_read_independently(path, ext), X + 1, rtol=1e-15)
    assert sorted(os.listdir(tmp_path)) == [f"a.{ext}"]


def _crash_fits(monkeypatch):
    def boom(self, name, *args, **kwargs):
        with open(name, "wb") as fh:
            fh.write(b"SIMPLE  =                    T")  # half a header, then the crash
        raise RuntimeError("disk full")

    monkeypatch.setattr(fits.HDUList, "writeto", boom)


def _crash_h5(monkeypatch):
    def boom(self, *args, **kwargs):
        raise RuntimeError("disk full")  # the HDF5 file exists, without its datasets

    monkeypatch.setattr(h5py.File, "create_dataset", boom)


@pytest.mark.parametrize(("ext", "crash"), [("fits", _crash_fits), ("h5", _crash_h5)])
def test_crash_while_replacing_keeps_the_old_file(tmp_path, monkeypatch, ext, crash):
    path = tmp_path / f"a.{ext}"
    WRITERS[ext](ModalLog(X, rate=10.0), path)
    before = path.read_bytes()
    crash(monkeypatch)
    with pytest.raises(RuntimeError, match="disk full"):
        WRITERS[ext](ModalLog(X + 1, rate=10.0), path, overwrite=True)
    assert path.read_bytes() == before
    assert os.listdir(tmp_path) == [f"a.{ext}"]
    with pytest.raises(RuntimeError, match="disk full"):
        WRITERS[ext](ModalLog(X, rate=10.0), tmp_path / f"new.{ext}")
    assert os.listdir(tmp_path) == [f"a.{ext}"]
