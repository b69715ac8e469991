"""The deprecated ``p_value`` alias obeys Python's warning filters (left24-status, W14).

Adversarial round 24 PART a, W14: ``ForecastEvaluation.p_value`` warned once per process
through the package's own set, so a caller's later ``warnings.simplefilter("error")`` or
``"always"`` saw nothing. Reference, outside the code: the documented behaviour of the
standard library's ``warnings`` module - ``"error"`` turns every matching warning into an
exception, ``"always"`` shows every occurrence, ``"default"`` shows the first occurrence
per location (module and line), and the location is the one ``stacklevel`` names (here
the caller's line in this file).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.forecast.evaluate import ForecastEvaluation


@pytest.fixture(scope="module")
def ev():
    rng = np.random.default_rng(24)
    x = np.cumsum(rng.standard_normal((400, 2)), axis=0)
    return evaluate({"linear": LinearPredictor()}, x, train=200, horizons=[1, 2])


def test_error_filter_after_a_first_access_raises(ev):
    with pytest.warns(DeprecationWarning, match=r"p_value is deprecated"):
        assert ev.p_value is ev.pvalue
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DeprecationWarning, match=r"ForecastEvaluation\.p_value"):
            ev.p_value  # noqa: B018 - the access is the test


def test_always_filter_shows_every_access_at_the_callers_line(ev):
    ev.pvalue  # noqa: B018
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(3):
            ev.p_value  # noqa: B018
    assert len(caught) == 3
    assert {w.filename for w in caught} == {__file__}


def test_error_filter_applies_to_the_constructor_keyword_too(ev):
    kwargs = {f.name: getattr(ev, f.name) for f in dataclasses.fields(ev)}
    kwargs["p_value"] = kwargs.pop("pvalue")
    with pytest.warns(DeprecationWarning):
        ForecastEvaluation(**kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DeprecationWarning, match=r"ForecastEvaluation\(p_value=\.\.\.\)"):
            ForecastEvaluation(**kwargs)
