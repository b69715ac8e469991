"""One spelling of the p-value across the public results: ``pvalue``, as scipy.stats spells it.

Issue 27, leftovers 12-cli item 4. References, outside the code: scipy.stats' result
objects (``ttest_1samp(...).pvalue``), the spelling every p-value field must follow; the
one-sided Diebold-Mariano p-value recomputed here from the evaluation's statistic with
scipy's Student t (``B`` degrees of freedom, B the number of cosine terms, at most
Lazarus et al.'s 0.4 N^(2/3): the docstring's definition); and the
JSON file format ``to_json`` has always written (key ``p_value``), read back with ``json``.
"""

from __future__ import annotations

import dataclasses
import json
import warnings

import numpy as np
import pytest
from scipy import stats

from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.forecast.evaluate import ForecastEvaluation
from modalinfo.information.flow import TransferEntropyMap
from modalinfo.information.selection import InputSelection, SelectedInput
from modalinfo.information.uncertainty import MIPermutationResult


@pytest.fixture(scope="module")
def ev():
    rng = np.random.default_rng(12)
    x = np.cumsum(rng.standard_normal((600, 2)), axis=0)
    return evaluate({"linear": LinearPredictor()}, x, train=300, horizons=[1, 2])


def test_every_public_p_value_field_is_spelled_as_scipy_spells_it():
    assert hasattr(stats.ttest_1samp([1.0, 2.0, 4.0], 0.0), "pvalue")
    for record in (ForecastEvaluation, MIPermutationResult, TransferEntropyMap,
                   SelectedInput, InputSelection):
        names = {f.name for f in dataclasses.fields(record)}
        assert not any("p_value" in n for n in names), record.__name__
    assert "pvalue" in {f.name for f in dataclasses.fields(ForecastEvaluation)}


def test_forecast_pvalue_is_the_one_sided_t_probability(ev):
    i = ev.index("linear")
    n = ev.origins.size
    b_max = int(np.floor(0.4 * n ** (2.0 / 3.0)))
    for dm, p in zip(ev.dm_statistic[i], ev.pvalue[i], strict=True):
        # some number of cosine terms B <= 0.4 N^(2/3) gives exactly this p
        assert any(stats.t.cdf(dm, b) == pytest.approx(p, rel=1e-12)
                   for b in range(1, b_max + 1)), (dm, p)
    assert np.isnan(ev.pvalue[ev.index("persistence")]).all()


def test_old_name_warns_and_gives_the_same_array(ev):
    with pytest.warns(DeprecationWarning, match=r"ForecastEvaluation\.p_value is deprecated: "
                                                r"use ForecastEvaluation\.pvalue"):
        old = ev.p_value
    assert old is ev.pvalue
    # how often is Python's warning filters' to decide (left24-status, W14): the default
    # action shows it once per calling line
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        for _ in range(3):
            assert ev.p_value is ev.pvalue
    assert [w.category for w in caught] == [DeprecationWarning]


def test_the_file_format_keeps_its_key(ev, tmp_path):
    path = ev.to_json(tmp_path / "ev.json")
    data = json.loads(path.read_text())
    assert "pvalue" not in data
    i = ev.index("linear")
    assert data["p_value"][i] == pytest.approx(ev.pvalue[i].tolist(), rel=1e-15)
    header = (ev.to_csv(tmp_path / "ev.csv").read_text().splitlines()[0]).split(",")
    assert header[7] == "p_value"
