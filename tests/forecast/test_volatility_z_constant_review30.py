"""``_volatility_z``: NaN on a constant level, few flags on an independent one (review30).

Fixes 47-c's docstring: "NaN when ``d`` is too short or ``d`` or the level is constant".
Tests reached a constant ``d`` only through ``evaluate``; a planted ``qq <= 0.0 and
pp <= 0.0`` (NaN only when both are constant) passed, and then a constant level divides
by its zero variance (numpy's warning, Python's ZeroDivisionError). Reference: the
docstring, with a level constant by construction.
"""

import math

import numpy as np

from modalinfo.forecast.evaluate import _volatility_z


def test_a_constant_level_gives_nan():
    d = np.random.default_rng(0).standard_normal(500)
    assert math.isnan(_volatility_z(d, np.full(500, 2.0)))
    assert math.isnan(_volatility_z(np.full(500, 1.0), d * d))


def test_an_independent_persistent_volatility_is_rarely_flagged():
    """Round 30 S8: ``_DM_VOL_LAGS = 2`` (the HAC variance of the correlation cut short)
    passed every test. A differential whose volatility wanders (``e_t |s_t|``, s an AR(1)
    0.99) independently of a persistent level (the square of another AR(1) 0.99 mode):
    no dependence exists by construction, and the module notes measure 0-1 % of such
    draws flagged. Measured here: 2 of 200 (K = 20); 29 of 200 with K = 2. Bound: 10 of
    200 (5 %), 4 binomial sd above 2 %."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(1)
    flagged = 0
    for _ in range(200):
        z = lfilter([1.0], [1.0, -0.99], rng.standard_normal(1500))[1000:]
        s = lfilter([1.0], [1.0, -0.99], rng.standard_normal(1500))[1000:]
        d = rng.standard_normal(500) * np.abs(s)
        flagged += abs(_volatility_z(d, z**2)) > 3
    assert flagged <= 10
