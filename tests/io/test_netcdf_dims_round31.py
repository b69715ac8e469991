"""Round 31 PART b (issue 27): a netCDF-4 variable's dimension scales give its layout.

docs/ADVERSARIAL.md, "Round 31 PART b, issue 27", a27: a netCDF-4 style file whose
coefficient variable is stored (mode, time), its two dimensions attached as HDF5
dimension scales named ``mode`` and ``time`` (how netCDF-4 records dimensions; it sets no
dimension labels), was refused as "looks transposed" although the file names its axes.
The refusal was correct but the file's own statement went unread.

Reference: the netCDF-4 on-HDF5 layout (each dimension a dataset made a dimension scale,
named by the dimension, attached to the variable's axes; a dimension without a
coordinate variable carries the NAME "This is a netCDF dimension but not a netCDF
variable."), written with h5py; the expected log is the (time, mode) array written.
"""

from __future__ import annotations

import h5py
import numpy as np

from modalinfo.io import load

T, M = 300, 200


def _write(path, x, *, coordinate: bool):
    with h5py.File(path, "w") as f:
        if coordinate:
            t = f.create_dataset("time", data=np.arange(T) / 1000.0)
            t.make_scale("time")
        else:
            t = f.create_dataset("time", shape=(T,), dtype="f4")
            t.make_scale("This is a netCDF dimension but not a netCDF variable.")
        m = f.create_dataset("mode", shape=(M,), dtype="f4")
        m.make_scale("This is a netCDF dimension but not a netCDF variable.")
        v = f.create_dataset("coeff", data=x.T)  # (mode, time)
        v.dims[0].attach_scale(m)
        v.dims[1].attach_scale(t)


def test_mode_time_variable_is_read_transposed_by_its_scales(tmp_path):
    x = np.random.default_rng(31).normal(size=(T, M))
    _write(tmp_path / "a.nc", x, coordinate=True)
    log = load(tmp_path / "a.nc", dataset="coeff")
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.rate == 1000.0
    assert "dimension scales" in log.metadata["layout"]["transposed"]


def test_scales_without_coordinate_values_still_name_the_axes(tmp_path):
    x = np.random.default_rng(32).normal(size=(T, M))
    _write(tmp_path / "b.nc", x, coordinate=False)
    log = load(tmp_path / "b.nc", dataset="coeff", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
