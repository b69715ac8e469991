"""Review20: a log in a group beside other 2-D datasets.

References, outside the code: ``numpy.array_equal`` of the log read back with the log
``write_log_group`` wrote (a round trip), and ``h5py``'s own listing of the file: a
group log beside a reconstructor matrix (a dataset not named as coefficients) is the
file's one log, read as written, not "corrupt" (before review20, any second 2-D
dataset sent the file to the foreign reader, which took the group's ``coefficients``
and called the file corrupt); beside a second dataset named ``coefficients`` the file
holds two candidate logs, and the refusal names both (as ``_foreign`` does for two).
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo import io
from modalinfo.io.files import LogFormatError
from modalinfo.io.hdf5 import write_log_group
from modalinfo.telemetry import ModalLog


def _log() -> ModalLog:
    coeffs = np.random.default_rng(20).standard_normal((200, 4))
    return ModalLog(coeffs, rate=1000.0, units="rad", wavelength=5e-7)


def test_a_group_log_beside_a_matrix_is_read(tmp_path):
    log, path = _log(), tmp_path / "with_matrix.h5"
    with h5py.File(path, "w") as f:
        write_log_group(f.create_group("run1"), log)
        f.create_dataset("reconstructor", data=np.ones((300, 6)))
    back = io.load(path)
    assert np.array_equal(back.coeffs, log.coeffs)
    assert (back.rate, back.units) == (1000.0, "rad")


def test_a_group_log_beside_other_coefficients_is_refused_naming_both(tmp_path):
    log, path = _log(), tmp_path / "two_candidates.h5"
    with h5py.File(path, "w") as f:
        write_log_group(f.create_group("run1"), log)
        f.create_dataset("raw/coefficients", data=np.ones((300, 6)))
    with pytest.raises(LogFormatError, match=r"group run1 and other coefficients "
                                             r"\(raw/coefficients\); pick one"):
        io.load(path)
    assert np.array_equal(io.load(path, dataset="run1").coeffs, log.coeffs)
    assert io.load(path, dataset="raw/coefficients").coeffs.shape == (300, 6)
