"""Each predictor's ``fit_bytes`` bounds the memory its fit allocates (left19-est).

Reference: :mod:`tracemalloc`'s peak during ``fit`` (outside the estimate's own
arithmetic), on a seeded Gaussian history at two sizes. tracemalloc counts every NumPy
buffer and is deterministic for a seeded history, so the bounds are not statistical:
the estimate must be at least the peak and less than 4 times it. Each predictor is
fitted once on a small history first: numba's compilation allocates once per process.
Since fix54-b ``fit`` runs the quality pass on histories of 2,000 frames or more (its
calibration-event warning): the model's peak is measured without it (``fit_bytes``), and
the whole fit's against the larger of ``fit_bytes`` and ``quality_memory`` (the pass's
estimate), as tests/ordering/test_memory_counts_fixes42.py does for ``order_modes``.
"""

import tracemalloc

import numpy as np
import pytest

from modalinfo.forecast.base import training_events_judged
from modalinfo.forecast.presets import make_predictor
from modalinfo.telemetry.quality import quality_memory


@pytest.mark.parametrize("name", ["linear", "linear-ls", "arma", "nn", "multivariate", "rls",
                                  "info"])
@pytest.mark.parametrize("n_samples", [3000, 6000])
def test_fit_bytes_bounds_the_fit_peak(name, n_samples):
    n_modes = 10
    rng = np.random.default_rng(5)
    make_predictor(name).fit(rng.standard_normal((600, n_modes)))
    x = rng.standard_normal((n_samples, n_modes))
    pred = make_predictor(name)
    tracemalloc.start()
    try:
        with training_events_judged():  # the model's own allocations (fix54-b)
            pred.fit(x)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    estimate = pred.fit_bytes(n_samples, n_modes)
    assert peak <= estimate < 4 * peak, (estimate, peak)
    # with the calibration-event pass (histories of >= 2,000 frames, fix54-b): it peaks
    # before the estimate and is freed, so the larger of the two bounds the fit
    tracemalloc.start()
    try:
        make_predictor(name).fit(x)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= max(estimate, quality_memory(n_samples, n_modes)), (estimate, peak)
