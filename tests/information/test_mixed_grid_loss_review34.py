"""``histogram.mixed_grid_loss`` against its documented model, computed by scipy (review34).

Round 51 PART a (Q63): y's normal scores given level i of the discrete x are modelled as
normal with the level's mean and the pooled within-level s.d. (``n - m`` degrees of
freedom); the loss is that model's MI minus its MI with y read by k equiprobable bins at
``Phi^-1(j / k)``. References, outside the package: the scores by
``scipy.stats.rankdata`` and ``scipy.special.ndtri``, the levels' means and pooled s.d. by
numpy, the mixture's entropy by ``scipy.integrate.quad``, the binned MI by
``scipy.stats.norm.cdf``. Levels far apart against the noise (two and three levels,
unequal shares), where the pooled and the total s.d. differ by a factor of 2 or more.
Seeded data; the comparison is deterministic (quadrature against the trapezoid rule of
4,001 points: agreement to 1e-6 nats).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, stats
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.information.histogram import mixed_grid_loss


def _reference(codes: np.ndarray, m: int, y: np.ndarray, k: int) -> float:
    n = y.size
    s = ndtri(rankdata(y) / (n + 1.0))
    p = np.array([np.mean(codes == i) for i in range(m)])
    mu = np.array([s[codes == i].mean() for i in range(m)])
    sd = math.sqrt(sum(((s[codes == i] - mu[i]) ** 2).sum() for i in range(m)) / (n - m))

    def pdf(t):
        return float(np.sum(p * stats.norm.pdf(t, mu, sd)))

    h = integrate.quad(lambda t: -pdf(t) * math.log(pdf(t)) if pdf(t) > 0 else 0.0,
                       -12, 12, limit=400, points=list(mu))[0]
    model = h - 0.5 * math.log(2 * math.pi * math.e * sd * sd)
    edges = np.concatenate(([-np.inf], stats.norm.ppf(np.arange(1, k) / k), [np.inf]))
    cond = np.array([np.diff(stats.norm.cdf(edges, mu_i, sd)) for mu_i in mu])
    pj = p @ cond
    binned = float(np.sum(p[:, None] * cond * np.log(cond / pj[None, :])))
    return max(model - binned, 0.0)


@pytest.mark.parametrize("shares, k", [((0.7, 0.3), 11), ((0.5, 0.3, 0.2), 7),
                                       ((0.5, 0.3, 0.2), 15)])
def test_the_loss_is_the_documented_models(shares, k):
    rng = np.random.default_rng(34)
    n = 3000
    codes = rng.choice(len(shares), size=n, p=shares)
    y = 1.5 * codes + 0.4 * rng.standard_normal(n)
    want = _reference(codes, len(shares), y, k)
    assert want > 0.003  # a loss worth comparing
    assert mixed_grid_loss(codes, len(shares), y, k) == pytest.approx(want, abs=1e-6)
