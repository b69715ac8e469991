"""A tar or zip archive of logs is named as such, not read as a corrupt log (round 53 PART b).

Reference: the archives are written by Python's ``tarfile`` and ``zipfile`` (a night of
logs packed for transfer, M47 / M48); an NPZ written by ``numpy.savez`` (a zip whose
members are ``.npy``) is still read, with its values equal to numpy's.
"""

from __future__ import annotations

import tarfile
import zipfile

import numpy as np
import pytest

from modalinfo.io import LogFormatError, load


@pytest.fixture
def night(tmp_path):
    folder = tmp_path / "2026-11-01"
    folder.mkdir()
    np.savez(folder / "a.npz", coeffs=np.random.default_rng(0).standard_normal((40, 3)))
    return folder


def test_tar_archive_named(night, tmp_path):
    packed = tmp_path / "night.tar"
    with tarfile.open(packed, "w") as tar:
        tar.add(night, arcname=night.name)
    # was "corrupt CSV file 'night.tar': UnicodeDecodeError: 'utf-8' codec can't decode"
    with pytest.raises(LogFormatError, match=r"is a tar archive, not a log.*tar xf"):
        load(packed)


def test_zip_archive_named(night, tmp_path):
    packed = tmp_path / "night.zip"
    with zipfile.ZipFile(packed, "w") as archive:
        archive.write(night / "a.npz", "2026-11-01/a.npz")
    # was "corrupt NPZ file 'night.zip': ValueError: the magic string is not correct"
    with pytest.raises(LogFormatError, match=r"is a zip archive of 1 file\(s\) with no \.npy"):
        load(packed)


def test_npz_still_read(night):
    x = np.load(night / "a.npz")["coeffs"]
    np.testing.assert_array_equal(np.asarray(load(night / "a.npz").coeffs), x)
