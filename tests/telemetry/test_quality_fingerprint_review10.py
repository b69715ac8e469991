"""A log derived from a read-only memory map does not inherit the map's fingerprint.

Round 10 of planted bugs (review10). Issue 27 leftovers 11 let a log whose bytes nobody
can write (a map opened read-only) keep its ``data_fingerprint``; a log derived from it
(other units, other columns) holds other values or labels. Reference, from outside the
cache: a pickle round trip of the derived log (``__setstate__`` drops any cached
fingerprint, so the copy's is computed from its bytes, times and labels) and the
fingerprint's contract ("any changed value, frame time or label changes it"). Planted
bug R10-M4 (``_derive`` no longer resetting the cache) escaped the quality tests: the
derived log answered with its parent's fingerprint and a report of the parent was
applied to it.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.telemetry import apply_outlier_policy, assess_quality
from modalinfo.telemetry.quality import data_fingerprint


@pytest.mark.parametrize("derive", ["units", "columns"])
def test_a_log_derived_from_a_read_only_map_has_its_own_fingerprint(tmp_path, derive):
    x = np.random.default_rng(10).standard_normal((400, 4))
    x[7, 1] = 60.0
    np.save(tmp_path / "x.npy", x)
    log = load(tmp_path / "x.npy", mmap=True, units="rad", wavelength=500e-9)
    report = assess_quality(log)  # the map's fingerprint is kept from here on
    assert report.fingerprint == data_fingerprint(log)
    if derive == "units":
        other = log.to_units("nm")  # x 500 / (2 pi): other values
    else:
        other = log.select(modes=list(reversed(log.modes)))  # other column order
    fresh = pickle.loads(pickle.dumps(other))  # same bytes, times, labels; no cache
    assert data_fingerprint(other) == data_fingerprint(fresh)
    assert data_fingerprint(other) != report.fingerprint
    with pytest.raises(ValueError, match="must be the assessment of this log"):
        apply_outlier_policy(other, "clip", report=report)
