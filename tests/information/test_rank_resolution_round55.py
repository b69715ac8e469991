"""The ranks' resolution of the rank-based MI / CMI / TE (round 55 PART a, issue 27).

References (exact, from outside the code): for x, y independent N(0, 1) and e N(0, 1),
I(x; x + s e) = 0.5 ln(1 + 1 / s^2) and I(x; x + y + s e | y) = 0.5 ln(1 + 1 / s^2)
(Cover & Thomas 2006, eq. 9.16 with the Gaussian channel's SNR); the transfer entropy of
y_t = x_(t-1) + s e_t from a white x is the same. At s = 1e-3 (6.91 nats) and n = 2,000
the normal-score estimates read 6.09 (ksg) and 6.28 (gaussian) for the MI and 2.9-3.5
for the CMI and the KSG transfer entropy, without a word before round 55; now each says
that the ranks cap it (``copula.rank_resolution_why``, ``copula.cmi_rank_resolution_why``).
Where the estimates are right (exact 1-2.3 nats) nothing is said, and the values'
estimator (``copula=False``) is not judged by the ranks' rule.
"""

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    mutual_information,
    transfer_entropy,
)

N = 2000


def _pair(s: float, seed: int = 55000) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(N)
    return x, x + s * rng.standard_normal(N)


def _triple(s: float, seed: int = 55110) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x, y = rng.standard_normal((2, N))
    return x, x + y + s * rng.standard_normal(N), y


def _exact(s: float) -> float:
    return 0.5 * math.log1p(s ** -2)


@pytest.mark.parametrize("method", ["ksg", "gaussian"])
def test_mi_near_copy_is_warned_as_capped_by_the_ranks(method):
    x, y = _pair(1e-3)
    with pytest.warns(BiasRuleWarning, match=r"within 2 nats of ln n"):
        value = mutual_information(x, y, method=method)
    assert value < 0.93 * _exact(1e-3)  # 6.07-6.41 for 6.91: the case the rule is for


@pytest.mark.parametrize("method", ["ksg", "gaussian", "kde"])
def test_mi_at_snr_100_stays_silent(method):
    x, y = _pair(0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = mutual_information(x, y, method=method)
    assert abs(value - _exact(0.1)) < 0.1 * _exact(0.1)


@pytest.mark.parametrize("method", ["ksg", "gaussian", "kde"])
def test_cmi_through_the_conditioning_is_warned_as_capped(method):
    x, z, y = _triple(1e-3)
    with pytest.warns(BiasRuleWarning, match=r"0\.5 ln n - 1\.5"):
        value = conditional_mutual_information(x, z, y, method=method)
    assert value < 0.6 * _exact(1e-3)  # 2.9-3.5 for 6.91


def test_histogram_cmi_switch_says_the_cap_too():
    x, z, y = _triple(1e-3)
    with pytest.warns(BiasRuleWarning) as record:
        conditional_mutual_information(x, z, y, method="histogram")
    text = " ".join(str(w.message) for w in record)
    assert "returning the KSG CMI instead" in text and "0.5 ln n - 1.5" in text


def test_ksg_transfer_entropy_of_a_near_delayed_copy_is_warned():
    rng = np.random.default_rng(55120)
    x = rng.standard_normal(N + 1)
    target = x[:-1] + 1e-3 * rng.standard_normal(N)
    with pytest.warns(BiasRuleWarning, match=r"0\.5 ln n - 1\.5"):
        value = transfer_entropy(x[1:], target, lag=1, method="ksg")
    assert value < 0.6 * _exact(1e-3)


@pytest.mark.parametrize("method", ["ksg", "gaussian", "kde"])
def test_cmi_of_one_nat_stays_silent(method):
    s = 1.0 / math.sqrt(math.expm1(2.0))  # exact 1 nat
    x, z, y = _triple(s)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = conditional_mutual_information(x, z, y, method=method)
    assert abs(value - 1.0) < 0.1


def test_values_estimator_is_not_judged_by_the_ranks():
    x, z, y = _triple(1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = conditional_mutual_information(x, z, y, method="gaussian", copula=False)
    assert abs(value - _exact(1e-3)) < 0.1
