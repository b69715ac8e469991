"""Mutation round 35 (review35): round 52 PART b's archive readers at their edges.

tests/io/test_archives_round52.py read each new rule once; the plants of
docs/MUTATION.md "Round 35" showed the ones it left unread: CF packing on a file of
one 1-D dataset per mode, and the fill value matched on the packed integers (CF: before
unpacking) with the default ``nonfinite``; a pandas frame's names read after its time
column is taken out (names written reversed) and its ``time_ms`` / ``frame`` columns;
pandas' integer column names (positions, not modes); ``scale_factor`` that is not one
finite number; the scale-offset filter on integers (lossless) and with 2 digits; rows
never written under chunks split along the columns; chunks missing inside the data
(sparse writes, not a tail); FITS tiles of which only some were quantized.

References, from outside the code: the files are built with h5py / astropy; expected
values are numpy on the arrays written (CF: unpacked = packed x scale_factor +
add_offset, fill matched on the packed integers); HDF5's scale-offset filter is lossless
on integers (its documentation: integer data are stored in the minimum bits, exactly)
and keeps ``scaleoffset`` decimal digits on floats (D-scaling); HDF5 returns the fill
value, 0, for chunks never written; astropy stores a tile it could not quantize (a
constant row) with ``ZSCALE`` 0, counted here from the file's own ``ZSCALE`` column.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

from ._archives import M, T
from ._archives import archive_log as _log
from ._archives import pandas_fixed as _pandas_fixed
from ._archives import pandas_table as _pandas_table


def _packed():
    return np.round(_log() / 1e-4).astype(np.int16)


def test_a_file_of_one_packed_dataset_per_mode_is_unpacked(tmp_path):
    packed = _packed()
    with h5py.File(tmp_path / "pm.h5", "w") as f:
        for j in range(M):
            f.create_dataset(f"z{j + 2}", data=packed[:, j]).attrs["scale_factor"] = 1e-4
    log = load(tmp_path / "pm.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, packed * 1e-4)
    assert log.modes == list(range(2, M + 2))


def test_the_fill_value_is_matched_on_the_packed_integers(tmp_path):
    packed = _packed()
    packed[10, 2] = -32768
    with h5py.File(tmp_path / "p.nc", "w") as f:
        d = f.create_dataset("coeffs", data=packed)
        d.attrs["scale_factor"] = np.float64(1e-4)
        d.attrs["add_offset"] = np.float64(0.25)
        d.attrs["_FillValue"] = np.int16(-32768)
    # the one missing cell is named (default nonfinite), not read as -3.0268
    with pytest.raises(ValueError, match=r"frame 10, column 2"):
        load(tmp_path / "p.nc", rate=1000.0)


@pytest.mark.parametrize("value", [np.float64(np.nan), np.array([1e-4, 2e-4])])
def test_a_scale_factor_that_is_not_one_finite_number_is_refused(tmp_path, value):
    with h5py.File(tmp_path / "b.nc", "w") as f:
        f.create_dataset("coeffs", data=_packed()).attrs["scale_factor"] = value
    with pytest.raises(LogFormatError, match="scale_factor.*not one finite number"):
        load(tmp_path / "b.nc", rate=1000.0)


def test_reversed_names_are_read_after_the_time_column_is_taken_out(tmp_path):
    x = _log()
    t = np.arange(T) / 1000.0
    names = [f"z{j}" for j in range(M + 1, 1, -1)] + ["time"]
    _pandas_fixed(tmp_path / "t.h5", np.column_stack([x, t]), names)
    log = load(tmp_path / "t.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(M + 1, 1, -1))
    assert log.rate == pytest.approx(1000.0)


def test_a_time_ms_column_is_converted_and_said(tmp_path):
    x = _log()
    _pandas_fixed(tmp_path / "ms.h5", np.column_stack([x, np.arange(T) * 2.0]),
                  [f"z{j}" for j in range(2, M + 2)] + ["time_ms"])
    log = load(tmp_path / "ms.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.rate == pytest.approx(500.0)
    assert log.metadata["time_column"] == "time_ms (ms, converted to s)"


def test_a_frame_column_is_the_frame_numbers(tmp_path):
    x = _log()
    frames = np.arange(T, dtype=float)
    frames[200:] += 5  # five frames lost: a gap the frame numbers show
    _pandas_fixed(tmp_path / "fr.h5", np.column_stack([x, frames]),
                  [f"z{j}" for j in range(2, M + 2)] + ["frame"])
    log = load(tmp_path / "fr.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(2, M + 2))
    np.testing.assert_allclose(log.timestamps - log.timestamps[0], frames / 1000.0)


def test_pandas_integer_column_names_are_positions_not_modes(tmp_path):
    x = _log()
    with h5py.File(tmp_path / "int.h5", "w") as f:
        g = f.create_group("coeffs")
        g.attrs["pandas_type"] = np.bytes_("frame")
        g.create_dataset("block0_items", data=np.arange(M))  # pandas' default 0..M-1
        g.create_dataset("block0_values", data=x)
    log = load(tmp_path / "int.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(2, M + 2))  # the foreign default, not modes 0..5


def test_scaleoffset_on_integers_is_lossless_and_says_nothing(tmp_path):
    packed = _packed()
    with h5py.File(tmp_path / "si.h5", "w") as f:
        f.create_dataset("coeffs", data=packed, chunks=(100, M), scaleoffset=0)
    log = load(tmp_path / "si.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, packed)
    assert "lossy_storage" not in log.metadata


@pytest.mark.parametrize("digits, step", [(0, "1"), (2, "1e-2")])
def test_scaleoffset_note_states_the_error_the_filter_leaves(tmp_path, digits, step):
    # review35 found the note wrong: D-scaling keeps whole steps from each chunk's
    # minimum, so the values read are not "a whole number" / "a multiple of 1e-2", and
    # they differ from the written ones by up to one step (not half) either way
    x = 3.0 * np.random.default_rng(35).standard_normal((2000, M))
    with h5py.File(tmp_path / "s.h5", "w") as f:
        f.create_dataset("coeffs", data=x, chunks=(100, M), scaleoffset=digits)
    log = load(tmp_path / "s.h5", rate=1000.0)
    with h5py.File(tmp_path / "s.h5") as f:
        stored = f["coeffs"][()]
    np.testing.assert_array_equal(log.coeffs, stored)
    scaled = stored * 10.0**digits
    assert np.max(np.abs(scaled - np.round(scaled))) > 0.1  # not multiples of the step
    error = np.abs(stored - x) * 10.0**digits
    assert 0.5 < np.max(error) <= 1.0  # more than half a step, at most one
    assert f"to within +-{step} (of the file's units)" in log.metadata["lossy_storage"]


def test_rows_never_written_are_refused_under_column_split_chunks(tmp_path):
    with h5py.File(tmp_path / "g.h5", "w") as f:
        d = f.create_dataset("coeffs", shape=(1000, M), maxshape=(None, M), chunks=(100, 2),
                             dtype="f8")
        d[:T] = _log()  # rows 400..999 never written: 12 of 30 chunks stored
    with pytest.raises(LogFormatError, match=r"rows 400\.\.999 .* never written"):
        load(tmp_path / "g.h5", rate=1000.0)


def test_chunks_missing_inside_the_data_are_read_as_stored(tmp_path):
    x = _log()[:300]
    with h5py.File(tmp_path / "sp.h5", "w") as f:
        d = f.create_dataset("coeffs", shape=(300, M), chunks=(100, M), dtype="f8")
        d[:100] = x[:100]
        d[200:] = x[200:]  # rows 100..199 never written, the last rows are
    expected = x.copy()
    expected[100:200] = 0.0  # HDF5's fill value
    np.testing.assert_array_equal(load(tmp_path / "sp.h5", rate=1000.0).coeffs, expected)


def test_partly_quantized_tiles_are_counted(tmp_path):
    x = np.repeat(_log(), 4, axis=1).astype(np.float32)
    x[:150] = 0.5  # constant rows: tiles astropy cannot quantize (ZSCALE 0)
    fits.CompImageHDU(data=x).writeto(tmp_path / "q.fz")
    with fits.open(tmp_path / "q.fz") as hdul:
        scales = np.asarray(hdul[1].compressed_data["ZSCALE"], dtype=float)
    quantized = int(np.count_nonzero(scales))
    assert 0 < quantized < scales.size
    note = load(tmp_path / "q.fz", rate=1000.0).metadata["lossy_storage"]
    assert f"({quantized} of {scales.size} tiles" in note


def test_two_time_columns_are_refused(tmp_path):
    # review35 found them read as modes: 8 "modes" z2 .. t_ms, no rate (CSV and FITS
    # refuse two time columns)
    x = _log()
    t = np.arange(T) / 1000.0
    _pandas_fixed(tmp_path / "tt.h5", np.column_stack([x, t, t * 1000.0]),
                  [f"z{j}" for j in range(2, M + 2)] + ["time", "t_ms"])
    with pytest.raises(LogFormatError, match=r"2 time axes \('time', 't_ms'\)"):
        load(tmp_path / "tt.h5")


def test_a_frame_column_beside_a_time_column_is_dropped(tmp_path):
    # as the CSV reader: the times are the axis, the frame numbers are said and dropped
    x = _log()
    t = np.arange(T) / 500.0
    _pandas_fixed(tmp_path / "tf.h5", np.column_stack([x, np.arange(T), t]),
                  [f"z{j}" for j in range(2, M + 2)] + ["frame", "time"])
    log = load(tmp_path / "tf.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(2, M + 2))
    assert log.rate == pytest.approx(500.0)
    assert "frame (frame numbers, unused" in log.metadata["frame_column"]


@pytest.mark.parametrize("dataset", ["timestamps", "frame"])
def test_a_time_column_beside_the_files_time_dataset_is_refused(tmp_path, dataset):
    x = _log()
    t = np.arange(T) / 1000.0
    _pandas_fixed(tmp_path / "td.h5", np.column_stack([x, t]),
                  [f"z{j}" for j in range(2, M + 2)] + ["time"])
    with h5py.File(tmp_path / "td.h5", "a") as f:
        f.create_dataset(dataset, data=t if dataset == "timestamps" else np.arange(T))
    with pytest.raises(LogFormatError, match=r"'time', the file's time dataset"):
        load(tmp_path / "td.h5", rate=1000.0)


def test_a_pandas_table_without_index_arrays_is_refused_by_name(tmp_path):
    # pandas to_hdf(format="table", index=False): the compound table alone, no 2-D dataset
    _pandas_table(tmp_path / "tab.h5", index_arrays=False)
    with pytest.raises(LogFormatError, match=r"pandas HDFStore table .*format='fixed'"):
        load(tmp_path / "tab.h5")


def test_one_mode_and_a_time_column(tmp_path):
    # the smallest frame with a time column: one mode beside it
    x = _log()[:, :1]
    _pandas_fixed(tmp_path / "one.h5", np.column_stack([x, np.arange(T) / 1000.0]),
                  ["z4", "time"])
    log = load(tmp_path / "one.h5")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == [4]
    assert log.rate == pytest.approx(1000.0)


def test_an_add_offset_alone_is_added(tmp_path):
    # CF: a missing scale_factor is 1 (unpacked = packed + add_offset)
    x = _log()
    with h5py.File(tmp_path / "o.nc", "w") as f:
        f.create_dataset("coeffs", data=x).attrs["add_offset"] = np.float64(0.5)
    np.testing.assert_array_equal(load(tmp_path / "o.nc", rate=1000.0).coeffs, x + 0.5)


@pytest.mark.parametrize("scales", [2, "short"])
def test_a_column_axis_without_one_matching_string_scale_gives_no_names(tmp_path, scales):
    # netCDF attaches one coordinate of the dimension's length; two scales, or one of
    # another length (attached by hand with h5py), name nothing: the foreign default
    x = _log()
    with h5py.File(tmp_path / "s.h5", "w") as f:
        v = f.create_dataset("coeffs", data=x)
        lists = ([[f"z{j}" for j in range(M + 1, 1, -1)], [f"z{j}" for j in range(3, M + 3)]]
                 if scales == 2 else [["z9", "z8", "z7"]])
        for k, names in enumerate(lists):
            m = f.create_dataset(f"mode{k}", data=names, dtype=h5py.string_dtype())
            m.make_scale(f"mode{k}")
            v.dims[1].attach_scale(m)
    log = load(tmp_path / "s.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(2, M + 2))


def test_pandas_items_of_another_length_name_nothing(tmp_path):
    # blockN_items lists the block's columns; a list of another length is not theirs
    x = _log()
    with h5py.File(tmp_path / "short.h5", "w") as f:
        g = f.create_group("coeffs")
        g.attrs["pandas_type"] = np.bytes_("frame")
        g.create_dataset("block0_items", data=np.array([b"z9", b"z8", b"z7"]))
        g.create_dataset("block0_values", data=x)
    log = load(tmp_path / "short.h5", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.modes == list(range(2, M + 2))
