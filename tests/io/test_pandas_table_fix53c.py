"""Stop 59's small items (fix53-c, issue 27): pandas ``format="table"`` HDF5 files.

docs/ADVERSARIAL.md, "Round 52 PART b" (Left): a pandas table was refused, not read, as
its column names sit in Python pickles (PyTables attributes such as
``values_block_0_kind``), which modalinfo never loads. With ``data_columns=True`` (the
columns written one field each) the names are the compound table's own field names:
read then, with the values; a block of several columns (names only pickled) stays
refused, naming how to re-save.

References, from outside the code: the layouts as inspected in round 52 PART b's files
(pandas 3.1 + PyTables 3.11, h5py's view: group attribute ``pandas_type="frame_table"``,
dataset ``table`` of fields ``index`` and either ``values_block_0`` (frames x columns) or
one field per data column, ``FIELD_<n>_NAME`` attributes), rebuilt with h5py in
``tests/io/_archives.py``; expected values are the numpy arrays written.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

from ._archives import M, T, archive_log, pandas_data_columns, pandas_table


@pytest.mark.parametrize("index_arrays", [True, False])
def test_a_data_columns_table_is_read_with_its_names(tmp_path, index_arrays):
    x = archive_log()
    names = [f"z{j}" for j in range(M + 1, 1, -1)]  # z7 .. z2: reversed
    pandas_data_columns(tmp_path / "dc.h5", x, names, index_arrays=index_arrays)
    log = load(tmp_path / "dc.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(M + 1, 1, -1))
    assert "modes" not in log.metadata.get("assumed", {})


def test_a_data_columns_time_column_is_the_time_axis(tmp_path):
    x = archive_log()
    pandas_data_columns(tmp_path / "t.h5", np.column_stack([x, np.arange(T) / 1000.0]),
                        [f"z{j}" for j in range(2, M + 2)] + ["time"])
    log = load(tmp_path / "t.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.rate == pytest.approx(1000.0)


def test_a_values_block_table_stays_refused_naming_the_resave(tmp_path):
    pandas_table(tmp_path / "tab.h5")
    with pytest.raises(LogFormatError, match=r"pickle.*format='fixed'.*data_columns=True"):
        load(tmp_path / "tab.h5")
