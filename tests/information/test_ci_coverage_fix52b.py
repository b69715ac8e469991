"""Coverage of ``conditional_mutual_information_ci`` on persistent rows (issue 27, fix52-b).

With one x and one y column the interval takes the floor of ``mutual_information_ci``
(fix51-b) on x's and y's residuals on z: the Gaussian method gives the Fisher-z interval
``z -+ z_0.975 s_z`` (``z = atanh|r_p|``, ``I = ln cosh z``) with ``s_z`` the larger of the
block replicates' s.d. of z and ``1 / sqrt(n_eff - 3 - k)`` (k conditioning columns,
n_eff Bartlett's effective pairs of the residuals); the other methods their "normal"
interval with the spread raised to ``|r_p| / sqrt(n_eff - 3 - k)``.

References, from outside the package:
- the exact CMI of a jointly Gaussian triple ``x = z bx + u``, ``y = z by + v``, (u, v)
  of correlation rho_p independent of z: ``-0.5 ln(1 - rho_p^2)`` (Cover & Thomas 2006,
  eq. 8.56 with the partial correlation); every series AR(1) of coefficient phi from a
  stationary start, so each frame is that Gaussian triple; the binomial s.e.
  ``sqrt(0.95 * 0.05 / seeds)`` of the nominal level;
- the interval: numpy / scipy only (``scipy.stats.rankdata``, ``scipy.special.ndtri``,
  ``numpy.linalg.lstsq`` residuals of the normal scores on z's and a constant, their
  Pearson correlation (the partial correlation), the lag-1 sample autocorrelation of the
  centred residuals with Kendall's (1954) bias correction ``r + (1 + 3 r) / n``,
  Bartlett's (1935) count, or his full sum over lags where fewer (round 52 PART a's long
  memory rule, test_ci_coverage_fix51b's ``_n_eff``), Fisher's (1924) ``n - 3 - k`` of a
  partial correlation), from
  the package's own replicates (its block indices are its own).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.special import ndtri

from modalinfo.information import conditional_mutual_information_ci, mutual_information_ci

from ._ar_coverage import ar1 as _ar
from ._ar_coverage import ar_pair as _ar_pair
from .test_ci_coverage_fix51b import _bartlett_mi_sd, _n_eff

Z975 = stats.norm.ppf(0.975)


def _ar_triple(phi: float, n: int, k: int, cmi: float, seed: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x = z bx + u, y = z by + v: (u, v) of partial correlation giving ``cmi`` nats."""
    rng = np.random.default_rng(seed)
    rp = math.sqrt(1.0 - math.exp(-2.0 * cmi))
    e = _ar(phi, n, 2 + k, rng)
    u, v, z = e[:, 0], rp * e[:, 0] + math.sqrt(1.0 - rp * rp) * e[:, 1], e[:, 2:]
    bx, by = np.array([0.8, -0.5, 0.3])[:k], np.array([0.6, 0.4, -0.7])[:k]
    return (z @ bx + u)[:, None], (z @ by + v)[:, None], z


def _scores(a: np.ndarray) -> np.ndarray:
    return ndtri(stats.rankdata(a, axis=0) / (a.shape[0] + 1.0))


def _residuals(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """lstsq residuals of x's and y's normal scores on z's and a constant."""
    d = np.column_stack([np.ones(z.shape[0]), _scores(z)])
    out = []
    for a in (x, y):
        s = _scores(a)[:, 0]
        out.append(s - d @ np.linalg.lstsq(d, s, rcond=None)[0])
    return out[0], out[1]


def _floor_parts(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[float, float, float]:
    """(partial correlation, normal-score correlation of the residuals, 1/sqrt(n_eff-3-k))."""
    rx, ry = _residuals(x, y, z)
    k = z.shape[1]
    n_eff = _n_eff(rx, ry, cross=True)  # the CMI's floor (fix54-c)
    r_scores = float(np.corrcoef(_scores(rx), _scores(ry))[0, 1])
    return (float(np.corrcoef(rx, ry)[0, 1]), r_scores,
            1.0 / math.sqrt(max(n_eff - 3.0 - k, 1.0)))


@pytest.mark.parametrize("phi, k, cmi, seed", [(0.97, 3, 0.1, 1), (0.9, 1, 0.5, 2),
                                               (0.97, 1, 0.0, 3)])
def test_gaussian_cmi_interval_is_the_bartlett_fisher_interval(phi: float, k: int,
                                                               cmi: float, seed: int) -> None:
    """Gaussian CMI, block bootstrap = numpy's Fisher interval on the partial correlation."""
    x, y, z = _ar_triple(phi, 500, k, cmi, 52500 + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # BlockBootstrapWarning below 50 effective pairs
        res = conditional_mutual_information_ci(x, y, z, method="gaussian", n_resamples=49,
                                                seed=seed)
    r_p, _, s_floor = _floor_parts(x, y, z)
    d = res.bootstrap_distribution
    s_boot = float(np.std(np.arctanh(np.sqrt(-np.expm1(-2.0 * np.maximum(d, 0.0)))), ddof=1))
    s_z = max(s_boot, s_floor)
    zh = math.atanh(abs(r_p))
    low = 0.0 if zh - Z975 * s_z <= 0.0 else math.log(math.cosh(zh - Z975 * s_z))
    assert res.interval == "fisher"
    assert res.estimate == pytest.approx(-0.5 * math.log(1.0 - r_p * r_p), abs=1e-12)
    assert (res.low, res.high) == pytest.approx(
        (low, math.log(math.cosh(zh + Z975 * s_z))), abs=1e-12)


@pytest.mark.parametrize("method, seed, options", [("histogram", 4, {"bins": 5}),
                                                   ("kde", 5, {})])
def test_cmi_normal_interval_takes_bartletts_floor(method: str, seed: int,
                                                   options: dict) -> None:
    """Histogram / kde CMI: half-width z_0.975 max(s_boot, |r_p| / sqrt(n_eff - 3 - k)).

    AR(1) 0.97 rows, n = 500, one conditioning column (~17 effective pairs): the floor
    binds (asserted), so the interval before (``z_0.975 s_boot``) fails here. The
    histogram at 5 bins per axis, the rule's at n = 500 over 3 columns, given: bins the
    caller chose keep the upper bound (fix53-b raises it by the grid's loss at the rule's
    bins: test_cmi_grid_loss_fix53b.py).
    """
    x, y, z = _ar_triple(0.97, 500, 1, 0.5, 52500 + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # BlockBootstrapWarning: ~17 effective pairs
        res = conditional_mutual_information_ci(x, y, z, method=method, n_resamples=49,
                                                seed=seed, **options)
    _, r_scores, s_floor = _floor_parts(x, y, z)
    s_boot = float(np.std(res.bootstrap_distribution, ddof=1))
    floor = abs(r_scores) * s_floor
    assert floor > s_boot
    assert res.interval == "normal"
    assert (res.low, res.high) == pytest.approx(
        (res.estimate - Z975 * floor, res.estimate + Z975 * floor), abs=1e-12)


def test_two_column_groups_keep_the_bootstrap_spread() -> None:
    """x of two columns: no partial correlation, so the interval is z_0.975 s_boot."""
    x, y, z = _ar_triple(0.97, 500, 2, 0.5, 52507)
    x2 = np.column_stack([x[:, 0], z[:, 1] + np.random.default_rng(7).standard_normal(500)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = conditional_mutual_information_ci(x2, y, z[:, :1], method="gaussian",
                                                n_resamples=49, seed=7)
    half = Z975 * float(np.std(res.bootstrap_distribution, ddof=1))
    assert res.interval == "normal"
    assert (res.low, res.high) == pytest.approx((res.estimate - half, res.estimate + half),
                                                abs=1e-12)


@pytest.mark.parametrize("method, interval, seed", [("gaussian", "percentile", 1),
                                                    ("gaussian", "basic", 2),
                                                    ("histogram", "percentile", 3),
                                                    ("kde", "basic", 4)])
def test_block_quantile_intervals_take_bartletts_floor(method: str, interval: str,
                                                       seed: int) -> None:
    """MI, block "percentile" / "basic": the quantiles' offsets from the estimate widened.

    By g = |r| / sqrt(n_eff - 3) over the replicates' s.d. where above 1 (asserted: AR(1)
    0.97 pairs, n = 500, ~17 effective pairs); numpy's type-6 quantiles (the package's rule,
    ``resampling.percentile_bounds``) of the package's replicates.
    """
    x, y = _ar_pair(0.97, 0.6, 500, 52600 + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # BlockBootstrapWarning: ~17 effective pairs
        res = mutual_information_ci(x, y, method=method, n_resamples=99, seed=seed,
                                    interval=interval)
    d, theta = res.bootstrap_distribution, res.estimate
    g = _bartlett_mi_sd(x, y) / float(np.std(d, ddof=1))
    q_lo, q_hi = np.quantile(d, [0.025, 0.975], method="weibull")
    lo, hi = theta - g * (theta - q_lo), theta + g * (q_hi - theta)
    if interval == "basic":
        lo, hi = 2.0 * theta - hi, 2.0 * theta - lo
    assert g > 1.0
    assert res.interval == interval
    assert res.low == pytest.approx(lo, abs=1e-12)
    if res.note:  # the histogram's grid-loss raise of the upper end (round 15 PART a)
        assert res.high > hi
    else:
        assert res.high == pytest.approx(hi, abs=1e-12)

