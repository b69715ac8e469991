"""Transfer entropy (``modalinfo.information.transfer_entropy``) on deterministic and
discrete dynamics (audit 9, issue 27).

References, from outside the code under test:

- a leaky integrator ``x[t] = 0.9 x[t-1] + 0.5 s[t-1]`` (a linear controller's output
  and its input) makes x[t] an affine function of (s[t-1], x[t-1]): the conditional law
  is a point, the TE from s to x is infinite (Cover & Thomas 2006, sec. 8.5), so every
  method must refuse it (they returned 0.09-1.2 nats); the TE from x to s (s white,
  independent of the past) is 0;
- with a noise of sd e added, the Gaussian TE is ``0.5 ln(1 + 0.25 / e^2)`` (the log
  ratio of the residual variances), finite and returned;
- the binary symmetric channel ``y[t] = b[t-1] XOR flip`` (fair bits, flip probability
  0.1): ``TE = ln 2 - H(0.1) = 0.368`` nats, and for the exact binary delayed copy the
  TE is the entropy of a fair bit, ln 2 (finite: discrete); kde gave 0.958 and 17.6.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import transfer_entropy
from modalinfo.information.api import BiasRuleWarning, InfiniteMIError

METHODS = ("gaussian", "histogram", "kde", "ksg")


def _te(*args, method, **kwargs):
    """``transfer_entropy``; the histogram's at n = 2000, history 1 (7 bins per axis over
    3 columns) warns its resolution rule since fixes 45-c (round 44 PART a I32)."""
    if method != "histogram":
        return transfer_entropy(*args, method=method, **kwargs)
    with pytest.warns(BiasRuleWarning, match="7 bins per axis over 3 columns"):
        return transfer_entropy(*args, method=method, **kwargs)


def _integrator(n=2000, noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    s = rng.standard_normal(n)
    e = noise * rng.standard_normal(n)
    x = np.zeros(n)
    for t in range(1, n):
        x[t] = 0.9 * x[t - 1] + 0.5 * s[t - 1] + e[t]
    return s, x


@pytest.mark.parametrize("method", METHODS)
def test_te_of_a_linear_controller_is_refused(method):
    s, x = _integrator()
    with pytest.raises(InfiniteMIError, match=r"1 sample\(s\) earlier are affinely related"):
        transfer_entropy(s, x, method=method)
    assert abs(_te(x, s, method=method)) < 0.05  # s is white


def test_te_of_a_noisy_controller_is_its_finite_gaussian_value():
    s, x = _integrator(noise=1e-4)
    exact = 0.5 * math.log(1 + 0.25 / 1e-8)  # 8.51 nats
    assert transfer_entropy(s, x, method="gaussian", copula=False) == pytest.approx(
        exact, abs=0.1)


def _channel(n=2000):
    b = np.random.default_rng(5).integers(0, 2, n)
    flip = (np.random.default_rng(6).random(n) < 0.1).astype(int)
    return b.astype(float), np.r_[0, b[:-1] ^ flip[1:]].astype(float)


@pytest.mark.parametrize("method", ["histogram", "kde", "ksg", "gaussian"])
def test_te_of_a_binary_channel_and_copy(method):
    b, y = _channel()
    h01 = -(0.1 * math.log(0.1) + 0.9 * math.log(0.9))
    assert transfer_entropy(b, y, method=method) == pytest.approx(math.log(2) - h01,
                                                                   abs=0.04)
    copy = np.r_[0.0, b[:-1]]
    assert transfer_entropy(b, copy, method=method) == pytest.approx(math.log(2), abs=0.02)


def test_gaussian_te_of_a_discrete_copy_is_refused_not_17_nats():
    # 60 levels: too many cells for the table rule (gaussian gives a binary copy its
    # table's ln 2 above), so the normal model's infinite partial correlation is refused
    b = np.random.default_rng(5).integers(0, 60, 2000).astype(float)
    with pytest.raises(ValueError, match="partial correlation is \\+-1"):
        transfer_entropy(b, np.r_[0.0, b[:-1]], method="gaussian")


@pytest.mark.parametrize("scale", [1e300, 1e-300])
def test_affine_rule_and_estimates_are_scale_free(scale):
    """TE is unchanged by a change of units; the affine screen once overflowed at 1e300
    (squares of 1e300) and refused a plain coupled pair."""
    rng = np.random.default_rng(1)
    x = rng.standard_normal(2000)
    y = np.r_[0.0, 0.8 * x[:-1]] + 0.6 * rng.standard_normal(2000)
    for method in METHODS:
        assert _te(x * scale, y * scale, method=method) == pytest.approx(
            _te(x, y, method=method), abs=1e-9)
    s, xi = _integrator()
    with pytest.raises(InfiniteMIError):
        transfer_entropy(s * scale, xi * scale)


@pytest.mark.parametrize("method", METHODS)
def test_te_to_a_target_that_holds_the_source_is_refused(method):
    """y = 0.8 x[t-1] + 0.6 n[t]: the 2-column target (y, n) gives x[t-1] exactly, an
    infinite TE (the Gaussian one came out 3.1 nats); with y alone it is finite,
    0.5 ln(1 + 0.8^2 / 0.6^2) = 0.511."""
    rng = np.random.default_rng(1)
    x, n = rng.standard_normal((2, 2000))
    y = np.r_[0.0, 0.8 * x[:-1]] + 0.6 * n
    with pytest.raises(InfiniteMIError):
        transfer_entropy(x, np.c_[y, n], method=method)
    assert _te(x, y, method=method) == pytest.approx(
        0.5 * math.log(1 + 0.64 / 0.36), abs=0.07)
