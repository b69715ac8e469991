"""A float32 log whose float64 copy does not fit is refused, naming it, before NumPy's
MemoryError (round 46 PART a, A11 - A13).

A 10^6 x 3000 float32 memory map (12 GB) met "MemoryError: Unable to allocate 22.4 GiB"
in ``fitting_error`` and ``order_modes`` (``as_float_array``'s float64 copy inside
``coefficients_in_basis``) and 11.2 GiB in ``evaluate`` (its training rows read from the
map). Reference (outside the code): the arithmetic of the copy, 8 bytes per value of the
(frames, modes) array, against an available memory set here
(``modalinfo.common.memory.available_memory_bytes`` replaced by 1 MiB). The logs are
sparse memory-mapped files (no RAM is used) just above the 128 MiB skip of
``check_memory``, so the tests read almost nothing.
"""
from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.common import memory
from modalinfo.forecast import PersistencePredictor, evaluate
from modalinfo.ordering import fitting_error, order_modes
from modalinfo.telemetry import ModalLog

MIB = 2**20


def _sparse_log(tmp_path, frames: int, modes: int) -> ModalLog:
    mapped = np.lib.format.open_memmap(tmp_path / "log.npy", mode="w+", dtype=np.float32,
                                       shape=(frames, modes))
    rng = np.random.default_rng(0)
    for start in range(0, frames, frames // 8):      # a few non-zero rows: the file stays sparse
        mapped[start] = rng.normal(size=modes).astype(np.float32)
    mapped.flush()
    del mapped
    return ModalLog(np.load(tmp_path / "log.npy", mmap_mode="r"), rate=1000.0)


def _gib(message: str) -> float:
    return float(re.search(r"needs about ([0-9.e+-]+) GiB", message).group(1))


@pytest.fixture
def small_memory(monkeypatch):
    monkeypatch.setattr(memory, "available_memory_bytes", lambda: float(MIB))


@pytest.mark.parametrize("call", ["fitting_error", "order_modes"])
def test_log_copy_refused_by_size(tmp_path, small_memory, call):
    frames, modes = 2**20, 16                        # float64 copy: 128 MiB exactly
    log = _sparse_log(tmp_path, frames, modes)
    basis = ZernikeBasis(Pupil(16), range(2, 2 + modes))
    with pytest.raises(ValueError, match=r"`[a-z_]+\.coeffs` needs about .* GiB .*float64 "
                                         r"copy.* is available; use fewer frames or modes"
                       ) as info:
        if call == "fitting_error":
            fitting_error(log, basis)
        else:
            order_modes(log, basis, "variance")
    # the message shows 3 significant digits
    assert _gib(str(info.value)) == pytest.approx(frames * modes * 8 / 2**30, rel=5e-3)


def test_evaluate_training_rows_refused_by_size(tmp_path, small_memory):
    frames, modes, train = 2**21, 9, 0.9
    log = _sparse_log(tmp_path, frames, modes)
    n_train = int(round(train * frames))
    with pytest.raises(ValueError, match=r"`log` needs about .* GiB for a float64 copy of "
                                         r"\d+ frames x 9 modes .* smaller `train`") as info:
        evaluate({"p": PersistencePredictor()}, log, train=train, horizons=[1])
    rows = int(re.search(r"copy of (\d+) frames", str(info.value)).group(1))
    assert abs(rows - n_train) <= 1
    # the message shows 3 significant digits
    assert _gib(str(info.value)) == pytest.approx(rows * modes * 8 / 2**30, rel=5e-3)


def test_small_copies_are_not_checked(tmp_path, small_memory):
    """Below 128 MiB nothing is read: a small float32 log is analysed as before."""
    rng = np.random.default_rng(1)
    log = ModalLog(rng.normal(size=(500, 5)).astype(np.float32), rate=1000.0)
    basis = ZernikeBasis(Pupil(16), range(2, 7), orthonormalize=True)
    result = fitting_error(log, basis)
    a = np.asarray(log.coeffs, np.float64)
    assert result.mean[0] == pytest.approx(np.mean(np.sum(a[:, 1:] ** 2, axis=1)), rel=1e-9)
