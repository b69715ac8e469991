"""``common.validation.check_memory``: the counts whose arrays need 128 MiB or more are
held against the available memory; below 128 MiB nothing is read.

Reference (outside the code): the arithmetic of the arrays, 8 bytes per float64 value
(a refit ring buffer of ``window`` rows by ``n_modes`` columns: ``8 window n_modes``
bytes), against an available memory set here (``modalinfo.common.memory.
available_memory_bytes`` replaced), and the documented 128 MiB = 2^27 bytes skip.

Planted bug R8-20 (docs/MUTATION.md, round 8): the skip raised to 2^37 bytes (128 GiB)
let every count needing 128 MiB - 128 GiB through unchecked (a 20 GiB ring buffer on a
16 GiB machine: NumPy's MemoryError again); the tests of audit 9-inputs ask for 10^12
values (TiB), above either threshold.
"""
from __future__ import annotations

import numpy as np
import pytest

from modalinfo.common import memory
from modalinfo.common.validation import check_memory
from modalinfo.forecast import ARMAPredictor

MIB = 2**20


def _available(monkeypatch, value):
    reads = []

    def fake():
        reads.append(value)
        return float(value)

    monkeypatch.setattr(memory, "available_memory_bytes", fake)
    return reads


def test_from_128_mib_the_available_memory_decides(monkeypatch):
    reads = _available(monkeypatch, 100 * MIB)
    check_memory(128 * MIB - 1, "count", 1, "arrays")  # the skip: no read, no refusal
    assert reads == []
    with pytest.raises(ValueError, match=r"`count` = 7 needs about 0.125 GiB for arrays and "
                                         r"0.0977 GiB is available"):
        check_memory(128 * MIB, "count", 7, "arrays")  # 128 / 1024, 100 / 1024 GiB
    assert len(reads) == 1
    _available(monkeypatch, 0)
    check_memory(128 * MIB - 1, "count", 1, "arrays")  # still not read: 0 bytes is no refusal


def test_a_refit_window_beyond_the_available_memory_is_refused(monkeypatch):
    window, n_modes = 2**24, 2  # 8 x 2^24 x 2 bytes = 256 MiB = 0.25 GiB
    _available(monkeypatch, 200 * MIB)  # 0.195 GiB
    x = np.random.default_rng(0).standard_normal((200, n_modes))
    with pytest.raises(ValueError, match=r"`window` = 16777216 needs about 0.25 GiB for the "
                                         r"refit ring buffer of 2 mode\(s\) and 0.195 GiB"):
        ARMAPredictor(order=(1, 0), refit_every=1, window=window).fit(x)
    _available(monkeypatch, 300 * MIB)  # now it fits: the same predictor is accepted
    ARMAPredictor(order=(1, 0), refit_every=1, window=window).fit(x)
