"""``ForecastEvaluation(p_value=...)`` beside positional fields (review13, planted bug R13-L2).

Reference, outside the code under test: the field order of the dataclass as Python's
``dataclasses.fields`` reports it. Fields given positionally up to (not including)
``pvalue``, then ``p_value=`` and the rest by keyword, are one record, equal to the
original, with the alias's ``DeprecationWarning``; the refusal of "both spellings"
is for a ``pvalue`` that really was given (by keyword, or positionally), not for one
positional argument fewer.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.forecast.evaluate import ForecastEvaluation


@pytest.fixture(scope="module")
def ev():
    rng = np.random.default_rng(13)
    x = np.cumsum(rng.standard_normal((400, 2)), axis=0)
    return evaluate({"linear": LinearPredictor()}, x, train=200, horizons=[1, 2])


@pytest.mark.parametrize("before", [0, 1, "all"])
def test_alias_after_the_positional_fields_before_it_is_accepted(ev, before):
    names = [f.name for f in dataclasses.fields(ev) if f.init]
    position = names.index("pvalue")
    k = position if before == "all" else before
    args = [getattr(ev, n) for n in names[:k]]
    kwargs = {n: getattr(ev, n) for n in names[k:] if n != "pvalue"}
    with pytest.warns(DeprecationWarning, match=r"p_value=\.\.\."):
        old = ForecastEvaluation(*args, p_value=ev.pvalue, **kwargs)
    assert old == ev and old.pvalue is ev.pvalue
    # one positional argument more is pvalue itself: both spellings, refused
    with pytest.raises(TypeError, match="give `pvalue` only"):
        ForecastEvaluation(*args, *[getattr(ev, n) for n in names[k:position + 1]],
                           p_value=ev.pvalue,
                           **{n: getattr(ev, n) for n in names[position + 1:]})
