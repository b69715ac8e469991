"""The rank-resolution rules' lines, units and scope (mutation round 38, issue 27).

References (from outside the code): the lines of ``copula.rank_resolution_why`` as its
docstring states them, max(ln n - 2, 0.5 ln n) nats for the KSG and the Gaussian copula
and ln n - 2 for the kde (its measured line kept at small n), and ln d for a variable
with d >= n / 2 distinct values (d counted by ``numpy.unique``); the line of
``copula.cmi_rank_resolution_why``, 0.5 ln n - 1.5 nats; the exact MI of y = x + s e,
0.5 ln(1 + 1 / s^2) (Cover & Thomas 2006, eq. 9.16) and of the CMI of z = x + y + s e
given y, the same; the units' factor 1 / ln 2 nats -> bits. The samples are fixed
(seeds chosen so that the estimate falls between the two lines each test tells apart);
each test names the plant of docs/MUTATION.md's round 38 it fails with.
"""

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    mutual_information,
)

N = 2000


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return fn(*args, **kwargs)


def _pair(n: int, s: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, x + s * rng.standard_normal(n)


def _triple(s: float, seed: int = 55110) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x, y = rng.standard_normal((2, N))
    return x, x + y + s * rng.standard_normal(N), y


def test_gaussian_copula_at_n_20_keeps_the_half_log_floor():
    """R38-CO4 / R38-AP3: 1.36 nats at n = 20 is above ln 20 - 2 = 1.00, not 0.5 ln 20."""
    x, y = _pair(20, 0.32, seed=0)
    value = _quiet(mutual_information, x, y, method="gaussian")
    assert math.log(20) - 2.0 < value <= 0.5 * math.log(20)  # between the two lines


def test_kde_at_n_30_keeps_its_measured_line():
    """R38-KD1: the kde's line is ln n - 2 = 1.40 at n = 30, not 0.5 ln 30 = 1.70."""
    x, y = _pair(30, 0.25, seed=3)
    with pytest.warns(BiasRuleWarning, match=r"within 2 nats of ln n") as record:
        value = mutual_information(x, y, method="kde")
    assert math.log(30) - 2.0 < value <= 0.5 * math.log(30)
    assert len(record) == 1


def test_tied_variable_is_judged_against_ln_of_its_distinct_values():
    """R38-CO10: x rounded to 1e-3 (d distinct, n / 2 <= d < n): the cap is ln d."""
    rng = np.random.default_rng(38)
    x = np.round(rng.standard_normal(N), 3)
    y = x + 1e-6 * rng.standard_normal(N)
    d = np.unique(x).size
    assert N // 2 <= d < N
    with pytest.warns(BiasRuleWarning) as record:
        mutual_information(x, y, method="kde")
    text = " ".join(str(w.message) for w in record)
    assert f"ln {d} = {math.log(d):.3f}" in text


def test_mi_in_bits_is_judged_in_nats():
    """R38-AP1: 4.4 nats (6.3 bits) at n = 2000 is below ln n - 2 = 5.6 nats: silent."""
    x, y = _pair(N, math.exp(-4.5), seed=1)
    nats = _quiet(mutual_information, x, y, method="gaussian")
    bits = _quiet(mutual_information, x, y, method="gaussian", units="bits")
    assert nats < math.log(N) - 2.0 < bits
    assert bits == pytest.approx(nats / math.log(2), rel=1e-12)


def test_gaussian_on_values_is_not_judged_by_the_ranks():
    """R38-AP2: copula=False reads the near copy on its values, exact and silent."""
    x, y = _pair(N, 1e-3, seed=2)
    value = _quiet(mutual_information, x, y, method="gaussian", copula=False)
    exact = 0.5 * math.log1p(np.var(x) / np.var(y - x))  # the sample's own SNR
    assert value == pytest.approx(exact, abs=0.05)


@pytest.mark.parametrize("method", ["gaussian", "ksg", "kde"])
def test_cmi_in_bits_is_judged_in_nats(method):
    """R38-CD6: exact 2 nats (about 2.8 bits) is below 0.5 ln n - 1.5 = 2.30 nats."""
    x, z, y = _triple(1.0 / math.sqrt(math.expm1(4.0)))
    nats = _quiet(conditional_mutual_information, x, z, y, method=method)
    bits = _quiet(conditional_mutual_information, x, z, y, method=method, units="bits")
    assert nats < 0.5 * math.log(N) - 1.5 < bits
    assert bits == pytest.approx(nats / math.log(2), rel=1e-12)


def test_histogram_switch_returns_the_ksg_in_the_asked_units():
    """R38-CD5: the fallback's KSG CMI comes back in bits when bits were asked."""
    x, z, y = _triple(1e-3)
    with pytest.warns(BiasRuleWarning, match="returning the KSG CMI instead"):
        nats = conditional_mutual_information(x, z, y, method="histogram")
    with pytest.warns(BiasRuleWarning, match="returning the KSG CMI instead"):
        bits = conditional_mutual_information(x, z, y, method="histogram", units="bits")
    assert bits == pytest.approx(nats / math.log(2), rel=1e-12)


def test_one_warning_when_the_ties_rule_spoke_first():
    """R38-CD4: x on 8 levels: the ties rule warns; the rank line is not said on top."""
    rng = np.random.default_rng(38)
    x, y = rng.standard_normal((2, N))
    x = np.round(x)  # 8 levels: a discrete side (at most n / 20 distinct values)
    z = x + y + 1e-3 * rng.standard_normal(N)
    assert np.unique(x).size <= N // 20
    with pytest.warns(BiasRuleWarning) as record:
        value = conditional_mutual_information(x, z, y, method="gaussian")
    assert value >= 0.5 * math.log(N) - 1.5  # the rank line would fire on its own
    texts = [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)]
    assert len(texts) == 1 and "discrete column(s)" in texts[0]
