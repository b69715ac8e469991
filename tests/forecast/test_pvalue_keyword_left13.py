"""``ForecastEvaluation(p_value=...)``: the deprecated alias as a constructor keyword too.

Issue 27, left13-cli item 3: ``.p_value`` was a deprecated alias of ``pvalue`` (left12-cli)
but ``ForecastEvaluation(p_value=...)`` raised ``TypeError: unexpected keyword``.
References, outside the code: Python's own ``dataclasses.replace`` and ``pickle`` (the
record rebuilt must equal the original field by field), the ``DeprecationWarning``
category of the standard library, and the JSON file format ``to_json`` has always written
(key ``p_value``, read back with ``json``).
"""

from __future__ import annotations

import dataclasses
import json
import pickle
import warnings

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.forecast.evaluate import ForecastEvaluation


@pytest.fixture(scope="module")
def ev():
    rng = np.random.default_rng(13)
    x = np.cumsum(rng.standard_normal((400, 2)), axis=0)
    return evaluate({"linear": LinearPredictor()}, x, train=200, horizons=[1, 2])


def _fields(ev) -> dict:
    return {f.name: getattr(ev, f.name) for f in dataclasses.fields(ev)}


def test_old_keyword_warns_and_builds_the_same_record(ev):
    kwargs = _fields(ev)
    kwargs["p_value"] = kwargs.pop("pvalue")
    with pytest.warns(DeprecationWarning, match=r"ForecastEvaluation\(p_value=\.\.\.\) is "
                                                r"deprecated: use ForecastEvaluation\(pvalue"):
        old = ForecastEvaluation(**kwargs)
    assert old == ev and old.pvalue is ev.pvalue
    # the default filter shows it once per calling line (left24-status, W14)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        for _ in range(3):
            assert ForecastEvaluation(**kwargs) == ev
    assert [w.category for w in caught] == [DeprecationWarning]


def test_both_spellings_are_refused_naming_pvalue(ev):
    kwargs = _fields(ev)
    with pytest.raises(TypeError, match=r"`pvalue` and its deprecated alias `p_value`; "
                                        r"give `pvalue` only"):
        ForecastEvaluation(**kwargs, p_value=kwargs["pvalue"])
    positional = list(kwargs.values())
    with pytest.raises(TypeError, match="give `pvalue` only"):
        ForecastEvaluation(*positional, p_value=kwargs["pvalue"])
    # replace passes every field: the alias is refused there, the name is accepted
    with pytest.raises(TypeError, match="give `pvalue` only"):
        dataclasses.replace(ev, p_value=np.zeros_like(ev.pvalue))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        new = dataclasses.replace(ev, pvalue=np.zeros_like(ev.pvalue))
    assert np.array_equal(new.pvalue, np.zeros_like(ev.pvalue)) and new.names == ev.names


def test_pickle_and_the_file_are_unchanged(ev, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no alias used on the way
        back = pickle.loads(pickle.dumps(ev))
    assert back == ev
    data = json.loads(ev.to_json(tmp_path / "ev.json").read_text())
    assert "p_value" in data and "pvalue" not in data
