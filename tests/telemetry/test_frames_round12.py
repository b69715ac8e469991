"""Round 12 PART a (issue 27): ``ModalLog`` of a pandas DataFrame with named columns.

Reference: pandas' ``DataFrame.columns`` are the names the scientist gave; a log whose
labels differ from them (Z2, Z3, Z4 for columns Z5, Z6, Z7) is a wrong label, so it is
refused until ``modes`` says which modes they are. Default integer columns, or names
equal to the default labels, are accepted as before.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from modalinfo.telemetry.log import ModalLog

A = np.random.default_rng(0).standard_normal((50, 3))


def test_named_columns_other_than_the_labels_are_refused():
    with pytest.raises(ValueError, match=r"named columns \(Z5, Z6, Z7\).*Z2, Z3, Z4.*modes="):
        ModalLog(pd.DataFrame(A, columns=["Z5", "Z6", "Z7"]), rate=100.0)


def test_modes_given_or_default_names_are_accepted():
    df = pd.DataFrame(A, columns=["Z5", "Z6", "Z7"])
    assert ModalLog(df, rate=100.0, modes=[5, 6, 7]).labels == ["Z5", "Z6", "Z7"]
    assert ModalLog(pd.DataFrame(A), rate=100.0).labels == ["Z2", "Z3", "Z4"]
    assert ModalLog(pd.DataFrame(A, columns=["Z2", "Z3", "Z4"]), rate=100.0).labels == [
        "Z2", "Z3", "Z4"]
