"""Mutation round 35 (review35): the Bartlett floors of fix52-b at their edges.

``conditional_mutual_information_ci``'s floor (one x and one y column) and
``mutual_information_ci``'s widened block quantiles were read only in nats, on persistent
AR(1) rows where the floor binds, for continuous columns. Here: the same calls in bits
(1 bit = ln 2 nats, so every bound is the nats one over ln 2 with the same seed, hence
the same resample indices); a pair where the floor does not bind (iid rows: the quantile
interval is numpy's type-6 quantiles of the package's own replicates, never narrowed);
the iid bootstrap (no floor: the replicates' quantiles); and the Gaussian method on a
table of discrete columns (no partial correlation to put on Fisher's z: the "normal"
interval). References: numpy's ``quantile(method="weibull")`` (the package's rule,
``resampling.percentile_bounds``), ``math.log(2)``, the normal quantile from scipy.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import stats

from modalinfo.information import conditional_mutual_information_ci, mutual_information_ci

from ._ar_coverage import ar_pair as _ar_pair
from .test_ci_coverage_fix52b import _ar_triple

LN2 = math.log(2.0)


def _quiet(call, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # BlockBootstrapWarning: few effective pairs
        return call(*args, **kwargs)


@pytest.mark.parametrize("method", ["gaussian", "histogram"])
def test_cmi_interval_in_bits_is_the_nats_one_over_ln_2(method: str) -> None:
    # AR(1) 0.97, n = 500: the floor binds (test_ci_coverage_fix52b), so its units count
    x, y, z = _ar_triple(0.97, 500, 1, 0.5, 52504)
    nats = _quiet(conditional_mutual_information_ci, x, y, z, method=method,
                  n_resamples=49, seed=4)
    bits = _quiet(conditional_mutual_information_ci, x, y, z, method=method, units="bits",
                  n_resamples=49, seed=4)
    assert bits.interval == nats.interval
    assert (bits.estimate, bits.low, bits.high) == pytest.approx(
        (nats.estimate / LN2, nats.low / LN2, nats.high / LN2), rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("interval", ["percentile", "basic"])
def test_mi_block_quantiles_in_bits_are_the_nats_ones_over_ln_2(interval: str) -> None:
    x, y = _ar_pair(0.97, 0.6, 500, 52601)
    nats = _quiet(mutual_information_ci, x, y, method="gaussian", n_resamples=99, seed=1,
                  interval=interval)
    bits = _quiet(mutual_information_ci, x, y, method="gaussian", units="bits",
                  n_resamples=99, seed=1, interval=interval)
    assert (bits.low, bits.high) == pytest.approx((nats.low / LN2, nats.high / LN2),
                                                  rel=1e-9, abs=1e-12)


def _quantile_interval(res, interval: str) -> tuple[float, float]:
    q_lo, q_hi = np.quantile(res.bootstrap_distribution, [0.025, 0.975], method="weibull")
    if interval == "basic":
        return 2.0 * res.estimate - q_hi, 2.0 * res.estimate - q_lo
    return q_lo, q_hi


@pytest.mark.parametrize("interval", ["percentile", "basic"])
def test_block_quantiles_are_not_narrowed_where_the_floor_is_below_the_spread(
        interval: str) -> None:
    # iid rows, rho = 0.3, n = 400: Bartlett's |r| / sqrt(n - 3) ~ 0.015 nats, while the
    # block replicates of the Gaussian MI spread ~0.03 (asserted below)
    rng = np.random.default_rng(3535)
    x = rng.standard_normal(400)
    y = 0.3 * x + math.sqrt(1 - 0.09) * rng.standard_normal(400)
    res = mutual_information_ci(x, y, method="gaussian", n_resamples=99, seed=5,
                                interval=interval, bootstrap="block")
    r = abs(float(np.corrcoef(stats.norm.ppf(stats.rankdata(x) / 401),
                              stats.norm.ppf(stats.rankdata(y) / 401))[0, 1]))
    assert r / math.sqrt(400 - 3) < np.std(res.bootstrap_distribution, ddof=1)
    assert (res.low, res.high) == pytest.approx(_quantile_interval(res, interval), abs=1e-12)


@pytest.mark.parametrize("interval", ["percentile", "basic"])
def test_iid_bootstrap_quantiles_take_no_floor(interval: str) -> None:
    x, y = _ar_pair(0.97, 0.6, 500, 52602)
    res = _quiet(mutual_information_ci, x, y, method="gaussian", n_resamples=99, seed=2,
                 interval=interval, bootstrap="iid")
    assert (res.low, res.high) == pytest.approx(_quantile_interval(res, interval), abs=1e-12)


def test_gaussian_cmi_of_discrete_columns_keeps_the_normal_interval() -> None:
    # three binary columns, y a noisy copy of x: the table's CMI, not a partial correlation
    rng = np.random.default_rng(35)
    z = rng.integers(0, 2, 2000).astype(float)
    x = (rng.random(2000) < 0.3 + 0.4 * z).astype(float)
    y = np.where(rng.random(2000) < 0.8, x, 1.0 - x)
    res = _quiet(conditional_mutual_information_ci, x[:, None], y[:, None], z[:, None],
                 method="gaussian", n_resamples=49, seed=3)
    assert res.interval == "normal"
    # the normal interval is symmetric about the estimate (Fisher's is not)
    assert res.high - res.estimate == pytest.approx(res.estimate - res.low, abs=1e-12)


def test_one_x_column_and_two_y_columns_keep_the_bootstrap_spread() -> None:
    """The floor needs one x and one y column (a partial correlation); y of two: none."""
    x, y, z = _ar_triple(0.97, 500, 2, 0.5, 52508)
    y2 = np.column_stack([y[:, 0], z[:, 1] + np.random.default_rng(8).standard_normal(500)])
    res = _quiet(conditional_mutual_information_ci, x, y2, z[:, :1], method="gaussian",
                 n_resamples=49, seed=8)
    half = stats.norm.ppf(0.975) * float(np.std(res.bootstrap_distribution, ddof=1))
    assert res.interval == "normal"
    assert (res.low, res.high) == pytest.approx((res.estimate - half, res.estimate + half),
                                                abs=1e-12)
