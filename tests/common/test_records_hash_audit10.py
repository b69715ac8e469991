"""Hashable result records hash consistently with ``==`` when a field is NaN (audit 10-state).

Reference: Python's data model (objects that compare equal have the same hash) and round
trips (a record and its pickle are equal). ``hash(float("nan"))`` follows the object's
identity, so a pickled ``SelectedInput`` with NaN interval bounds, or an
``InputSelection`` stopped by its budget (``last_pvalue`` NaN), compared unequal to the
original before the fix.
"""

import dataclasses
import math
import pickle

import numpy as np
import pytest

from modalinfo.common.records import array_fields_eq
from modalinfo.information import InputSelection, SelectedInput


@array_fields_eq
@dataclasses.dataclass(frozen=True)
class _Record:
    value: float
    items: tuple


@array_fields_eq
@dataclasses.dataclass(frozen=True)
class _WithArray:
    data: np.ndarray


def test_nan_fields_hash_and_compare_alike():
    a = _Record(math.nan, (1.0, math.nan))
    b = pickle.loads(pickle.dumps(a))
    assert a == b and hash(a) == hash(b)
    assert {a: 1}[b] == 1
    assert a != _Record(0.0, (1.0, math.nan))


def test_records_holding_arrays_stay_unhashable():
    with pytest.raises(TypeError, match="unhashable"):
        hash(_WithArray(np.zeros(2)))


def test_selection_records_survive_pickle_with_nan():
    si = SelectedInput("Z2[t-1]", 0, "Z2", 1, 0.1, math.nan, math.nan, math.nan)
    q = pickle.loads(pickle.dumps(si))
    assert si == q and hash(si) == hash(q)
    sel = InputSelection(target="Z2", horizon=1, max_lag=2, inputs=(si,), information=0.1,
                         n_candidates=6, n_samples=100, stop_reason="budget reached",
                         last_pvalue=math.nan, method="gaussian", units="nats", alpha=0.05,
                         n_surrogates=19, min_shift=10)
    r = pickle.loads(pickle.dumps(sel))
    assert sel == r and hash(sel) == hash(r)
    assert sel != dataclasses.replace(sel, information=0.2)
