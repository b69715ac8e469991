"""The quality pass on a log longer than its sample holds two copies of the sample, not five.

Issue 27, left30-prov (left28-prov's "Left": the strided case, T > ``sample_frames``,
peaked at 4.3-5 x the sample). The first pass held the sample, the AR(4) windows
(about as many frames as the sample), the level rule's bin sums and a float64 array of
bin counts at once: four arrays of the sample's size. The bin sums are now accumulated
in the flagging pass, after the windows are freed, and a bin's count is its frame count
less the non-finite values (counted only when there are some).

References: ``tracemalloc``'s peak of a second call (numpy's allocations, counted
deterministically; no timing) against a bound in units of the sample's bytes
(``ceil(T / step) x M x 8``): two copies plus the slices' temporaries, with blocks of
1,000 frames and slices of 10 modes' values (a tenth of the sample; the AR fits' lag
stacks, their masked copies and the lattice sort, ~6 at once: <= 0.6 x), so <= 3 x;
the code before peaked at 4.62 x here. The bin means against
``numpy.nanmean`` of each bin (NaN where a bin has no finite value), and
``quality_memory``'s estimate against the measured peak with the default slices.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import modalinfo._stats as stats_mod
from modalinfo.telemetry import assess_quality
from modalinfo.telemetry import quality as quality_mod

T, M, SAMPLE, BLOCK = 20_000, 100, 5_000, 1_000  # stride 4


def _log(frames: int = T, modes: int = M) -> np.ndarray:
    from scipy.signal import lfilter

    rng = np.random.default_rng(3030)  # AR(1), rho 0.5
    return lfilter([1.0], [1.0, -0.5], rng.standard_normal((frames, modes)), axis=0)


def _peak(x: np.ndarray, **kw) -> int:
    assess_quality(x, **kw)  # numba, the MAD's simulated law: cached outside the count
    tracemalloc.start()
    try:
        report = assess_quality(x, **kw)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert report.sample_frames == -(-x.shape[0] // -(-x.shape[0] // kw.get(
        "sample_frames", quality_mod.DEFAULT_SAMPLE_FRAMES)))
    return peak


def test_strided_peak_is_two_copies_of_the_sample_plus_slices(monkeypatch):
    monkeypatch.setattr(quality_mod, "_SLICE_VALUES", 10 * SAMPLE)
    monkeypatch.setattr(stats_mod, "_STACK_VALUES", 10 * SAMPLE)
    x = _log()
    sample_bytes = SAMPLE * M * 8
    peak = _peak(x, sample_frames=SAMPLE, chunk_frames=BLOCK)
    assert peak <= 3.0 * sample_bytes, f"peak {peak / sample_bytes:.2f} x the sample"


@pytest.mark.parametrize("frames", [4000, 4003])  # whole last bin, short last bin
def test_bin_means_are_nanmeans_of_the_bins(frames):
    rng = np.random.default_rng(7)
    x = rng.standard_normal((frames, 5))
    x[100:140, 1] = np.nan  # whole bins with no finite value
    x[::37, 2] = np.inf
    x[-1, 3] = np.nan
    step = 8
    bins = quality_mod._BinMeans(frames, 5, step)
    for i0 in range(0, frames, 1000):  # blocks not aligned with the bins
        bins.add(x[i0:i0 + 1000], i0)
    got = bins.means()
    pad = -frames % step
    padded = np.vstack([np.where(np.isfinite(x), x, np.nan), np.full((pad, 5), np.nan)])
    with np.errstate(invalid="ignore"), pytest.warns(RuntimeWarning, match="Mean of empty"):
        want = np.nanmean(padded.reshape(-1, step, 5), axis=1)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
    np.testing.assert_allclose(got, want, rtol=1e-13, equal_nan=True)
    clean = quality_mod._BinMeans(frames, 5, step)  # no gap: no counts array at all
    clean.add(rng.standard_normal((frames, 5)), 0)
    assert clean.missing is None


def test_estimate_covers_the_strided_peak():
    x = _log(3 * 65_536 + 1, 30)  # stride 4 at the default sample, default slices
    peak = _peak(x, chunk_frames=8192)
    estimate = quality_mod.quality_memory(*x.shape)
    assert peak <= estimate, f"peak {peak / 2**20:.0f} MiB > {estimate / 2**20:.0f} MiB"
