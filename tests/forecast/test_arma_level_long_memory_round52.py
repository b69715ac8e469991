"""ARMAPredictor's level-step warning on long memory says so (round 52 PART a, P61).

Reference: fractional Gaussian noise (exact, circulant embedding of its
autocovariance ``0.5 (|k + 1|^2H - 2 |k|^2H + |k - 1|^2H)``, Davies & Harte 1987) is
stationary: it has no level step. The EWC level rule reads its slow wander as one (round
30 PART a, Q11 / Q12; 13 of 50 fits of fGn / ARFIMA of 10,000 frames in round 52), and
the warning said only "the mean ... steps or drifts ... fit each stretch of steady
conditions on its own". It must name long memory as the other reading.
"""

from __future__ import annotations

import warnings

import numpy as np

from modalinfo._stats import LevelStepWarning
from modalinfo.forecast import ARMAPredictor


def _fgn(n: int, hurst: float, rng: np.random.Generator) -> np.ndarray:
    k = np.arange(n, dtype=float)
    g = 0.5 * (np.abs(k + 1) ** (2 * hurst) - 2 * k ** (2 * hurst)
               + np.abs(k - 1) ** (2 * hurst))
    lam = np.clip(np.fft.fft(np.concatenate([g, g[-2:0:-1]])).real, 0.0, None)
    z = rng.standard_normal(lam.size) + 1j * rng.standard_normal(lam.size)
    return np.fft.fft(np.sqrt(lam / lam.size) * z).real[:n]


def test_the_level_warning_on_fractional_noise_names_long_memory():
    # since fix54-a the rule reads the series' long memory and is silent on these
    # stationary seeds (tests/forecast/test_level_shift_long_memory_fix54a.py); the
    # wording is checked where it warns: the same fGn with +4 sd from 60 % of the record
    texts = []
    for seed in range(6):
        x = _fgn(10_000, 0.9, np.random.default_rng(9100 + seed))
        x[6000:] += 4.0 * x.std()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            ARMAPredictor().fit(x[:, None])
        texts += [str(w.message) for w in caught if issubclass(w.category, LevelStepWarning)]
    assert texts, "no seed warned: the test would not test the wording"
    assert all("long memory" in t for t in texts)
