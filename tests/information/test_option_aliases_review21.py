"""Review 21: every documented alias of ``OPTION_ALIASES`` names the parameter meant.

Reference, outside the code under test: ``inspect.signature`` of the public function
called (the keyword given is not one of its parameters, the keyword named is), and the
same call with the keyword named, which must then run (a round trip through the advice).
Round 28's file covers ``level``, ``n_permutations`` / ``n_surrogates``, ``rng``,
``lag`` / ``lags``; here the other aliases its table documents.
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from modalinfo.information import mutual_information_ci

RNG = np.random.default_rng(21)
X = RNG.standard_normal(300)
Y = 0.6 * X + 0.8 * RNG.standard_normal(300)


@pytest.mark.parametrize(("given", "meant", "value"), [
    ("random_state", "seed", 1),
    ("confidence", "confidence_level", 0.9),
    ("n_bootstrap", "n_resamples", 19),
])
def test_ci_alias_refusal_names_the_parameter_meant(given, meant, value):
    params = inspect.signature(mutual_information_ci).parameters
    assert meant in params and given not in params
    extra = {} if meant == "n_resamples" else {"n_resamples": 19}
    with pytest.raises(TypeError) as info:
        mutual_information_ci(X, Y, **{given: value}, **extra)
    message = str(info.value)
    assert f"`{given}` is not an estimator option" in message and f"`{meant}`" in message
    mutual_information_ci(X, Y, **{meant: value}, **extra)
