"""Archive layouts other software writes, built with h5py: one copy for the io tests.

For tests/io/test_archives_round52.py, test_archives_review35.py and later rounds.
References (the layouts as inspected in round 52 PART b's files): pandas 3.1 + PyTables
3.11 ``DataFrame.to_hdf(format="fixed")`` is a group with attribute
``pandas_type="frame"``, datasets ``axis0`` / ``blockN_items`` (the column names),
``axis1`` (the index) and ``blockN_values`` (frames x columns); ``to_hdf(format="table")``
is a group with ``pandas_type="frame_table"`` holding the compound dataset ``table``
(an ``index`` field and a ``values_block_0`` field of the columns), and with
``data_columns`` or an index PyTables' index arrays under ``_i_table``.
"""

from __future__ import annotations

import h5py
import numpy as np

T, M = 400, 6  # frames and modes of the test log


def archive_log() -> np.ndarray:
    """A (T, M) AR(1) log: a log's modes persist in time (seed 52)."""
    rng = np.random.default_rng(52)
    x = np.zeros((T, M))
    for t in range(1, T):
        x[t] = 0.95 * x[t - 1] + rng.normal(scale=0.05, size=M)
    return x


def pandas_fixed(path, x, names) -> None:
    """The layout of pandas ``DataFrame.to_hdf(path, key="coeffs", format="fixed")``."""
    with h5py.File(path, "w") as f:
        g = f.create_group("coeffs")
        g.attrs["pandas_type"] = np.bytes_("frame")
        g.create_dataset("axis0", data=np.array([n.encode() for n in names]))
        g.create_dataset("axis1", data=np.arange(x.shape[0]))
        g.create_dataset("block0_items", data=np.array([n.encode() for n in names]))
        g.create_dataset("block0_values", data=x)


def pandas_table(path, index_arrays: bool = True) -> None:
    """The layout of ``to_hdf(path, key="coeffs", format="table")`` (zeros, T x M).

    ``index_arrays``: with PyTables' index arrays under ``_i_table`` (pandas' default
    index), else the compound table alone (``index=False``).
    """
    with h5py.File(path, "w") as f:
        g = f.create_group("coeffs")
        g.attrs["pandas_type"] = np.bytes_("frame_table")
        rec = np.zeros(T, dtype=[("index", "<i8"), ("values_block_0", "<f8", (M,))])
        g.create_dataset("table", data=rec)
        if index_arrays:
            for name in ("bounds", "indices"):
                g.create_dataset(f"_i_table/index/{name}", data=np.zeros((4, 4)))


def pandas_data_columns(path, x, names, index_arrays: bool = True) -> None:
    """The layout of ``to_hdf(path, key="coeffs", format="table", data_columns=True)``.

    Every column is a field of the compound ``table`` named by the column (PyTables also
    writes ``FIELD_<n>_NAME`` attributes); the pickled attributes pandas adds
    (``values_cols``, ``non_index_axes``, ...) are left out: a reader must not need them.
    """
    dtype = [("index", "<i8")] + [(n, x.dtype.str) for n in names]
    rec = np.zeros(x.shape[0], dtype=dtype)
    rec["index"] = np.arange(x.shape[0])
    for j, n in enumerate(names):
        rec[n] = x[:, j]
    with h5py.File(path, "w") as f:
        g = f.create_group("coeffs")
        g.attrs["pandas_type"] = np.bytes_("frame_table")
        t = g.create_dataset("table", data=rec)
        for k, n in enumerate(["index", *names]):
            t.attrs[f"FIELD_{k}_NAME"] = np.bytes_(n)
        if index_arrays:
            for name in ("bounds", "indices"):
                g.create_dataset(f"_i_table/index/{name}", data=np.zeros((4, 4)))
