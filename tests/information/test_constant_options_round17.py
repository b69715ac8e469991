"""Option values are checked even where a constant input answers without an estimate.

Adversarial round 17 (PART a, rows w-te-k0 .. w-h-nonsense): ``transfer_entropy`` and
``conditional_mutual_information`` with a constant x or y returned 0.0, and ``entropy``
of a constant returned ``-inf``, before the estimator had looked at its options, so
``k=0``, ``k=-3``, ``bandwidth=-1``, ``bins=0`` or an unknown option name were accepted.

Reference: the documented contract, read against the same call on a non-constant
sample (which is refused): ``mutual_information`` documents "ValueError ... if
``method``, ``units`` or an option is invalid" and refuses these values on any input;
the answer on a constant (0.0 nats; ``-inf`` for the entropy, its documented value)
must come with the same refusal of an invalid option, and stay unchanged for a valid one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information, entropy, transfer_entropy

CONST = np.ones(60)
RAMP = np.arange(60.0)
WAVE = np.sin(np.arange(60.0))

BAD = [
    ({"method": "ksg", "k": 0}, ValueError, "`k`"),
    ({"method": "ksg", "k": -3}, ValueError, "`k`"),
    ({"method": "ksg", "k": "x"}, TypeError, "`k`"),
    ({"method": "kde", "bandwidth": -1.0}, ValueError, "`bandwidth`"),
    ({"method": "histogram", "bins": 0}, ValueError, "`bins`"),
]


@pytest.mark.parametrize(("options", "error", "name"), BAD)
def test_transfer_entropy_of_constants_checks_options(options, error, name):
    with pytest.raises(error, match=name):
        transfer_entropy(CONST, CONST, **options)


@pytest.mark.parametrize(("options", "error", "name"), BAD)
def test_cmi_with_a_constant_checks_options(options, error, name):
    with pytest.raises(error, match=name):
        conditional_mutual_information(CONST, RAMP, WAVE, **options)
    with pytest.raises(error, match=name):
        conditional_mutual_information(RAMP, CONST, **options)


@pytest.mark.parametrize(("options", "error", "name"), BAD)
def test_entropy_of_a_constant_checks_options(options, error, name):
    with pytest.raises(error, match=name):
        entropy(CONST, **options)


def test_entropy_of_a_constant_refuses_an_unknown_option():
    with pytest.raises(TypeError, match="nonsense"):
        entropy(CONST, method="ksg", nonsense=1)


@pytest.mark.parametrize("method", ["ksg", "kde", "histogram", "gaussian"])
def test_valid_options_keep_the_documented_answers(method):
    assert transfer_entropy(CONST, CONST, method=method) == 0.0
    assert conditional_mutual_information(CONST, RAMP, WAVE, method=method) == 0.0
    assert entropy(CONST, method=method) == -math.inf
