"""A result file's logs go through modalinfo.io's one HDF5 writer and reader of a ModalLog.

References: round trips, compared field by field and bit for bit with the object
written; the file read back by :func:`modalinfo.io.read_hdf5`'s own checks (a flipped
coefficient is caught by the SHA-256 modalinfo.io records); a format-1 file written here
by hand in the old layout (bare datasets with JSON attributes), which must still load;
the budget's datasets against ``dataclasses.fields(ErrorBudget)``.
"""

import dataclasses
import json

import h5py
import numpy as np
import pytest

from closedloop import SimulationResult, simulate
from closedloop.budget import ErrorBudget as BudgetFromBudget
from closedloop.result import ErrorBudget
from modalinfo.io import LogFormatError, read_hdf5, write_hdf5
from modalinfo.io.hdf5 import read_log_group, write_log_group

from .test_loop import small


@pytest.fixture(scope="module")
def run():
    return simulate(small(), 0.02, seed=2, progress=False, budget_every=4)


def _same_log(a, b):
    assert a.coeffs.dtype == b.coeffs.dtype and a.coeffs.tobytes() == b.coeffs.tobytes()
    assert (a.modes, a.convention, a.units, a.metadata) == (b.modes, b.convention, b.units,
                                                             b.metadata)
    assert (a.rate, a.start_time, a.wavelength) == (b.rate, b.start_time, b.wavelength)
    np.testing.assert_array_equal(a.times, b.times)


def test_result_round_trip_is_exact(run, tmp_path):
    path = tmp_path / "run.h5"
    run.save(path)
    back = SimulationResult.load(path)
    assert set(back.logs) == set(run.logs)
    for name, log in run.logs.items():
        _same_log(back.logs[name], log)
    assert back.budget is not None and BudgetFromBudget is ErrorBudget
    for f in dataclasses.fields(ErrorBudget):
        np.testing.assert_array_equal(getattr(back.budget, f.name), getattr(run.budget, f.name))
    with h5py.File(path, "r") as f:
        assert sorted(f["budget"]) == sorted(x.name for x in dataclasses.fields(ErrorBudget))
        assert f.attrs["format_version"] == 2


def test_log_groups_are_modalinfo_io_files(run, tmp_path):
    log = run.logs["dm1.pol"]
    # the group layout is write_hdf5's: a file written by one is read by the other
    path = tmp_path / "log.h5"
    write_hdf5(log, path)
    with h5py.File(path, "r") as f:
        _same_log(read_log_group(f, path), log)
    other = tmp_path / "group.h5"
    with h5py.File(other, "w") as f:
        write_log_group(f, log)
    _same_log(read_hdf5(other), log)
    # damage one coefficient of a result's log: its checksum names the file
    res = tmp_path / "run.h5"
    run.save(res)
    with h5py.File(res, "r+") as f:
        d = f["logs/dm0.pol/coefficients"]
        d[3, 2] = d[3, 2] + 1.0
    with pytest.raises(LogFormatError, match="run.h5"):
        SimulationResult.load(res)


def test_format_1_files_still_load(run, tmp_path):
    path = tmp_path / "old.h5"
    run.save(path)
    with h5py.File(path, "r+") as f:  # rewrite the logs as format 1 did
        f.attrs["format_version"] = 1
        del f["logs"]
        g = f.create_group("logs")
        for name, log in run.logs.items():
            d = g.create_dataset(name, data=np.asarray(log.coeffs))
            d.attrs["modes"] = json.dumps(list(log.modes))
            d.attrs["metadata"] = json.dumps(log.metadata)
            d.attrs["rate"] = log.rate
            d.attrs["start_time"] = float(log.times[0])
            d.attrs["wavelength"] = log.wavelength
    back = SimulationResult.load(path)
    for name, log in run.logs.items():
        _same_log(back.logs[name], log)
