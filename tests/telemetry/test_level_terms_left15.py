"""The level rule's number of cosine terms at each edge of its constants, in the fast tier.

Reference: the closed-form AR(1) spectrum ``f(w) = sigma^2 / (2 pi (1 - 2 phi cos w +
phi^2))`` at the cosine frequencies ``pi j / n``, with ``phi`` the least-squares AR(1)
coefficient of the record on its lag, a constant and a step dummy at the first frame
after the largest CUSUM excursion (``numpy.linalg.lstsq``), as the documented rule of
``modalinfo._stats.level_stationarity`` states (left14-level): B is the largest count of
terms ``j = 2..B + 1`` whose spectrum stays at least 90 % of ``f(pi / n)`` (so the first
frequency k falling below gives B = k - 2), capped at 40 and at (n - 1) // 2, and a
record with fewer than 6 terms or 64 frames is not judged. The records are seeded AR(1)
draws whose ratio at the crossing is > 2e-3 away from 0.9 on both sides (checked). And
``ar_cosine_transfer`` against
``scipy.signal.freqz`` (``A(exp(-i w))`` is the denominator of ``1 / A``).
"""

import numpy as np
import pytest
from scipy.signal import freqz, lfilter

from modalinfo._stats import ar_cosine_transfer, level_stationarity

N = 2000


def _record(phi, seed):
    return lfilter([1.0], [1.0, -phi], np.random.default_rng(seed).standard_normal(N))


def _ratio(x):
    """f(pi j / n) / f(pi / n), j = 1..41, of the record's least-squares AR(1) fit."""
    n = x.size
    frame = int(np.argmax(np.abs(np.cumsum(x - x.mean())[:-1]))) + 1
    t = np.arange(1, n)
    design = np.column_stack([x[:-1], np.ones(n - 1), (t >= frame).astype(float)])
    phi = np.linalg.lstsq(design, x[1:], rcond=None)[0][0]
    w = np.pi * np.arange(1, 42) / n
    f = 1.0 / (1.0 - 2.0 * phi * np.cos(w) + phi ** 2)
    return f / f[0]


def _first_below(ratio, flatness):
    below = np.flatnonzero(ratio < flatness)
    return int(below[0]) + 1 if below.size else None     # frequency index j


@pytest.mark.parametrize("phi, seed, k", [
    (0.97023, 0, 7),     # 5 terms: one short of the fewest judged
    (0.96561, 0, 8),     # 6 terms: the fewest judged
    (0.91236, 5, 20),    # 18 terms: far from either edge
])
def test_terms_end_where_the_ar1_spectrum_falls_below_90_percent(phi, seed, k):
    x = _record(phi, seed)
    ratio = _ratio(x)
    assert _first_below(ratio, 0.9) == k
    # no rounding luck: the crossing is clear on both sides
    assert ratio[k - 2] > 0.9 + 2e-3 and ratio[k - 1] < 0.9 - 2e-3
    # 10 % of the flatness either way moves the crossing
    assert _first_below(ratio, 0.81) > k > _first_below(ratio, 0.99)
    t = level_stationarity(x, p=1)
    assert t.terms == k - 2
    assert t.judged == (k - 2 >= 6)


def test_a_flat_spectrum_takes_forty_terms():
    # white noise whose fitted AR(1) coefficient is negative: the spectrum rises from
    # pi / n on, every one of the 41 frequencies passes, so the cap of 40 decides
    x = np.random.default_rng(0).standard_normal(N)
    ratio = _ratio(x)
    assert _first_below(ratio, 0.9) is None and ratio.min() >= 1.0
    t = level_stationarity(x, p=1)
    assert t.terms == 40 and t.judged


def test_cosine_transfer_is_scipys_frequency_response():
    a = np.array([-1.6, 0.8, 0.05])          # A(z) = 1 - 1.6 z^-1 + 0.8 z^-2 + 0.05 z^-3
    n, j = 500, np.arange(0, 30)
    transfer, phase = ar_cosine_transfer(a, n, j)
    _, h = freqz([1.0], np.r_[1.0, a], worN=np.pi * j / n)
    np.testing.assert_allclose(transfer, 1.0 / h, rtol=1e-12)
    np.testing.assert_allclose(phase, np.exp(-1j * np.pi * np.outer(j, [1, 2, 3]) / n),
                               rtol=1e-12)
    white, _ = ar_cosine_transfer(np.zeros(0), n, j)
    np.testing.assert_array_equal(white, np.ones(j.size))


def test_the_fewest_frames_judged_is_64():
    # documented: the rule judges from 64 frames (MIN_LEVEL_FRAMES); at 64 a flat
    # spectrum's terms are capped by the record, (64 - 1) // 2 = 31 (fewer than 40)
    x = np.random.default_rng(1).standard_normal(64)
    assert _first_below(_ratio(x), 0.9) is None
    t = level_stationarity(x, p=1)
    assert t.judged and t.terms == 31
    short = level_stationarity(x[:63], p=1)
    assert not short.judged and short.terms == 0 and short.frame == 0
