"""A log with one varying mode is judged for frames written twice (fixes 48-b).

Merge fixes of stop 54 left it (modalinfo/telemetry/quality.py ``_copied_frames``): the
chance that two frames agree was each varying mode's collision share on the sample, which
holds the copies themselves, so with one mode the expected count of chance ties was the
count of copies, and a block of 500 frames written twice into a 20,000-frame AR(1) float64
log was never flagged. The one-mode chance model now comes from the mode's grid (the
smallest gap between its distinct values, which copies do not change, times its density).
References: the construction (which rows were copied from where) for the flagged logs;
for the logs that must not be flagged, their quantisation by construction (8-bit, 12-bit,
five DAC levels, float32 storage: ties that are chance) and the shipped logs (data/).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.io import load
from modalinfo.telemetry.quality import assess_quality

DATA = Path(__file__).resolve().parents[2] / "data"


def _ar(seed: int, n: int = 20000) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal(n + 500)
    return lfilter([1.0], [1.0, -0.9], e)[500:]


def test_a_block_written_twice_in_one_mode_is_flagged():
    x = _ar(0)
    x[10000:10050] = x[5000:5050]  # a re-sent block of 50 frames
    r = assess_quality(x[:, None])
    assert np.array_equal(r.copied_frames, np.arange(10000, 10050))
    assert r.copied_block == (10000, 10050, 5000)


def test_scattered_resent_frames_of_one_mode_are_flagged():
    rng = np.random.default_rng(3)
    x = _ar(1)
    idx = np.sort(rng.choice(np.arange(1000, 20000, 3), 20, replace=False))
    x[idx] = x[idx - rng.integers(2, 999, idx.size)]  # earlier frames, not the one before
    assert np.array_equal(assess_quality(x[:, None]).copied_frames, idx)


@pytest.mark.parametrize("kind", ["float64", "float32", "8-bit", "12-bit", "dac-5"])
def test_clean_and_quantised_single_modes_are_not_flagged(kind):
    for seed in range(3):
        x = _ar(10 + seed)
        s = x.std()
        x = {"float64": x, "float32": x.astype(np.float32), "8-bit": np.round(x / s * 32),
             "12-bit": np.round(x / s * 512),
             "dac-5": np.clip(np.round(x / s), -2, 2)}[kind]
        assert assess_quality(x[:, None]).copied_frames.size == 0, (kind, seed)


@pytest.mark.parametrize("name", sorted(p.name for p in DATA.glob("*.npz")))
def test_no_column_of_a_shipped_log_is_flagged(name):
    coeffs = np.asarray(load(DATA / name).coeffs)
    for j in range(coeffs.shape[1]):
        assert assess_quality(coeffs[:, j:j + 1]).copied_frames.size == 0, j
