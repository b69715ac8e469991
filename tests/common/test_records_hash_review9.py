"""Records hash NumPy NaN fields as ``==`` compares them (Python's hash contract).

Round 9 of planted bugs (review9, bug P6): ``array_fields_eq`` hashes every NaN as one
value so that equal records hash alike; the existing tests used Python floats only, so
a rule that recognised ``float`` NaN but not ``numpy.float64`` NaN (what a NumPy
reduction returns, e.g. ``np.nanmean([])`` or a p-value from an array) went unseen.
Reference: Python's data model ("objects which compare equal have the same hash
value") and a pickle round trip; ``hash(np.float64('nan'))`` follows the object's
identity, as ``hash(float('nan'))`` does (Python >= 3.10).
"""

import dataclasses
import pickle

import numpy as np

from modalinfo.common.records import array_fields_eq
from modalinfo.information import SelectedInput


@array_fields_eq
@dataclasses.dataclass(frozen=True)
class _Record:
    value: float
    items: tuple


def test_numpy_nan_fields_hash_alike():
    a = _Record(np.float64("nan"), (1.0, np.float64("nan")))
    b = pickle.loads(pickle.dumps(a))
    assert a is not b and a == b
    assert hash(a) == hash(b)
    assert {a: 1}[b] == 1
    assert hash(a) == hash(_Record(float("nan"), (1.0, float("nan"))))


def test_selected_input_with_numpy_nan_bounds_survives_a_pickle():
    nan = np.float64("nan")
    s = SelectedInput(label="Z2[t-1]", source=0, mode="Z2", lag=1, gain=np.float64(0.1),
                      low=nan, high=nan, pvalue=np.float64(0.01))
    t = pickle.loads(pickle.dumps(s))
    assert s == t and hash(s) == hash(t)
    assert len({s, t}) == 1
