"""Planted-bug review 18 (issue 27): forecast / reorder / select read a small log, map a large one.

Leftovers 18-sigint made every command reading through ``load_log_with_hints`` map a
log only when it is larger than ``min(MAP_ABOVE, usable memory / 8)`` (a mapped file
truncated meanwhile is a SIGBUS). Only ``info`` was tested end to end; this pins the
shared loader, for the mapping requested (``mmap=True``, as forecast / reorder / select
ask) and not requested.

Reference from outside the code: NumPy's own type for a memory-mapped array
(``numpy.memmap``, found on the array or its ``.base`` chain) and the values of the array
the test wrote (``numpy.save``), compared bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

import modalinfo.io
from modalinfo.cli import build_parser
from modalinfo.cli.shared import load_log_with_hints


def _mapped(a) -> bool:
    while a is not None:
        if isinstance(a, np.memmap):
            return True
        a = getattr(a, "base", None)
    return False


@pytest.fixture
def small(tmp_path):
    data = np.random.default_rng(31).standard_normal((400, 6))
    path = tmp_path / "night.npy"
    np.save(path, data)
    return path, data


@pytest.mark.parametrize("above, asked, want", [
    (None, True, False),  # 19 kB below 128 MiB: read even when mapping is asked
    (0, True, True),  # above the threshold and asked: mapped
    (0, False, False),  # above the threshold, not asked: read
])
def test_shared_loader_maps_only_large_logs_when_asked(small, monkeypatch, above, asked, want):
    path, data = small
    if above is not None:
        monkeypatch.setattr(modalinfo.io, "MAP_ABOVE", above)
    args = build_parser().parse_args(["forecast", str(path), "--rate", "1000"])
    log = load_log_with_hints(path, args, mmap=asked, announce=False)
    assert _mapped(log.coeffs) is want
    assert np.array_equal(np.asarray(log.coeffs), data)
