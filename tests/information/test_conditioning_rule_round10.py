"""The histogram's conditioning rule: a persistent target's own past (round 10 PART a).

Reference: the analytic transfer entropy of the Gaussian process
``y[t] = a y[t-1] + b x[t-1] + s e[t]`` with white x, e: given y[t-1], y[t] has variance
``b^2 + s^2`` without x[t-1] and ``s^2`` with it, so TE = 0.5 ln((b^2 + s^2) / s^2)
(0.347 nats at b = s = 0.5). The histogram TE (the default until left25-api) was 33 %
low at a = 0.95 (57 % at 0.99) without a word; at a = 0 it is within its documented
10-bin loss.
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    transfer_entropy,
    transfer_entropy_variables,
)

B = S = 0.5
TRUE_TE = 0.5 * np.log((B * B + S * S) / (S * S))


def _series(a: float, n: int = 5000, seed: int = 3):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    e = S * rng.standard_normal(n)
    y = np.zeros(n)
    for t in range(1, n):
        y[t] = a * y[t - 1] + B * x[t - 1] + e[t]
    return x, y


def test_persistent_target_warns_and_names_the_rule():
    x, y = _series(0.95)
    with pytest.warns(BiasRuleWarning, match=r"conditioning column.*beyond the rule of 10%"):
        te = transfer_entropy(x, y, method="histogram")
    assert te < 0.8 * TRUE_TE  # the warning is about a real loss


def test_white_target_is_not_judged():
    x, y = _series(0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        te = transfer_entropy(x, y, method="histogram")
    assert abs(te - TRUE_TE) < 0.15 * TRUE_TE


def test_raise_refuses():
    x, y = _series(0.95)
    with pytest.raises(ValueError, match="fallback='raise'"):
        transfer_entropy(x, y, method="histogram", fallback="raise")


def test_cmi_point_estimate_switches_to_ksg_and_is_right():
    x, y = _series(0.95)
    with pytest.warns(BiasRuleWarning, match="KSG CMI instead"):
        cmi = conditional_mutual_information(*transfer_entropy_variables(x, y),
                                             method="histogram")
    assert abs(cmi - TRUE_TE) < 0.1 * TRUE_TE
