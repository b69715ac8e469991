"""``histogram._within_bin_excess`` against a numpy copy of its documented model (review33).

Mutation round 33 (docs/MUTATION.md): the round-50 Markov-chain file reads the per-bin
model only through warnings at n = 2,000-4,000 with one z column, where every bin of z
holds n / k >= 250 rows: the cell floor (10 samples per column) and the half-of-the-rows
rule could change (10 for 10 d; 5 % for 50 %) unseen. Reference, from the docstring, with
numpy / scipy only: cells = the joint equiprobable bins of z (``scipy.stats.rankdata``,
ordinal, bin ``min(rank k // n, k - 1)`` per column); cells with >= 10 d rows kept, 0.0
if they hold fewer than half the rows; in each, the Gaussian MI of (x, y) from Pearson's
r (``numpy.corrcoef``), ``-0.5 ln(1 - r^2)``, less the Gaussian CMI given z from the
partial correlation of x's and y's least-squares residuals on z and a constant
(``numpy.linalg.lstsq``); averaged with the kept cells' row shares.
"""

import math

import numpy as np
import pytest
from scipy import stats

from modalinfo.information.histogram import _within_bin_excess


def _reference(x, y, z, k):
    n, dz = z.shape
    d = 2 + dz
    bins = np.column_stack([np.minimum((stats.rankdata(z[:, j], method="ordinal") - 1) * k // n,
                                       k - 1) for j in range(dz)])
    cells = {}
    for i, key in enumerate(map(tuple, bins)):
        cells.setdefault(key, []).append(i)
    kept = [np.array(v) for v in cells.values() if len(v) >= 10 * d]
    rows = sum(len(v) for v in kept)
    if rows < 0.5 * n:
        return 0.0
    total = 0.0
    for idx in kept:
        r = np.corrcoef(x[idx], y[idx])[0, 1]
        a = np.column_stack([np.ones(len(idx)), z[idx]])
        ex = x[idx] - a @ np.linalg.lstsq(a, x[idx], rcond=None)[0]
        ey = y[idx] - a @ np.linalg.lstsq(a, y[idx], rcond=None)[0]
        p = np.corrcoef(ex, ey)[0, 1]
        total += len(idx) / rows * (-0.5 * math.log(1 - r * r) + 0.5 * math.log(1 - p * p))
    return total


def _chain(n, seed, dz=1, rho_z=0.0):
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((n, dz))
    if dz == 2:
        z[:, 1] = rho_z * z[:, 0] + math.sqrt(1 - rho_z**2) * z[:, 1]
    s = z.sum(axis=1)
    return s + 0.3 * rng.standard_normal(n), s + 0.3 * rng.standard_normal(n), z


@pytest.mark.parametrize(("n", "dz", "rho_z", "k"), [
    (4000, 1, 0.0, 8),   # every cell kept: the model itself
    (200, 1, 0.0, 8),    # 25 rows a cell, below 10 d = 30: none kept, 0.0
    (400, 2, 0.9, 5),    # two correlated z columns: 28 % of the rows in kept cells, 0.0
    (1200, 2, 0.9, 5),   # the same with 96 % kept (98 % in cells of >= 10 rows)
])
def test_the_per_bin_model_is_the_docstrings(n, dz, rho_z, k):
    x, y, z = _chain(n, 11, dz, rho_z)
    ref = _reference(x, y, z, k)
    got = _within_bin_excess(x[:, None], y[:, None], z, k)
    assert got == pytest.approx(ref, rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("full", [0.0, 0.5, 4.0])
def test_the_excess_gate_is_the_larger_of_point_two_and_ten_percent(full):
    """Warned iff the excess exceeds max(MAX_CONDITIONING_EXCESS = 0.2, 10 % of the CMI).

    The excess here (the reference above) is 0.32 nats: past 0.2 and 10 % of 0.5, not
    10 % of 4.0.
    """
    from modalinfo.information.histogram import _excess_why

    x, y, z = _chain(1200, 11, 2, 0.9)
    excess = _reference(x, y, z, 5)
    assert 0.25 < excess < 0.35
    why = _excess_why(x[:, None], y[:, None], z, 5, full)
    assert (why is not None) == (excess > max(0.2, 0.1 * full))
    if why is not None:
        assert f"reads {excess:.3g} nats" in why and "biased high" in why


def test_the_public_form_bins_the_triple_as_the_histogram_does():
    """``within_bin_excess``: normal scores (scipy), k of the histogram's rule for d = 3."""
    from modalinfo.information.histogram import _bins_per_axis, within_bin_excess

    n = 3000
    x, y, z = _chain(n, 12)

    def scores(v):
        return stats.norm.ppf(stats.rankdata(v) / (n + 1))

    k = _bins_per_axis("auto", n, 3)
    assert k != _bins_per_axis("auto", n, 2)  # the rule reads d here
    ref = _reference(scores(x), scores(y), scores(z[:, 0])[:, None], k)
    got = within_bin_excess(x[:, None], y[:, None], z, {})
    assert got == pytest.approx(ref, rel=1e-6, abs=1e-9)
