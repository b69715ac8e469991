"""A result file's logs go through modalinfo.io's one HDF5 writer and reader of a ModalLog.

References: round trips, compared field by field and bit for bit with the object
written; the file read back by :func:`modalinfo.io.read_hdf5`'s own checks (a flipped
coefficient is caught by the SHA-256 modalinfo.io records); a format-1 file written here
by hand in the old layout (bare datasets with JSON attributes), which must still load;
the budget's datasets against ``dataclasses.fields(ErrorBudget)``. Integrity: a saved
file damaged here with h5py (a value edited in place, a dataset removed or added, an
attribute changed, the checksums removed) must be refused by ``SimulationResult.load``
and by ``closedloop info`` / ``export`` (exit 2, one stderr line naming the dataset); a
format-2 file (written before results carried checksums, rebuilt here by removing them)
still loads, with a warning and a note.
"""

import dataclasses
import json

import h5py
import numpy as np
import pytest

from closedloop import SimulationResult, simulate
from closedloop.budget import ErrorBudget as BudgetFromBudget
from closedloop.cli import main as closedloop_main
from closedloop.result import ErrorBudget, UncheckedResultWarning
from modalinfo.io import LogFormatError, read_hdf5, write_hdf5
from modalinfo.io.hdf5 import read_log_group, write_log_group

from .conftest import small


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
        assert f.attrs["format_version"] == 3


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
    with pytest.warns(UncheckedResultWarning, match="format-1 .* not verified"):
        back = SimulationResult.load(path)
    for name, log in run.logs.items():
        _same_log(back.logs[name], log)


# ---------------------------------------------------------------- integrity of results
@pytest.fixture(scope="module")
def saved(run, tmp_path_factory):
    path = tmp_path_factory.mktemp("integrity") / "run.h5"
    run.save(path)
    return path


@pytest.fixture()
def copy(saved, tmp_path):
    path = tmp_path / "run.h5"
    path.write_bytes(saved.read_bytes())
    return path


def _bump(path, name, index=(0, 0)):
    """Add 1 to one value of dataset ``name``, in place (h5py, as a user could)."""
    with h5py.File(path, "r+") as f:
        d = f[name]
        index = index[:d.ndim]
        d[index] = d[index] + 1


def _refused_by_the_cli(path, needle, capsys, tmp_path):
    out = tmp_path / "run.fits"
    for argv in (["info", str(path)], ["export", str(path), str(out)]):
        assert closedloop_main(argv) == 2
        cap = capsys.readouterr()
        assert cap.err.count("\n") == 1 and needle in cap.err and "Traceback" not in cap.err
        assert cap.err.startswith(f"closedloop {argv[0]}: error: corrupt closedloop result")
    assert not out.exists()


@pytest.mark.parametrize("name", ["residual_variance", "measurements/wfs1", "budget/noise",
                                  "times", "directions", "logs/dm1.residual/modalinfo_header"])
def test_a_dataset_edited_in_place_is_refused_naming_it(run, copy, name, capsys, tmp_path):
    with h5py.File(copy, "r") as f:
        assert name in f
    _bump(copy, name, (1, 1))
    with pytest.raises(ValueError, match=f"dataset '{name}' does not match its SHA-256"):
        SimulationResult.load(copy)
    _refused_by_the_cli(copy, f"'{name}'", capsys, tmp_path)


def test_every_dataset_of_the_file_is_covered(run, saved, tmp_path):
    # each dataset outside the logs' coefficients (covered by their own header checksum,
    # test_log_groups_are_modalinfo_io_files) is refused when one of its values changes
    names = []
    with h5py.File(saved, "r") as f:
        f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
    covered = [n for n in names if not n.endswith(("/coefficients", "/timestamps"))]
    assert len(covered) >= 15 and "residual_variance" in covered
    for name in covered:
        path = tmp_path / f"{name.replace('/', '_')}.h5"
        path.write_bytes(saved.read_bytes())
        _bump(path, name)
        with pytest.raises(ValueError, match=f"'{name}'"):
            SimulationResult.load(path)


def test_removed_added_attributes_and_checksums(copy, saved, tmp_path):
    with h5py.File(copy, "r+") as f:
        del f["measurements/wfs0"]
    with pytest.raises(ValueError, match="dataset 'measurements/wfs0' is missing"):
        SimulationResult.load(copy)
    cases = {
        "added": (lambda f: f.create_dataset("extra", data=np.zeros(3)),
                  "dataset 'extra' was added after the file was written"),
        "seed": (lambda f: f.attrs.__setitem__("seed", 7), "attributes .* do not match"),
        "config": (lambda f: f.attrs.__setitem__(
            "config", f.attrs["config"].replace('"gain": 0.', '"gain": 1.')),
            "attributes .* do not match"),
        "no sums": (lambda f: f.attrs.__delitem__("sha256"), "checksums .* missing"),
    }
    for case, (damage, message) in cases.items():
        path = tmp_path / f"{case}.h5"
        path.write_bytes(saved.read_bytes())
        with h5py.File(path, "r+") as f:
            before = dict(f.attrs)
            damage(f)
            assert case in ("added", "no sums") or dict(f.attrs) != before
        with pytest.raises(ValueError, match=message):
            SimulationResult.load(path)


def test_an_intact_file_is_verified_and_said_so(saved, capsys):
    assert closedloop_main(["info", str(saved)]) == 0
    cap = capsys.readouterr()
    assert "integrity: SHA-256 of every dataset and attribute verified" in cap.out
    assert cap.err == ""


def test_format_2_file_loads_unverified_with_a_note(run, copy, capsys, tmp_path):
    # a format-2 file: the same layout without the checksums; a damaged value goes unseen
    with h5py.File(copy, "r+") as f:
        del f.attrs["sha256"]
        f.attrs["format_version"] = 2
    _bump(copy, "residual_variance")
    with pytest.warns(UncheckedResultWarning, match="format-2 .* not verified"):
        back = SimulationResult.load(copy)
    np.testing.assert_array_equal(back.residual_variance[1:], run.residual_variance[1:])
    for name, log in run.logs.items():
        _same_log(back.logs[name], log)
    assert closedloop_main(["info", str(copy)]) == 0
    cap = capsys.readouterr()
    assert "integrity: not verified" in cap.out
    assert cap.err.count("\n") == 1
    assert cap.err.startswith("closedloop info: note: ") and "format-2" in cap.err
    out = tmp_path / "old.fits"
    assert closedloop_main(["export", str(copy), str(out)]) == 0 and out.is_file()
    assert "closedloop export: note: " in capsys.readouterr().err
    # saving it again adds the checksums (of the data as read)
    again = tmp_path / "again.h5"
    back.save(again)
    SimulationResult.load(again)


def test_a_fifo_as_result_file_is_named_not_said_missing(tmp_path):
    # round 5: `closedloop info fifo.h5` said "does not exist"
    import os

    os.mkfifo(tmp_path / "run.h5")
    with pytest.raises(FileNotFoundError, match="is not a regular file"):
        SimulationResult.load(tmp_path / "run.h5")
