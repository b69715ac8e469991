"""``select_inputs`` refuses a candidate search that cannot fit before it reads the log
(round 46 PART a, A10b).

On a 200,000 x 1000 memory-mapped log the refusal "the candidate search needs about
152580.3 MiB" came after 47 s and 4.1 GB: the log was converted to float64 and scaled
first. Reference (outside the code): the documented size of the search, 10 float64
arrays of (T - horizon - max_lag + 1) x M x max_lag values, against a free memory set
here (``selection.free_memory_bytes`` replaced); the log's reading (``selection._series``)
replaced by a function that fails, so the refusal must come before it.
"""
from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.information import selection
from modalinfo.telemetry import ModalLog


def _no_read(data, name):
    raise AssertionError(f"`{name}` was read before the memory check")


@pytest.mark.parametrize("as_log", [True, False])
def test_refused_before_the_log_is_read(monkeypatch, as_log):
    T, M, h, L = 300, 4, 1, 10
    values = np.random.default_rng(0).normal(size=(T, M))
    data = ModalLog(values, rate=1000.0) if as_log else values
    monkeypatch.setattr(selection, "free_memory_bytes", lambda: 100.0)
    monkeypatch.setattr(selection, "_series", _no_read)
    with pytest.raises(ValueError, match="the candidate search needs about") as info:
        selection.select_inputs(data, 0, horizon=h, max_lag=L, intervals=False)
    n_values = int(re.search(r"= (\d+) values", str(info.value)).group(1))
    assert n_values == (T - h - L + 1) * M * L


def test_extra_columns_counted(monkeypatch):
    T, h, L = 300, 2, 5
    rng = np.random.default_rng(1)
    monkeypatch.setattr(selection, "free_memory_bytes", lambda: 100.0)
    monkeypatch.setattr(selection, "_series", _no_read)
    with pytest.raises(ValueError, match="the candidate search needs about") as info:
        selection.select_inputs(rng.normal(size=(T, 3)), 0, horizon=h, max_lag=L,
                                extra=rng.normal(size=(T, 2)), intervals=False)
    n_values = int(re.search(r"= (\d+) values", str(info.value)).group(1))
    assert n_values == (T - h - L + 1) * 5 * L
