"""Integer fill values of foreign HDF5 files and a CSV header of ANSI indices from 0.

References (outside the code): files written here with h5py and plain text, read back:
- CF conventions 1.11, sect. 2.5.1: a cell equal to ``_FillValue`` is undefined. The
  attribute has the type of its variable, so an integer variable (counts, scaled
  int16 coefficients) has an integer fill value; netCDF writers and ``h5py`` given a
  Python int store an integer one beside float data too. Undefined cells must reach the
  nonfinite policy (refused by default, dropped with ``nonfinite='drop'``), never be
  read as the number -9999, and every other cell must come back as written.
- ANSI / OSA indices count from 0 (ISO 24157: j = 0 is piston): a first row ``0,1,2``
  above float data is a header of mode indices, as ``1,2,3`` and ``2,3,4`` are (the
  reader's documented rule), so the log has the 30 written frames, not 31.

Planted bugs R8-28 and R8-29 (docs/MUTATION.md, round 8): the fill value honoured only
when it is a float (an int16 file's -9999 read as a coefficient), and the index header
accepted only from 1 or 2 (the ANSI header read as a frame of data); every test before
used a float fill and a header from 2.
"""
from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo.io import load

X = np.random.default_rng(9).standard_normal((30, 3))


@pytest.mark.parametrize("kind", ["int16 data", "float data, int fill"])
def test_hdf5_integer_fill_value_is_a_missing_value(tmp_path, kind):
    if kind == "int16 data":
        data, fill = np.round(X * 1000).astype(np.int16), np.int16(-9999)
    else:
        data, fill = X.copy(), -9999  # h5py stores a Python int as int64
    data[4, 1] = -9999
    with h5py.File(tmp_path / "f.h5", "w") as f:
        f.create_dataset("coeffs", data=data).attrs["_FillValue"] = fill
    with pytest.raises(ValueError, match="must be finite.*frame 4, column 1"):
        load(tmp_path / "f.h5")
    log = load(tmp_path / "f.h5", nonfinite="drop")
    np.testing.assert_array_equal(log.coeffs, np.delete(data, 4, axis=0).astype(float))


def test_csv_header_of_ansi_indices_from_zero(tmp_path):
    rows = "\n".join(",".join(repr(float(v)) for v in row) for row in X) + "\n"
    path = tmp_path / "a.csv"
    path.write_text("0,1,2\n" + rows)
    log = load(path, convention="ansi")
    assert log.n_frames == 30 and log.modes == [0, 1, 2]
    np.testing.assert_array_equal(log.coeffs, X)
