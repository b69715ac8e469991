"""Leftovers 18-stats: the union bound's spread term for a value inside / outside its sample.

References, all outside the code: seeded numpy simulations of standard Gaussian samples
(their median and 1.4826 MAD from ``numpy.median``), against

* the variance ``var(e_t - median) = 1 + (pi / 2 - 2) / N`` of a value of its own sample
  (``var(median) = pi / (2 N)`` and ``cov(e_t, median) = 1 / N`` from Bahadur's
  representation, Ann. Math. Statist. 37, 577 (1966)), not the ``1 + pi / (2 N)`` of a
  value outside it;
* the per-value tail ``P(|e_t - median| > k s)`` that ``modalinfo._stats.
  mad_union_threshold`` sets to ``alpha`` for one value (``n_values = 1``), the law of
  ``s`` from 1e5 separate seeded samples: counted over 1e7 values inside their sample
  and 5e6 outside, the standard error from the spread of the per-sample counts (the
  values of one sample share its median and MAD). The bound is 4 standard errors; the
  other term's ``k`` misses by > 15 of them (measured: in-sample 0.981 +- 0.008 of
  alpha with the in-sample term, 0.755 with the outside one; outside 0.992 +- 0.012
  with the outside term, 1.28 with the in-sample one).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from modalinfo._stats import MAD_RELATIVE_SD, mad_union_threshold
from modalinfo.information.resampling import heavy_tail_threshold
from modalinfo.telemetry.quality import MAD_TO_SIGMA, small_sample_threshold

N = 50
ALPHA = 2e-3


def _deviations(rng: np.random.Generator, rows: int, n: int):
    g = rng.standard_normal((rows, n))
    d = g - np.median(g, axis=1, keepdims=True)
    return d, MAD_TO_SIGMA * np.median(np.abs(d), axis=1)


@functools.lru_cache(maxsize=1)
def _law() -> np.ndarray:
    return _deviations(np.random.default_rng(7), 100_000, N)[1]


def _ratio(counts: np.ndarray, per_row: int) -> tuple[float, float]:
    """Measured rate / ALPHA and its standard error (rows independent)."""
    p = counts.sum() / (counts.size * per_row)
    se = counts.std() / math.sqrt(counts.size) / per_row
    return p / ALPHA, se / ALPHA


def test_variance_of_a_value_about_its_own_median():
    n = 101
    d, _ = _deviations(np.random.default_rng(5), 20_000, n)
    sq = (d ** 2).mean(axis=1)
    m, se = sq.mean(), sq.std() / math.sqrt(sq.size)  # se ~ 1e-3
    inside = 1.0 + (math.pi / 2.0 - 2.0) / n  # 0.99575
    outside = 1.0 + math.pi / (2.0 * n)  # 1.01555
    assert abs(m - inside) < 4 * se, (m, se)
    assert abs(m - outside) > 10 * se, (m, se)


def test_in_sample_tail_is_alpha():
    law = _law()
    k_in = mad_union_threshold(law, None, 1, 1, N, ALPHA, 1.0, 10.0, in_sample=True)
    k_out = mad_union_threshold(law, None, 1, 1, N, ALPHA, 1.0, 10.0, in_sample=False)
    rng = np.random.default_rng(11)
    c_in, c_out = [], []
    for _ in range(10):
        d, s = _deviations(rng, 20_000, N)
        c_in.append((np.abs(d) > k_in * s[:, None]).sum(axis=1))
        c_out.append((np.abs(d) > k_out * s[:, None]).sum(axis=1))
    r_in, se = _ratio(np.concatenate(c_in), N)
    r_out, _ = _ratio(np.concatenate(c_out), N)
    assert abs(r_in - 1.0) < 4 * se, (r_in, se)
    assert abs(r_out - 1.0) > 15 * se, (r_out, se)  # the term used before left18


def test_out_of_sample_tail_is_alpha():
    law = _law()
    k_out = mad_union_threshold(law, None, 1, 1, N, ALPHA, 1.0, 10.0, in_sample=False)
    k_in = mad_union_threshold(law, None, 1, 1, N, ALPHA, 1.0, 10.0, in_sample=True)
    rng = np.random.default_rng(13)
    c_out, c_in = [], []
    for _ in range(5):
        g = rng.standard_normal((20_000, 2 * N))
        med = np.median(g[:, :N], axis=1, keepdims=True)
        s = MAD_TO_SIGMA * np.median(np.abs(g[:, :N] - med), axis=1)
        dev = np.abs(g[:, N:] - med)  # N values tested against the other N's median
        c_out.append((dev > k_out * s[:, None]).sum(axis=1))
        c_in.append((dev > k_in * s[:, None]).sum(axis=1))
    r_out, se = _ratio(np.concatenate(c_out), N)
    r_in, _ = _ratio(np.concatenate(c_in), N)
    assert abs(r_out - 1.0) < 4 * se, (r_out, se)
    assert abs(r_in - 1.0) > 15 * se, (r_in, se)


def test_callers_pass_the_right_term():
    # heavy_tail_threshold tests the innovations its median and MAD come from: below the
    # outside term's k, which its quad reference (test_resampling_rules_left16) pins
    nodes, w = np.polynomial.hermite_e.hermegauss(80)
    s = 1.0 + MAD_RELATIVE_SD / math.sqrt(496) * nodes
    outside = mad_union_threshold(s, w / w.sum(), 496, 2, 496, 1e-4, 1.0, 20.0,
                                  in_sample=False)
    assert heavy_tail_threshold(496) < outside - 0.01
    # the quality rule's default (a strided subsample) keeps the outside term
    assert small_sample_threshold(50, 50, 27, in_sample=True) < \
        0.99 * small_sample_threshold(50, 50, 27)
