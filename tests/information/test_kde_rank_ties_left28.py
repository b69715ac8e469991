"""The kde rank-resolution rule counts distinct values (issue 27, left28-misc; review 21 K2).

References, outside the code: ``numpy.unique`` counts; ln d, the entropy of a rank
uniform on the d distinct values of a tied variable (tied values share one rank), the
most its ranks resolve; and the exact MI of a standard Gaussian pair at rho with x
rounded to ``delta`` (``_exact_rounded``: ``H(X_d) - H(X_d | Y)`` by quadrature over y,
``P(X_d = k | y)`` from ``scipy.special.ndtr``; at rho = 0.999999 it is 6.541 for delta
= 1e-3 and 5.769 for 1e-2, against 6.561 unrounded). Before, any repeated value
exempted the pair, so x rounded to 1e-3 (about 1530 distinct of 2000) read 6.1-6.3
with no word while past ln d - 2 = 5.33. Measured (5 seeds per cell, n = 500 / 2000 /
1e4, rho 0.9 .. 1 - 1e-8, x rounded to 1e-4 .. 0.1): the rule never fires at rho <=
0.999; it fires where d >= n / 2 and the estimate passes ln d - 2.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.special import ndtr, xlogy

from modalinfo.information import BiasRuleWarning, mutual_information

N = 2000
EXACT_1E_3 = 6.541  # rho = 0.999999, x (or y) rounded to 1e-3 (test_the_quadrature_reference)


def _exact_rounded(rho: float, delta: float) -> float:
    """MI (nats) of (round(x / delta) delta, y), standard Gaussian pair at rho."""
    s = math.sqrt(1.0 - rho * rho)
    k = np.arange(-int(9 / delta) - 1, int(9 / delta) + 2)
    pk = ndtr((k + 0.5) * delta) - ndtr((k - 0.5) * delta)
    step = min(delta, s) / 20
    y = np.arange(-8.5, 8.5 + step, step)
    w = np.exp(-0.5 * y * y) / math.sqrt(2 * math.pi) * step
    nb = int(math.ceil(12 * s / delta)) + 3
    c = np.floor(rho * y / delta + 0.5).astype(int)
    kk = c[:, None] + np.arange(-nb, nb + 1)[None, :]
    q = np.clip(ndtr(((kk + 0.5) * delta - rho * y[:, None]) / s)
                - ndtr(((kk - 0.5) * delta - rho * y[:, None]) / s), 0.0, None)
    return float(-np.sum(xlogy(pk, pk)) + np.sum(w * np.sum(xlogy(q, q), axis=1)))


def _pair(rho: float, seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(N)
    return x, rho * x + math.sqrt(1.0 - rho * rho) * rng.standard_normal(N)


def _rank_warnings(x, y) -> tuple[float, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method="kde")
    return value, [str(w.message) for w in caught
                   if issubclass(w.category, BiasRuleWarning) and "ranks of n" in str(w.message)]


def test_the_quadrature_reference():
    # unrounded limit and the saturation at H(X_d) (a check of the reference itself)
    assert _exact_rounded(0.999, 1e-2) == pytest.approx(-0.5 * math.log1p(-0.999**2), abs=3e-3)
    assert _exact_rounded(0.999999, 1e-3) == pytest.approx(EXACT_1E_3, abs=1e-3)


@pytest.mark.parametrize("side", ["x", "y"])
def test_one_variable_rounded_to_1e_3_is_judged_by_its_distinct_values(side):
    x, y = _pair(0.999999)
    if side == "x":
        x = np.round(x, 3)
    else:
        y = np.round(y, 3)
    d = min(np.unique(x).size, np.unique(y).size)
    assert N / 2 <= d < N
    value, got = _rank_warnings(x, y)
    assert value > math.log(d) - 2.0
    assert len(got) == 1, got
    assert f"ln {d} = {math.log(d):.3f}" in got[0] and f"`{side}` takes {d}" in got[0]
    assert "copula=False" in got[0]
    assert value < EXACT_1E_3  # low against the rounded pair's exact MI (5 of 5 seeds)


@pytest.mark.parametrize("rho", [0.9, 0.999])
def test_rounded_pairs_below_are_silent(rho):
    x, y = _pair(rho)
    x = np.round(x, 3)
    value, got = _rank_warnings(x, y)
    assert got == []
    # rounding to 1e-3 << the noise sd sqrt(1 - rho^2) >= 0.045 moves the exact MI by
    # under 1e-4 nats (Sheppard: delta^2 / 12 added to the noise variance)
    exact = -0.5 * math.log1p(-rho * rho)
    assert abs(value - exact) < max(0.05, 0.1 * exact)


def test_discrete_table_is_not_judged_by_the_ranks():
    rng = np.random.default_rng(3)
    x = rng.integers(0, 8, N).astype(float)  # 8 levels: the table path (64 cells <= n / 10)
    value, got = _rank_warnings(x, x.copy())
    assert value == pytest.approx(math.log(8), abs=0.01)  # H of 8 equiprobable levels
    assert got == []
