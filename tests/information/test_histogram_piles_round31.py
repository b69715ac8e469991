"""Quantile bins keep a pile of one value apart from the values above it (round 31 PART a).

References, from outside the code: the exact MI of a discrete flag B and a mode
Y = mu_B + N(0, 1) is ``h(Y) - h(Y | B)``, with ``h(Y)`` of the Gaussian mixture by
``scipy.integrate.quad`` and ``h(Y | B) = 0.5 ln(2 pi e)``; a conditional MI that is 0
by construction (x and y independent given a rare flag z that moves both); and
``numpy.searchsorted(edges, v, "right")`` for the bin of a value against edges.

Before the fix a binary flag set in 2 % of the frames fell in the bin of its 0's
whenever every inner quantile edge was 0: the histogram MI of a flag moving a mode by
3 sd read exactly 0.000 nats for the exact 0.065 (no warning), a 3-level flag with a
2 % top level lost 10-15 %, and the histogram CMI given a 3 % flag kept half of the
unconditional MI.
"""

import warnings

import numpy as np
import pytest
from scipy import integrate, stats

from modalinfo.information import _kernels as kern
from modalinfo.information import conditional_mutual_information, mutual_information


def _mixture_mi(w, mus) -> float:
    """Exact I(B; Y) for Y = mu_B + N(0, 1), P(B = i) = w[i] (quadrature)."""
    w, mus = np.asarray(w, float), np.asarray(mus, float)

    def p(t):
        return float(np.sum(w * stats.norm.pdf(t, mus, 1.0)))

    hy = -integrate.quad(lambda t: p(t) * np.log(p(t)), mus.min() - 12, mus.max() + 12,
                         limit=400, points=list(mus))[0]
    return hy - 0.5 * np.log(2 * np.pi * np.e)


def test_split_tied_edges_against_searchsorted():
    inner = np.array([0.0, 0.0, 0.0, 1.0, 2.0, 2.0])
    split = inner.copy()
    kern.split_tied_edges(split)
    # untied edges and all but the last of each tied run unchanged
    assert list(split[[0, 1, 3, 4]]) == [0.0, 0.0, 1.0, 2.0]
    assert split[2] == np.nextafter(0.0, 1.0) and split[5] == np.nextafter(2.0, 3.0)
    values = np.array([0.0, 1e-300, 0.5, 1.0, 2.0, 2.5])
    bins = np.searchsorted(split, values, side="right")
    # the pile at 0 alone in its bin, the values above it in others
    assert bins[0] != bins[1] and bins[0] == 2
    assert len(set(np.searchsorted(split, values[[0, 4]], side="right"))) == 2


@pytest.mark.parametrize("n", [2000, 10000])
def test_rare_binary_flag(n):
    rng = np.random.default_rng(31 + n)
    b = (rng.random(n) < 0.02).astype(float)
    y = 3.0 * b + rng.standard_normal(n)
    truth = _mixture_mi([0.98, 0.02], [0.0, 3.0])  # 0.0650 nats
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        value = mutual_information(b, y, method="histogram")
    # before: 0.000 at both n (no warning). After: 0.047-0.049, the quantile bins'
    # discretisation of the continuous mode (uniform bins give 0.062); within 0.03 nats
    assert abs(value - truth) < 0.03


@pytest.mark.parametrize("n", [2000, 10000])
def test_three_levels_rare_top(n):
    rng = np.random.default_rng(7 + n)
    level = rng.choice(3, n, p=[0.49, 0.49, 0.02]).astype(float)
    y = 3.0 * level + rng.standard_normal(n)
    truth = _mixture_mi([0.49, 0.49, 0.02], [0.0, 3.0, 6.0])  # 0.588 nats
    value = mutual_information(level, y, method="histogram")
    # before: 0.502 (n = 2000) and 0.529 (1e4), 10-15 % low
    assert truth - value < 0.1 * truth * (0.6 if n == 10000 else 1.0)


def test_same_levels_apart_unchanged():
    """A balanced flag's levels were already apart: the same table, the same value."""
    rng = np.random.default_rng(5)
    n = 4000
    b = rng.integers(0, 2, n).astype(float)
    y = 2.0 * b - 1.0 + rng.standard_normal(n)
    coded = np.where(b > 0, 7.0, -3.0)  # a monotone relabelling: quantile bins rank-only
    assert mutual_information(b, y, method="histogram") == mutual_information(
        coded, y, method="histogram")
    truth = _mixture_mi([0.5, 0.5], [-1.0, 1.0])
    assert abs(mutual_information(b, y, method="histogram") - truth) < 0.05


def test_cmi_given_rare_flag():
    rng = np.random.default_rng(7)
    n = 10000
    z = (rng.random(n) < 0.03).astype(float)
    x = 4.0 * z + rng.standard_normal(n)
    y = 4.0 * z + rng.standard_normal(n)
    # x and y independent given z: I(x; y | z) = 0 (before: 0.022, half of I(x; y))
    value = conditional_mutual_information(x, y, z, method="histogram")
    assert abs(value) < 0.01


def _rho_given_flag(n: int, seed: int = 31):
    """x, y Gaussian with rho 0.9 where a balanced binary z is 1, independent where 0."""
    rng = np.random.default_rng(seed)
    z = rng.integers(0, 2, n).astype(float)
    rho = np.where(z > 0, 0.9, 0.0)
    x = rng.standard_normal(n)
    y = rho * x + np.sqrt(1.0 - rho ** 2) * rng.standard_normal(n)
    return x, y, z


def test_cmi_given_a_discrete_column_below_the_resolution_rule_warns():
    from modalinfo.information import BiasRuleWarning

    truth = 0.5 * (-0.5 * np.log(1.0 - 0.81))  # 0.415 nats: the strata's mean Gaussian MI
    x, y, z = _rho_given_flag(2000)
    # 7 bins per axis (< 8): before, 0.347 (-16 %) returned with no warning, the KSG
    # switch being skipped for the discrete z
    with pytest.warns(BiasRuleWarning, match="a discrete column keeps the histogram"):
        value = conditional_mutual_information(x, y, z, method="histogram")
    assert truth - value > 0.05  # the loss the warning names
    with pytest.raises(ValueError, match="resolution rule"):
        conditional_mutual_information(x, y, z, method="histogram", fallback="raise")
    # the default estimator (ksg) is untouched: within its stated 0.05 nats, no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert abs(conditional_mutual_information(x, y, z) - truth) < 0.05
        # 9 bins per axis at n = 1e4: the rule holds, nothing said
        conditional_mutual_information(*_rho_given_flag(10000), method="histogram")
