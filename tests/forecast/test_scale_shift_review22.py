"""``_scale_shift`` leaves out the modes of too few correlation times (review 22).

Issue 27, review22 (docs/MUTATION.md, "Planted bugs, round 22", F2: the lag-1
autocorrelation of the effective-count gate centred over the modes instead of over each
mode's frames passed the forecast tests, whose judged modes are all AR(1) 0.9). Reference,
outside the code: each mode's lag-1 autocorrelation by ``numpy.corrcoef`` and the
documented gate ``n (1 - r) / (1 + r) >= MIN_SHIFT_EFFECTIVE`` (10) on the ``n = n_train -
p`` rows of the training fit; an AR(1) at 0.9999 over 1,500 training frames spans about
0.1 effective values (not judged: NaN), an AR(1) at 0.9 about 79 (judged, finite).
"""

from __future__ import annotations

import importlib

import numpy as np

from modalinfo._stats import INNOVATION_ORDER, MIN_SHIFT_EFFECTIVE

ev = importlib.import_module("modalinfo.forecast.evaluate")


def _ar1(n: int, phi: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    for t in range(1, n):
        x[t] += phi * x[t - 1]
    return x


def test_modes_of_too_few_correlation_times_are_not_judged(monkeypatch):
    monkeypatch.setattr(ev, "_SHIFT_BLOCK_VALUES", 1500, raising=False)  # a mode a block
    x = np.column_stack([_ar1(3000, 0.9, 1), _ar1(3000, 0.9999, 2) + 5.0,
                         _ar1(3000, 0.9, 3) - 2.0])
    n_train = 1500
    ratio, _, _ = ev._scale_shift(x, x[:n_train], n_train, 400, 0.01)
    n_rows = n_train - INNOVATION_ORDER
    for m in range(x.shape[1]):
        col = x[:n_train, m]
        r = min(max(np.corrcoef(col[:-1], col[1:])[0, 1], 0.0), 0.999)
        judged = n_rows * (1 - r) / (1 + r) >= MIN_SHIFT_EFFECTIVE
        assert np.isfinite(ratio[m]) == judged, (m, r)
    assert np.isnan(ratio[1]) and np.isfinite(ratio[[0, 2]]).all()
