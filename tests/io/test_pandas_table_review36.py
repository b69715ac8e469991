"""Mutation round 36 (review36): pandas ``format="table", data_columns=True`` files.

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"): the table's units
never read, one mode beside a time column never written, two tables in one file never
written, a text column never written (read as a mode by the plant; refused before in
the pickled-names words, whose advice does not fit: now refused naming the column).

References (outside the code): the layout of ``tests/io/_archives.pandas_data_columns``
(pandas + PyTables as inspected in round 52 PART b), the values written (numpy), the
units attribute written with h5py.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

from ._archives import M, T, archive_log, pandas_data_columns


def test_the_tables_units_are_read(tmp_path):
    x = archive_log()
    pandas_data_columns(tmp_path / "u.h5", x, [f"z{j}" for j in range(2, M + 2)])
    with h5py.File(tmp_path / "u.h5", "a") as f:
        f["coeffs/table"].attrs["units"] = "nm"
    log = load(tmp_path / "u.h5", rate=1000.0)
    assert log.units == "nm"
    np.testing.assert_array_equal(log.coeffs, x)


def test_one_mode_and_a_time_column(tmp_path):
    x = archive_log()[:, :1]
    pandas_data_columns(tmp_path / "t.h5", np.column_stack([x, np.arange(T) / 1000.0]),
                        ["z2", "time"])
    log = load(tmp_path / "t.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == [2] and log.rate == pytest.approx(1000.0)


def test_two_tables_in_one_file_are_not_read_as_one(tmp_path):
    x = archive_log()
    pandas_data_columns(tmp_path / "two.h5", x, [f"z{j}" for j in range(2, M + 2)])
    pandas_data_columns(tmp_path / "b.h5", 2 * x, [f"z{j}" for j in range(2, M + 2)])
    with h5py.File(tmp_path / "two.h5", "a") as f, h5py.File(tmp_path / "b.h5") as g:
        g.copy("coeffs", f, name="other")
    with pytest.raises(LogFormatError):
        load(tmp_path / "two.h5", rate=1000.0)


def test_a_text_column_is_not_read_as_a_mode(tmp_path):
    # a data-columns table with a text field (b"2.5" in every row): not read as numbers
    x = archive_log()[:, :3]
    dtype = [("index", "<i8"), ("z2", "<f8"), ("z3", "<f8"), ("z4", "<f8"), ("label", "S8")]
    rec = np.zeros(T, dtype=dtype)
    for j, n in enumerate(("z2", "z3", "z4")):
        rec[n] = x[:, j]
    rec["label"] = b"2.5"
    with h5py.File(tmp_path / "s.h5", "w") as f:
        g = f.create_group("coeffs")
        g.attrs["pandas_type"] = np.bytes_("frame_table")
        g.create_dataset("table", data=rec)
    # refused naming the text column (before review36: the pickled-names refusal, whose
    # advice, re-save with format='fixed', does not fit a table whose names are its own)
    with pytest.raises(LogFormatError, match="holds text column\\(s\\) 'label' beside"):
        load(tmp_path / "s.h5", rate=1000.0)
