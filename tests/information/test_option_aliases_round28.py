"""A keyword meant for the function, under another function's name, is refused naming it.

Adversarial round 28 PART a, issue 27 (rows A01-A04, A08-A10, A12, A13). The
package names one concept two ways: the confidence level is ``level`` in the
forecasting API and ``confidence_level`` in the MI intervals; the null draws are
``n_permutations`` in ``mutual_information_permutation_test`` and ``n_surrogates`` in
the conditional tests, ``select_inputs`` and ``transfer_entropy_map``; the lags are
``lag`` / ``lags``. A user who passes the other name sees it land in the estimator's
``**options`` and was told "method='histogram' does not accept option(s) level;
allowed: bins, ...", which blames the estimator. The refusal must name the parameter
meant.

Reference, outside the code under test: ``inspect.signature`` of the public function
called (the parameter the message names must be one of its keywords), and the same
call with that keyword, which must then run (a round trip through the advice).
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from modalinfo.information import (
    conditional_mutual_information_ci,
    conditional_mutual_information_test,
    mutual_information,
    mutual_information_ci,
    mutual_information_permutation_test,
    select_inputs,
    transfer_entropy,
    transfer_entropy_map,
)

RNG = np.random.default_rng(28)
X = RNG.standard_normal(300)
Y = 0.6 * X + 0.8 * RNG.standard_normal(300)
Z = RNG.standard_normal(300)
DATA = np.column_stack([X, Y])

# (function, positional arguments, keyword given, keyword meant, its value)
CASES = [
    (mutual_information_ci, (X, Y), "level", "confidence_level", 0.9),
    (conditional_mutual_information_ci, (X, Y, Z), "level", "confidence_level", 0.9),
    (mutual_information_permutation_test, (X, Y), "n_surrogates", "n_permutations", 19),
    (conditional_mutual_information_test, (X, Y, Z), "n_permutations", "n_surrogates", 19),
    (transfer_entropy_map, (DATA,), "n_permutations", "n_surrogates", 19),
    (select_inputs, (DATA, 0), "n_permutations", "n_surrogates", 19),
    (mutual_information_ci, (X, Y), "rng", "seed", 1),
    (transfer_entropy, (X, Y), "lags", "lag", 2),
    (transfer_entropy_map, (DATA,), "lag", "lags", 2),
]

SMALL = {mutual_information_ci: {"n_resamples": 19},
         conditional_mutual_information_ci: {"n_resamples": 19, "method": "gaussian"},
         select_inputs: {"intervals": False, "max_inputs": 1, "max_lag": 2},
         transfer_entropy_map: {"max_seconds": 60.0}}


@pytest.mark.parametrize(("fn", "args", "given", "meant", "value"), CASES,
                         ids=[f"{c[0].__name__}-{c[2]}" for c in CASES])
def test_refusal_names_the_parameter_meant(fn, args, given, meant, value):
    assert meant in inspect.signature(fn).parameters
    assert given not in inspect.signature(fn).parameters
    extra = dict(SMALL.get(fn, {}))
    if fn is transfer_entropy_map and given == "lag":
        extra["n_surrogates"] = 19
    with pytest.raises(TypeError) as info:
        fn(*args, **{given: value}, **extra)
    message = str(info.value)
    assert "\n" not in message
    assert f"`{given}` is not an estimator option" in message
    assert f"`{meant}`" in message
    # the advice followed: the same call with the keyword meant runs
    fn(*args, **{meant: value}, **extra)


def test_unrelated_unknown_option_keeps_its_message():
    with pytest.raises(TypeError) as info:
        mutual_information(X, Y, "histogram", bogus=1)
    assert str(info.value) == ("method='histogram' does not accept option(s) bogus; "
                               "allowed: bins, bias_correction, binning.")
