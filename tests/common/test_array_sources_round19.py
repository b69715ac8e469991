"""Lazy and buffer array sources (adversarial round 19 PART a, issue 27).

Reference: ``np.asarray`` of the same data (values must be bit-equal when read), and the
bytes themselves: a ``bytearray`` of float64 data holds 8 bytes per sample, which NumPy
reads as that many uint8 numbers, so the raw-bytes refusal is checked against
``np.frombuffer(..., dtype=np.float64)`` recovering the samples. A closed h5py dataset
raises h5py's RuntimeError on reading; the API must turn it into a TypeError naming the
argument.
"""

from __future__ import annotations

import array

import numpy as np
import pytest

from modalinfo.bases import pupil_from_mask
from modalinfo.information import mutual_information
from modalinfo.telemetry import ModalLog

h5py = pytest.importorskip("h5py")

RNG = np.random.default_rng(19)
X = RNG.standard_normal(400)
Y = 0.6 * X + 0.8 * RNG.standard_normal(400)


@pytest.fixture
def closed_datasets(tmp_path):
    with h5py.File(tmp_path / "log.h5", "w") as f:
        f["coeffs"] = np.ones((10, 2))
        f["t"] = np.arange(10.0) * 1e-3
        f["mask"] = np.ones((16, 16), bool)
        dsets = f["coeffs"], f["t"], f["mask"]
    return dsets


def test_closed_h5py_dataset_is_refused_naming_the_argument(closed_datasets):
    coeffs, t, mask = closed_datasets
    with pytest.raises(TypeError, match=r"`coeffs` .*Closed HDF5 dataset.*reading it failed"):
        ModalLog(coeffs, rate=1e3)
    with pytest.raises(TypeError, match=r"`timestamps` .*reading it failed"):
        ModalLog(np.ones((10, 2)), timestamps=t)
    with pytest.raises(TypeError, match=r"`mask` .*reading it failed"):
        pupil_from_mask(mask)


def test_open_h5py_dataset_and_buffers_read_as_the_array(tmp_path):
    with h5py.File(tmp_path / "xy.h5", "w") as f:
        f["x"] = X
        want = mutual_information(X, Y)
        assert mutual_information(f["x"], Y) == want
    assert mutual_information(memoryview(X), Y) == want
    assert mutual_information(array.array("d", X), Y) == want
    assert mutual_information(memoryview(X.tobytes()).cast("d"), Y) == want


@pytest.mark.parametrize("wrap", [bytearray, lambda b: memoryview(b), bytes])
def test_raw_bytes_are_refused_not_read_as_uint8(wrap):
    raw = wrap(X.tobytes())
    assert np.array_equal(np.frombuffer(raw, dtype=np.float64), X)  # what the bytes hold
    y8 = RNG.standard_normal(8 * X.size)  # the length NumPy's uint8 reading would have
    with pytest.raises(TypeError, match=r"`x` .*raw bytes.*np\.frombuffer"):
        mutual_information(raw, y8)
    with pytest.raises(TypeError, match=r"`coeffs` .*raw bytes"):
        ModalLog(raw, rate=1e3)
