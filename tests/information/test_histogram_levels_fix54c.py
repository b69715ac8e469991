"""The histogram CMI of discrete columns: levels coded as levels, merged levels judged (fix54-c).

References, all outside the estimator: the Miller-Madow plug-in CMI of the exact levels'
table, counted with ``numpy.unique`` (Miller 1955); the exact MI of a bivariate normal
quantised on a lattice, from rectangle probabilities of
``scipy.stats.multivariate_normal.cdf`` (z independent, so the CMI is that MI); the exact
CMI of a symmetric channel of categories, ``ln L + q ln q + (L - 1) r ln r``; the exact
transfer entropy of Poisson counts, H(Poisson 3) - H(Poisson 1) from ``scipy.stats.poisson``.
Measured before / after in docs/ADVERSARIAL.md, "Discrete levels and ties in the
estimators (fix54-c)".
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import multivariate_normal, poisson

from modalinfo.information import conditional_mutual_information, transfer_entropy
from modalinfo.information.methods import BiasRuleWarning

from ._levels_table import plugin_cmi_mm as _plugin_cmi_mm


def _lattice_mi(rho: float, t: np.ndarray) -> float:
    """Exact MI (nats) of a standard bivariate normal quantised at thresholds ``t``."""
    e = np.concatenate([[-12.0], t, [12.0]])
    mvn = multivariate_normal([0.0, 0.0], [[1.0, rho], [rho, 1.0]])
    f = np.array([[mvn.cdf([a, b]) for b in e] for a in e])
    p = np.clip(f[1:, 1:] - f[:-1, 1:] - f[1:, :-1] + f[:-1, :-1], 0.0, None)
    p /= p.sum()
    outer = np.outer(p.sum(1), p.sum(0))
    m = p > 0
    return float((p[m] * np.log(p[m] / outer[m])).sum())


def _channel(rng: np.random.Generator, n: int, levels: int):
    """x uniform, z uniform, y = (x kept with 0.6, else uniform) + z mod L."""
    z = rng.integers(0, levels, n)
    x = (z + rng.integers(0, levels, n)) % levels
    y = (np.where(rng.random(n) < 0.6, x, rng.integers(0, levels, n)) + z) % levels
    return x, y, z


def _channel_cmi(levels: int, keep: float = 0.6) -> float:
    q, r = keep + (1 - keep) / levels, (1 - keep) / levels
    return float(np.log(levels) + q * np.log(q) + (levels - 1) * r * np.log(r))


def test_levels_above_the_bins_are_read_as_their_table():
    """9 levels at n = 4,000 (8 bins per axis): the histogram equals the levels' plug-in.

    Before, 9 levels shared 8 quantile bins and the value was the merged table's.
    """
    rng = np.random.default_rng(3)
    x, y, z = _channel(rng, 4000, 9)
    got = conditional_mutual_information(*(a.astype(float) for a in (x, y, z)),
                                         method="histogram")
    assert got == pytest.approx(_plugin_cmi_mm(x, y, z), abs=1e-9)
    exact = _channel_cmi(9)  # the table's own upward bias (729 cells): +0.052 here
    assert abs(got - exact) < max(0.05, 0.1 * exact)  # the package's tolerance


def test_lattice_quantised_gaussian_reads_its_exact_mi():
    """A rho = 0.8 pair on an 8-level lattice (+-2.5 sd), z independent, n = 2,000.

    Exact 0.4517 nats; before -0.0755 (5 seeds, s.d. 0.007), after -0.002: the mean of
    3 seeds within 0.03 (4 s.e. of the after spread; before it is 0.07 off).
    """
    t = np.linspace(-2.5, 2.5, 9)[1:-1]
    exact = _lattice_mi(0.8, t)
    got = []
    for seed in range(3):
        rng = np.random.default_rng(seed)
        a = rng.standard_normal(2000)
        b = 0.8 * a + 0.6 * rng.standard_normal(2000)
        x = np.searchsorted(t, a).astype(float)
        y = np.searchsorted(t, b).astype(float)
        got.append(conditional_mutual_information(x, y, rng.standard_normal(2000),
                                                  method="histogram"))
    assert abs(np.mean(got) - exact) < 0.03


def test_merged_categories_are_judged_against_the_ksg():
    """12 categories at n = 2,000 (7 bins, table over budget): 0.48 for 0.95, warned.

    Before, the value was returned without a word.
    """
    rng = np.random.default_rng(0)
    x, y, z = (a.astype(float) for a in _channel(rng, 2000, 12))
    with pytest.warns(BiasRuleWarning, match="merges into 7 bins") as rec:
        got = conditional_mutual_information(x, y, z, method="histogram")
    assert got < _channel_cmi(12) - 0.3  # the loss the warning names
    assert "method='ksg'" in str(rec[0].message)


def test_transfer_entropy_of_poisson_counts():
    """Q55: TE of y_t = x_(t-1) + Poisson(1), x ~ Poisson(2) iid, T = 4,001, history 1.

    Exact H(Poisson 3) - H(Poisson 1) = 0.6266; seeds 0-4: before -0.0346 (s.e. 0.0034),
    after -0.0160 (s.e. 0.0040): the mean within 0.027 (2.7 s.e. from the after mean,
    2.2 s.e. from the before one).
    """
    k = np.arange(100)

    def h(mu: float) -> float:
        p = poisson.pmf(k, mu)
        p = p[p > 0]
        return float(-(p * np.log(p)).sum())

    exact = h(3.0) - h(1.0)
    got = []
    for seed in range(5):
        rng = np.random.default_rng(seed)
        x = rng.poisson(2, 4001).astype(float)
        y = np.r_[0.0, x[:-1]] + rng.poisson(1, 4001)
        got.append(transfer_entropy(x, y, lag=1, history=1, method="histogram"))
    assert abs(np.mean(got) - exact) < 0.027
