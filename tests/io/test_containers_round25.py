"""Adversarial round 25 PART b: structural corners of HDF5 containers.

Reference: the arrays and attributes written with h5py and astropy themselves (round trips: the log
read back equals the ``ModalLog`` that ``write_log_group`` wrote, bit for bit, with its
rate and units; the coefficients equal the numpy array h5py stored; the unit is the
``units`` attribute h5py stored on the nesting group).
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo import io
from modalinfo.io.files import LogFormatError
from modalinfo.io.hdf5 import write_log_group
from modalinfo.telemetry import ModalLog


def _log(seed: int = 0) -> ModalLog:
    rng = np.random.default_rng(seed)
    return ModalLog(rng.standard_normal((200, 6)), rate=1000.0, units="rad",
                    wavelength=5e-7)


def test_a_log_in_a_group_is_read_not_called_corrupt(tmp_path):
    """H12-H14: one ``write_log_group`` log nested in /run1 reads back bit-equal."""
    log = _log()
    path = tmp_path / "one.h5"
    with h5py.File(path, "w") as f:
        write_log_group(f.create_group("run1"), log)
    for dataset in (None, "run1", "run1/coefficients"):
        back = io.load(path, dataset=dataset)
        assert np.array_equal(back.coeffs, log.coeffs)
        assert (back.rate, back.units, back.wavelength) == (1000.0, "rad", 5e-7)


def test_several_log_groups_are_named_and_chosen_with_dataset(tmp_path):
    """H13-H15: two logs: refused naming both groups; ``dataset=`` picks either."""
    logs = [_log(0), _log(1)]
    path = tmp_path / "two.h5"
    with h5py.File(path, "w") as f:
        for k, log in enumerate(logs):
            write_log_group(f.create_group(f"run{k + 1}"), log)
    with pytest.raises(LogFormatError, match=r"2 modalinfo logs, in groups run1, run2"):
        io.load(path)
    assert np.array_equal(io.load(path, dataset="run2").coeffs, logs[1].coeffs)
    assert np.array_equal(io.load(path, dataset="/run1/coefficients").coeffs,
                          logs[0].coeffs)


def test_units_on_the_nesting_group_are_read(tmp_path):
    """H01: ``units="nm"`` on the group of /run/wfs/coeffs only: the log is in nm."""
    data = np.random.default_rng(2).standard_normal((300, 5))
    path = tmp_path / "nested.h5"
    with h5py.File(path, "w") as f:
        f.create_group("run/wfs").create_dataset("coeffs", data=data)
        f["run/wfs"].attrs["units"] = "nm"
        f.attrs["units"] = "um"  # the innermost group wins over the file's
    back = io.load(path)
    assert back.units == "nm"
    assert np.array_equal(back.coeffs, data)
    assert "units" not in back.metadata.get("assumed", {})


def test_an_image_read_before_a_table_says_so(tmp_path):
    """F05: image HDU 1 and table HDU 2 (astropy): the image is read and that is said."""
    fits = pytest.importorskip("astropy.io.fits")
    data = np.random.default_rng(3).standard_normal((100, 4))
    cols = [fits.Column(name=f"Z{j + 2}", format="D", array=data[:, j]) for j in range(4)]
    path = tmp_path / "image_and_table.fits"
    fits.HDUList([fits.PrimaryHDU(), fits.ImageHDU(data, name="COEFFS"),
                  fits.BinTableHDU.from_columns(cols, name="MODES")]).writeto(path)
    back = io.load(path, units="rad", modes=[2, 3, 4, 5])
    assert np.array_equal(back.coeffs, data)
    assert "not the table HDU(s) 2" in back.metadata["source_hdu"]


def test_a_modalinfo_header_without_its_coefficients_is_refused(tmp_path):
    """N10: the ``coefficients`` member renamed (numpy ``savez``): refused, not foreign."""
    log = _log()
    own = tmp_path / "own.npz"
    io.save(log, own)
    members = dict(np.load(own))
    members["coeffs"] = members.pop("coefficients")
    renamed = tmp_path / "renamed.npz"
    np.savez(renamed, **members)
    with pytest.raises(LogFormatError, match=r"modalinfo header but no 'coefficients'"):
        io.load(renamed)
    # named explicitly: read as a foreign array, the values numpy stored
    assert np.array_equal(io.load(renamed, dataset="coeffs", units="rad", modes=list(
        range(2, 8))).coeffs, log.coeffs)
    # another tool's 'header' member is no modalinfo header: read as before
    other = tmp_path / "other.npz"
    np.savez(other, header=np.array("camera v2"), data=log.coeffs)
    assert np.array_equal(io.load(other, units="rad", modes=list(range(2, 8))).coeffs,
                          log.coeffs)


def test_a_log_in_a_group_has_its_checksum_verified(tmp_path):
    """H12 through ``info``: its SHA-256 is checked, a changed value refused."""
    from modalinfo.io.integrity import integrity_check

    log = _log()
    path = tmp_path / "one.h5"
    with h5py.File(path, "w") as f:
        write_log_group(f.create_group("run1"), log)
    for mmap in (False, True):
        check = integrity_check(path, io.load(path, mmap=mmap), mmap=mmap)
        assert check.status == "verified"
    with h5py.File(path, "a") as f:
        f["run1/coefficients"][5, 3] += 1e-9
    with pytest.raises(LogFormatError, match="SHA-256"):
        integrity_check(path, io.load(path, verify=False), mmap=True)
