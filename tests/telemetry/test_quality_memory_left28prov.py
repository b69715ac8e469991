"""The quality pass holds about two copies of its sample, not ten (issue 27, left28-prov).

At 10^4 frames x 2,000 modes the pass peaked at 1408 MiB of numpy allocations for
153 MiB of data (tracemalloc; left28-quality's "Left"): the residuals, their deviations,
the sorts' copies and the level rule's temporaries of every mode at once. Each of those
steps is per mode, so they now run a slice of modes at a time; what must stay whole is
the median / MAD sample itself and the spread rule's absolute deviations (its
Bonferroni union reads every mode), so the peak is bounded by those two copies plus the
slices' temporaries.

References: ``tracemalloc``'s peak of a second call (numpy's allocations, counted
deterministically; no timing; the first call fills the cache of the MAD's simulated law,
a fixed cost whatever the number of modes) against the bound above, 3 x the sample's bytes (2 copies
plus slices of 50 modes, a tenth of the log each, with ~5 temporaries: <= 0.5 x;
the code before this change peaked at 9-10 x); ``numpy.median`` of each column (centre)
and ``1.4826 numpy.median(|x - centre|)`` (scale); the planted glitch, level step and
change of spread found at their frames; and every field of the report the same bits
with slices of 50 modes as with one slice of all (the answers do not depend on the
slicing).
"""

from __future__ import annotations

import dataclasses
import tracemalloc

import numpy as np
import pytest

import modalinfo._stats as stats_mod
from modalinfo.telemetry import assess_quality
from modalinfo.telemetry import quality as quality_mod
from modalinfo.telemetry.quality import MAD_TO_SIGMA

T, M = 1000, 500
SLICE = 50  # modes a slice: 10 slices
GLITCH, STEP, SPREAD = 300, 600, 500


def _log() -> np.ndarray:
    rng = np.random.default_rng(2810)
    x = rng.standard_normal((T, M))
    for t in range(1, T):
        x[t] += 0.5 * x[t - 1]
    x[GLITCH, :5] += 60.0  # a glitched frame, in the first slice
    x[STEP:, 480] += 3.0  # a level step, in the last slice
    x[SPREAD:, 230] *= 4.0  # a change of spread, in a middle slice
    return x


def _slices(monkeypatch, values: int) -> None:
    # raising=False: the code before this change had no slices (the test then measures
    # its whole-sample peak)
    monkeypatch.setattr(quality_mod, "_SLICE_VALUES", values, raising=False)
    monkeypatch.setattr(stats_mod, "_STACK_VALUES", values)


def test_peak_is_two_copies_of_the_sample_plus_slices(monkeypatch):
    x = _log()
    _slices(monkeypatch, SLICE * T)
    # once outside the measurement: numba's compilation, and the simulated law of the
    # MAD for this many effective frames (a cached fixed cost of ~50 MB, whatever M)
    assess_quality(x)
    tracemalloc.start()
    try:
        assess_quality(x)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= 3.0 * x.nbytes, f"peak {peak / x.nbytes:.2f} x the sample"


def test_sliced_pass_gives_the_same_answers(monkeypatch):
    x = _log()
    _slices(monkeypatch, SLICE * T)
    sliced = assess_quality(x)
    _slices(monkeypatch, 10 * T * M)  # every mode in one slice
    whole = assess_quality(x)
    for f in dataclasses.fields(sliced):
        a, b = getattr(sliced, f.name), getattr(whole, f.name)
        if f.name == "predictor":
            assert all(np.array_equal(u, v, equal_nan=True) for u, v in zip(a, b, strict=True))
        elif isinstance(a, np.ndarray):
            assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), f.name
        else:
            assert a == b or (a != a and b != b), f.name
    # against numpy, column by column
    centre = np.median(x, axis=0)
    np.testing.assert_allclose(sliced.median, centre, rtol=1e-15)
    np.testing.assert_allclose(sliced.sigma, MAD_TO_SIGMA * np.median(np.abs(x - centre),
                                                                       axis=0), rtol=1e-15)
    # the planted frames and modes
    assert GLITCH in sliced.glitch_frames
    assert [(label, frame) for label, frame, _, _ in sliced.level_steps] == [
        ("col480", pytest.approx(STEP, abs=10))]
    assert [label for label, *_ in sliced.variance_steps] == ["col230"]
